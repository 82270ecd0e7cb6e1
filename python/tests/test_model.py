"""Model files (penedge.model): every example reads and checks; every bad input gets an
error naming its field before anything runs; the quantities the checks resolve (regions,
strength reduction, water pressure, seismic load, support forces) against hand values."""

import math
from pathlib import Path

import numpy as np
import pytest

import penedge
from penedge import model as pm

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "models"

BASE = """\
[domain]
type = "box"
min = [0, 0, 0]
max = [1, 1, 3]

[[joints]]
type = "set"
name = "bedding"
dip = 0
dip_direction = 0
spacing = 1
origin = [0, 0, 1]
number = 2

[rock]
density = 2000

[joint_properties.default]
kn = 1e9
ks = 1e8
friction = 30
"""

FIX_BASE = """
[[boundary]]
region = {type = "face", face = "bottom"}
condition = "fixed"
"""


def model(extra="", boundary=FIX_BASE):
    return pm.parse_model(BASE + boundary + extra)


def error_of(text, prepare=False):
    """The ModelError (or generation SpecError) a model text raises."""

    def read():
        m = pm.parse_model(text)
        if prepare:
            pm.prepare(m)

    with pytest.raises(penedge.SpecError) as caught:
        read()
    return caught.value


def test_every_example_reads_and_checks():
    names = sorted(p.name for p in EXAMPLES.glob("*.toml"))
    assert names == [
        "block_column.toml",
        "column_excavation.toml",
        "slope_excavation.toml",
        "slope_planar.toml",
        "slope_step_path.toml",
        "slope_toppling.toml",
        "tunnel_concave.toml",
        "tunnel_roof_bolt.toml",
        "tunnel_support.toml",
        "wedge_dry.toml",
        "wedge_water.toml",
    ]
    for path in EXAMPLES.glob("*.toml"):
        setup = pm.prepare(path)
        assert len(setup.system) > 1, path
        free = ~setup.layout.fixed
        assert free.any(), path
        assert not free.all(), path


def test_wedge_example_frees_only_the_wedge():
    setup = pm.prepare(EXAMPLES / "wedge_dry.toml")
    assert len(setup.system) == 4  # two planes through a box: four pieces
    free = np.flatnonzero(~setup.layout.fixed)
    assert len(free) == 1
    # the wedge is the tetrahedron (10,5,5), (10-5 sqrt2, 5, 10), (10, 5 -+ 5 sqrt2, 10)
    s = 5 * math.sqrt(2)
    corners = np.array([[10, 5, 5], [10 - s, 5, 10], [10, 5 - s, 10], [10, 5 + s, 10]])
    volume = abs(np.linalg.det(corners[1:] - corners[0])) / 6
    assert setup.blocks.volumes[free[0]] == pytest.approx(volume, rel=1e-9)
    assert setup.layout.monitors == {"wedge": int(free[0])}
    assert set(setup.model.properties) == {"A", "B"}


def test_tunnel_example_bolt_ties_the_roof_wedge_to_the_rock_above():
    setup = pm.prepare(EXAMPLES / "tunnel_roof_bolt.toml")
    free = np.flatnonzero(~setup.layout.fixed)
    assert len(free) == 1
    # a pyramid of height 3 on an equilateral triangle of inradius 3 / tan 60
    side = 2 * math.sqrt(3) * 3 / math.tan(math.radians(60))
    volume = math.sqrt(3) / 4 * side**2 * 3 / 3
    assert setup.blocks.volumes[free[0]] == pytest.approx(volume, rel=1e-9)
    collar, anchor = setup.layout.bolts[0]
    assert collar == free[0]
    assert anchor == setup.blocks.containing([5, 5, 5])
    assert setup.blocks.centroids[anchor, 2] > 3


def test_water_example_has_pressures_per_set():
    m = pm.read_model(EXAMPLES / "wedge_water.toml")
    assert m.water is not None
    assert m.water.pressures == {"A": 5e3, "B": 5e3}
    assert m.water.phreatic is None


def test_column_example():
    setup = pm.prepare(EXAMPLES / "block_column.toml")
    assert len(setup.system) == 5
    z = setup.blocks.centroids[:, 2]
    assert setup.layout.fixed.tolist() == (z < 1).tolist()
    assert z[setup.layout.monitors["top"]] == pytest.approx(4.5)
    assert [s.kind for s in setup.model.stages] == ["solve"]


def test_defaults():
    m = model()
    assert m.mechanics.gravity == (0, 0, -9.81)
    assert m.mechanics.damping == 0.8
    assert m.mechanics.ratio == 1e-5
    assert m.properties["bedding"] == m.default_properties
    assert m.default_properties.cohesion == 0
    assert m.default_properties.tension == 0
    assert [(s.kind, s.ratio) for s in m.stages] == [("solve", 1e-5)]
    assert m.results.moved == 1e-3
    assert m.results.moving == 1e-4
    fos = model('[results]\nmoving = 0.01\n[[stages]]\ntype = "factor_of_safety"\n').stages[0]
    assert fos.velocity == 0.01


def test_set_properties_override_only_what_they_give():
    m = model("[joint_properties.bedding]\nfriction = 20\ncohesion = 1e5\n")
    p = m.properties["bedding"]
    assert (p.kn, p.ks, p.friction, p.cohesion) == (1e9, 1e8, 20, 1e5)
    assert m.default_properties.friction == 30


def test_strength_reduction_divides_tan_phi_cohesion_and_tension():
    p = pm.JointProperties(kn=1, ks=2, friction=35, cohesion=100, tension=50)
    r = p.reduced(1.25)
    assert math.tan(math.radians(r.friction)) == pytest.approx(math.tan(math.radians(35)) / 1.25)
    assert (r.cohesion, r.tension, r.kn, r.ks) == (80, 40, 1, 2)
    assert r.residual_friction == pytest.approx(r.friction)


def test_seismic_coefficient_adds_a_horizontal_body_force():
    m = model("[seismic]\ncoefficient = 0.2\nazimuth = 90\nvertical = 0.1\n")
    gx, gy, gz = m.gravity
    assert (gx, gy, gz) == pytest.approx((0.2 * 9.81, 0, -9.81 + 0.1 * 9.81), abs=1e-12)
    m = model("[seismic]\ncoefficient = 0.1\nazimuth = 180\n")
    assert m.gravity == pytest.approx((0, -0.981, -9.81), abs=1e-12)


def test_phreatic_surface_forms_give_hydrostatic_pressure():
    flat = model("[water]\nphreatic = {elevation = 2.5}\n").water
    # 1.5 m below the water table: rho g h
    assert flat.pressure_at(np.array([[0.3, 0.2, 1.0]]), 9.81)[0] == pytest.approx(
        1000 * 9.81 * 1.5
    )
    assert flat.pressure_at(np.array([[0.3, 0.2, 3.0]]), 9.81)[0] == 0
    # an inclined table through three points: z = 2 + 0.1 x
    tilted = model("[water]\nphreatic = {points = [[0, 0, 2], [10, 0, 3], [0, 10, 2]]}\n").water
    assert tilted.pressure_at(np.array([[5.0, 7.0, 0.0]]), 10.0)[0] == pytest.approx(
        1000 * 10 * 2.5
    )
    dipping = model(
        "[water]\nphreatic = {point = [0, 0, 2], dip = 45, dip_direction = 90}\n"
    ).water  # z = 2 - x
    assert dipping.pressure_at(np.array([[1.0, 3.0, 0.0]]), 10.0)[0] == pytest.approx(
        1000 * 10 * 1.0
    )


def test_regions():
    m = model(
        """
[regions.low]
type = "below"
z = 1.5
[regions.high]
type = "above"
point = [0, 0, 1.2]
normal = [0, 0, -2]
[regions.middle]
type = "box"
min = [0, 0, 1]
max = [1, 1, 2]
[regions.east]
type = "face"
face = "east"
[regions.lid]
type = "face"
face = 1
[regions.two]
type = "blocks"
ids = [2]
[regions.here]
type = "point"
point = [0.5, 0.5, 2.5]
"""
    )
    setup = pm.prepare(m)
    z = setup.blocks.centroids[:, 2]
    masks = setup.layout.regions
    assert sorted(z[masks["low"]]) == [0.5]
    assert sorted(z[masks["high"]]) == [1.5, 2.5]  # the normal's sense does not matter
    assert sorted(z[masks["middle"]]) == [1.5]
    assert masks["east"].all()  # every block of the column touches the east face
    assert sorted(z[masks["lid"]]) == [2.5]  # face 1 of a box is its top
    assert np.flatnonzero(masks["two"]).tolist() == [2]
    assert sorted(z[masks["here"]]) == [2.5]


def test_support_pressure_forces():
    setup = pm.prepare(
        model('[[support]]\nregion = {type = "all"}\nface = "top"\npressure = 5e4\n')
    )
    forces, moments = setup.layout.support_forces, setup.layout.support_moments
    top = np.argmax(setup.blocks.centroids[:, 2])
    expected = np.zeros_like(forces)
    expected[top] = [0, 0, -5e4 * 1.0]  # 1 m2 top face, pushed down into the rock
    assert forces == pytest.approx(expected, abs=1e-6)
    assert moments == pytest.approx(np.zeros_like(moments), abs=1e-6)  # face centred on the block


def test_bolt_resolves_its_blocks():
    setup = pm.prepare(
        model(
            "[[bolts]]\npoint = [0.5, 0.5, 3]\nplunge = 90\ntrend = 0\nlength = 1.5\n"
            "capacity = 1e5\nstiffness = 1e7\n"
        )
    )
    z = setup.blocks.centroids[:, 2]
    collar, anchor = setup.layout.bolts[0]
    assert (z[collar], z[anchor]) == (2.5, 1.5)


# --- bad input: an error naming the field, before anything runs ----------------------


@pytest.mark.parametrize(
    ("extra", "field", "words"),
    [
        (
            "[joint_properties.default2]\nkn = 1\n",
            "joint_properties.default2",
            "no joint set is named",
        ),
        (
            "[joint_properties.bedding]\nfrction = 3\n",
            "joint_properties.bedding.frction",
            "unknown field",
        ),
        ("[rocks]\ndensity = 3\n", "rocks", "unknown field"),
        ("[mechanics]\ndamping = 1.5\n", "mechanics.damping", "less than 1"),
        ("[mechanics]\ngap = 0.01\n", "mechanics.gap", "less than 0.01"),
        ("[mechanics]\npoint_width = 0\n", "mechanics.point_width", "greater than 0"),
        ("[mechanics]\ngravity = [0, -9.81]\n", "mechanics.gravity", "three numbers"),
        ("[mechanics]\ntime_step = 'small'\n", "mechanics.time_step", "must be a number"),
        (
            "[[stages]]\ntype = 'excavate'\nregion = 'tunnel'\n",
            "stages[0].region",
            "no region is named 'tunnel'",
        ),
        (
            "[[stages]]\ntype = 'properties'\nsets = ['joint']\nfriction = 3\n",
            "stages[0].sets[0]",
            "no joint set is named 'joint'",
        ),
        ("[[stages]]\ntype = 'properties'\n", "stages[0]", "changes nothing"),
        # a misspelt change, alone or with others: named, with the field it is a typo of
        (
            "[[stages]]\ntype = 'properties'\nfrction = 20\n",
            "stages[0].frction",
            "unknown field ('friction' is a field here: a typo?)",
        ),
        (
            "[[stages]]\ntype = 'properties'\nkn = 1e9\ncohsion = 1e5\n",
            "stages[0].cohsion",
            "'cohesion' is a field here: a typo?",
        ),
        ("[[stages]]\ntype = 'properties'\ncolour = 3\n", "stages[0].colour", "unknown field;"),
        ("[[stages]]\ntype = 'properties'\nfriction = 95\n", "stages[0].friction", "less than 90"),
        ("[[stages]]\ntype = 'solv'\n", "stages[0].type", "unknown value 'solv'"),
        ("[[stages]]\ntype = 'cycle'\n", "stages[0].steps", "required"),
        ("[[stages]]\ntype = 'cycle'\nsteps = 10\nratio = 3\n", "stages[0].ratio", "unknown field"),
        (
            "[[stages]]\ntype = 'factor_of_safety'\nlow = 2\nhigh = 1\n",
            "stages[0].high",
            "greater than low",
        ),
        ("[water]\nphreatic = 30\n", "water.phreatic", "must be a table"),
        (
            "[water]\nphreatic = {elevation = 3, points = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]}\n",
            "water.phreatic",
            "found elevation and points",
        ),
        (
            "[water]\nphreatic = {points = [[0, 0, 0], [1, 1, 1], [2, 2, 2]]}\n",
            "water.phreatic.points",
            "on one line",
        ),
        (
            "[water]\nphreatic = {points = [[0, 0, 0], [1, 1]]}\n",
            "water.phreatic.points",
            "three points",
        ),
        (
            "[water]\nphreatic = {point = [0, 0, 0], dip = 90, dip_direction = 0}\n",
            "water.phreatic",
            "cannot be vertical",
        ),
        ("[water]\nphreatic = {level = 3}\n", "water.phreatic", "found none of"),
        (
            "[water]\n[water.pressure]\nJ9 = 1e4\n",
            "water.pressure.J9",
            "no joint set is named 'J9'",
        ),
        ("[water]\ndensity = 1000\n", "water", "give a phreatic surface"),
        (
            "[[bolts]]\npoint = [0, 0, 0]\nlength = 2\ncapacity = 1\nstiffness = 1\n",
            "bolts[0].trend",
            "required",
        ),
        (
            "[[bolts]]\npoint = [0, 0, 0]\ndirection = [0, 0, 1]\nplunge = 90\nlength = 2\n"
            "capacity = 1\nstiffness = 1\n",
            "bolts[0].plunge",
            "give either direction or trend + plunge",
        ),
        (
            "[[bolts]]\npoint = [0, 0, 0]\ndirection = [0, 0, 0]\nlength = 2\n"
            "capacity = 1\nstiffness = 1\n",
            "bolts[0].direction",
            "non-zero",
        ),
        ("[seismic]\ncoefficient = 0.1\n", "seismic.azimuth", "required"),
        (
            "[initial_stress]\ntype = 'overburden'\nk0 = 1\nk0_x = 2\n",
            "initial_stress.k0",
            "either k0 or",
        ),
        (
            "[regions.r]\ntype = 'box'\nmin = [0, 0, 0]\nmax = [1, 0, 1]\n",
            "regions.r.max",
            "greater than min",
        ),
        ("[regions.r]\ntype = 'face'\nface = 'up'\n", "regions.r.face", "unknown value 'up'"),
        ("[[monitors]]\nname = 'm'\n", "monitors[0]", "either point"),
        ("[results]\nmoved = 0\n", "results.moved", "greater than 0"),
    ],
)
def test_bad_fields_are_named(extra, field, words):
    e = error_of(BASE + FIX_BASE + extra)
    assert e.field == field, str(e)
    assert str(e).startswith(f"{field}: ")
    assert words in str(e)


def test_missing_required_tables():
    e = error_of("[rock]\ndensity = 1\n")
    assert e.field == "domain"
    e = error_of(
        BASE.replace("[joint_properties.default]\nkn = 1e9\nks = 1e8\nfriction = 30\n", "")
    )
    assert e.field == "joint_properties.default"
    e = error_of(BASE.replace("friction = 30\n", ""))
    assert e.field == "joint_properties.default.friction"
    assert "required" in str(e)
    e = error_of(BASE.replace("density = 2000", "densty = 2000"))
    assert e.field == "rock.density"
    assert "'densty' is given: a typo?" in str(e)


def test_toml_syntax_error_names_the_line():
    e = error_of(BASE + "[rock\n")
    assert e.field == "model"
    assert "line" in str(e)


def test_generation_errors_are_the_spec_errors():
    e = error_of(BASE.replace("dip = 0\n", "dip = 120\n") + FIX_BASE, prepare=True)
    assert "joints[0].dip" in str(e)


@pytest.mark.parametrize(
    ("boundary", "field", "words"),
    [
        ("", "boundary", "no block is fixed or driven"),
        (
            '[[boundary]]\nregion = {type = "all"}\ncondition = "fixed"\n',
            "boundary",
            "every block (3) is fixed",
        ),
        (
            '[[boundary]]\nregion = {type = "all"}\ncondition = "velocity"\nvelocity = [0, 0, 1]\n',
            "boundary",
            "every block (3) is fixed or driven",
        ),
        (
            '[[boundary]]\nregion = {type = "box", min = [5, 5, 5], max = [6, 6, 6]}\n'
            'condition = "fixed"\n',
            "boundary[0].region",
            "selects no block",
        ),
        (
            '[[boundary]]\nregion = {type = "point", point = [9, 9, 9]}\ncondition = "fixed"\n',
            "boundary[0].region.point",
            "no block contains",
        ),
        (
            '[[boundary]]\nregion = {type = "blocks", ids = [7]}\ncondition = "fixed"\n',
            "boundary[0].region.ids",
            "no block 7",
        ),
        (
            '[[boundary]]\nregion = {type = "face", face = 9}\ncondition = "fixed"\n',
            "boundary[0].region.face",
            "no face 9",
        ),
        (
            '[[boundary]]\nregion = {type = "face", face = "bottom", part = 7}\n'
            'condition = "fixed"\n',
            "boundary[0].region.part",
            "the domain has 1 part(s) (0 to 0); no part 7",
        ),
        (
            '[[boundary]]\nregion = "base"\ncondition = "fixed"\n',
            "boundary[0].region",
            "no region is named 'base'",
        ),
        (
            '[[boundary]]\nregion = {type = "all"}\ncondition = "fixed"\nvelocity = [0, 0, 0]\n',
            "boundary[0].velocity",
            'only with condition = "velocity"',
        ),
    ],
)
def test_boundary_errors(boundary, field, words):
    e = error_of(BASE + boundary, prepare=True)
    assert e.field == field, str(e)
    assert words in str(e)


def test_region_names_with_a_dot_are_listed_and_brackets_refused():
    # a name with a dot is a name like another: listed when a reference misses it
    regions = '[regions."zone.1"]\ntype = "all"\n[regions.b]\ntype = "all"\n'
    support = '[[support]]\nregion = "zone.2"\npressure = 1e5\n'
    e = error_of(BASE + FIX_BASE + regions + support)
    assert e.field == "support[0].region"
    assert "no region is named 'zone.2' (the regions are: zone.1, b)" in str(e)
    m = model(regions + support.replace("zone.2", "zone.1"))
    assert m.support[0].region == "zone.1"
    # the inline regions (named by their place) are neither listed nor names to refer to
    e = error_of(BASE + FIX_BASE + support.replace("zone.2", "boundary[0].region"))
    assert "no region is named 'boundary[0].region' (the regions are: none" in str(e)
    # a named region is named by its table, dot or not
    e = error_of(BASE + FIX_BASE + '[regions."zone.1"]\ntype = "above"\nz = 10\n', prepare=True)
    assert e.field == "regions.zone.1"
    assert "selects no block" in str(e)
    e = error_of(BASE + FIX_BASE + '[regions."boundary[0].region"]\ntype = "all"\n')
    assert e.field == "regions.boundary[0].region"
    assert "must not be empty nor hold [ or ]" in str(e)


def test_named_region_that_selects_nothing():
    e = error_of(BASE + FIX_BASE + "[regions.sky]\ntype = 'above'\nz = 10\n", prepare=True)
    assert (e.field, "selects no block" in str(e)) == ("regions.sky", True)


@pytest.mark.parametrize(
    ("bolt", "field", "words"),
    [
        (
            "point = [5, 5, 5]\ndirection = [1, 0, 0]\nlength = 2\n",
            "bolts[0].point",
            "outside the rock",
        ),
        (
            "point = [0.5, 0.5, 3]\ndirection = [0, 0, -1]\nlength = 4\n",
            "bolts[0].length",
            "far end",
        ),
        (
            "point = [0.5, 0.5, 3]\ndirection = [0, 0, -1]\nlength = 0.5\n",
            "bolts[0]",
            "crosses no joint",
        ),
    ],
)
def test_bolt_errors(bolt, field, words):
    e = error_of(
        BASE + FIX_BASE + "[[bolts]]\ncapacity = 1e5\nstiffness = 1e7\n" + bolt, prepare=True
    )
    assert e.field == field, str(e)
    assert words in str(e)


def test_monitor_outside_the_rock():
    e = error_of(BASE + FIX_BASE + "[[monitors]]\npoint = [3, 3, 3]\n", prepare=True)
    assert e.field == "monitors[0].point"
    assert "outside the rock" in str(e)


def test_a_point_on_a_face_two_blocks_share_is_refused():
    # z = 1 is the joint between the fixed bottom block and the one above: a point on it is
    # in both (it went to the first, the fixed one: a monitor recording zeros)
    on_joint = "blocks 0 (centroid (0.5, 0.5, 0.5)) and 2 (centroid (0.5, 0.5, 1.5))"
    for extra, field in [
        ("[[monitors]]\npoint = [0.5, 0.5, 1]\n", "monitors[0].point"),
        (
            "[regions.r]\ntype = 'point'\npoint = [0.2, 0.7, 1]\n[[support]]\nregion = 'r'\n"
            "pressure = 1\n",
            "regions.r.point",
        ),
        (
            "[[bolts]]\npoint = [0.5, 0.5, 3]\nplunge = 90\ntrend = 0\nlength = 2\n"
            "capacity = 1e5\nstiffness = 1e7\n",
            "bolts[0].length",
        ),
    ]:
        e = error_of(BASE + FIX_BASE + extra, prepare=True)
        assert e.field == field, str(e)
        assert f"on the boundary between {on_joint}" in str(e)
        assert "move it inside the block it means" in str(e)
    # a hair inside the upper block is that block's
    setup = pm.prepare(model("[[monitors]]\nname = 'm'\npoint = [0.5, 0.5, 1.001]\n"))
    assert setup.layout.monitors == {"m": 2}


def test_support_without_free_face():
    # the middle block's only free faces are its sides: none faces up
    e = error_of(
        BASE + FIX_BASE + '[[support]]\nregion = {type = "point", point = [0.5, 0.5, 1.5]}\n'
        'face = "top"\npressure = 1e3\n',
        prepare=True,
    )
    assert e.field == "support[0]"
    assert "no free face" in str(e)


def test_duplicate_and_reserved_joint_names():
    e = error_of(BASE.replace('name = "bedding"', 'name = "default"'))
    assert e.field == "joints[0].name"
    two = (
        BASE
        + '[[joints]]\ntype = "plane"\nname = "bedding"\npoint = [0, 0, 2.5]\n'
        + "dip = 0\ndip_direction = 0\n"
    )
    e = error_of(two)
    assert (e.field, "also the name of joints[0]" in str(e)) == ("joints[1].name", True)


def test_model_from_dict_and_unnamed_sets():
    import tomllib

    data = tomllib.loads(BASE.replace('name = "bedding"\n', "") + FIX_BASE)
    data["joint_properties"]["joints[0]"] = {"cohesion": 3.0}
    m = pm.load_model(data)
    assert m.properties["joints[0]"].cohesion == 3.0


def test_error_is_a_value_error_with_the_field():
    e = error_of(BASE + "[mechanics]\nmax_steps = 0\n")
    assert isinstance(e, ValueError)
    assert isinstance(e, penedge.PenedgeError)
    assert e.field == "mechanics.max_steps"


def test_docstring_example():
    import doctest

    failures, tried = doctest.testmod(pm, optionflags=doctest.NORMALIZE_WHITESPACE)
    assert tried > 0
    assert failures == 0


def test_a_model_file_not_in_utf8_is_named(tmp_path):
    # A degree sign saved by an editor in Windows-1252: byte 0xb0, not UTF-8.
    path = tmp_path / "m.toml"
    path.write_bytes((BASE + "# friction 30\u00b0\n" + FIX_BASE).encode("cp1252"))
    with pytest.raises(pm.ModelError) as caught:
        pm.read_model(path)
    assert caught.value.field == "model"
    assert "not UTF-8" in str(caught.value)
    assert str(path) in str(caught.value)


def test_a_model_file_with_a_byte_order_mark_reads(tmp_path):
    # Notepad's "UTF-8 with BOM": the file starts with EF BB BF, which TOML does not take
    # but `penedge generate` skips; the model reads as the same file without it.
    path = tmp_path / "m.toml"
    path.write_bytes(b"\xef\xbb\xbf" + (BASE + FIX_BASE).encode())
    assert pm.read_model(path) == model()
    assert pm.parse_model("\ufeff" + BASE + FIX_BASE) == model()
    # a bad byte after the mark is still named by its place in the file
    path.write_bytes(b"\xef\xbb\xbf# \xb0\n" + (BASE + FIX_BASE).encode())
    with pytest.raises(pm.ModelError, match="byte 5 is not valid UTF-8"):
        pm.read_model(path)


def test_a_model_whose_blocks_are_all_dropped_has_no_blocks():
    text = BASE + FIX_BASE + '[options]\nmin_volume = 10\nslivers = "drop"\n'
    e = error_of(text, prepare=True)
    assert e.field == "domain"
    assert "no blocks" in str(e)


@pytest.mark.parametrize(
    ("old", "new", "field", "words"),
    [
        # density = 1e300 ran to a NaN ratio and infinite displacements, exit status 0
        ("density = 2000", "density = 1e300", "rock.density", "1e+300 kg/m³ is outside"),
        ("density = 2000", "density = 1e-300", "rock.density", "1 to 100000 kg/m³"),
        # kn = 1e300 gave an infinite ratio and ran the whole step budget
        ("kn = 1e9", "kn = 1e300", "joint_properties.default.kn", "1000 to 1e+15 Pa/m"),
        ("ks = 1e8", "ks = 1e-300", "joint_properties.default.ks", "1e-300 Pa/m is outside"),
        (
            "[rock]",
            "[mechanics]\ngravity = [0, 1e300, 0]\n[rock]",
            "mechanics.gravity",
            "1e+300 m/s² is outside the range a model takes, at most 10000 m/s²",
        ),
        (
            "friction = 30\n",
            "friction = 30\n[joint_properties.bedding]\nkn = 1e16\n",
            "joint_properties.bedding.kn",
            "1e+16 Pa/m",
        ),
    ],
)
def test_magnitudes_beyond_any_model_are_named_with_their_range(old, new, field, words):
    e = error_of(BASE.replace(old, new) + FIX_BASE)
    assert e.field == field, str(e)
    assert words in str(e)
    assert "a unit or an exponent typed wrong?" in str(e)


@pytest.mark.parametrize(
    ("extra", "field", "words"),
    [
        (
            "[[support]]\nregion = {type = 'all'}\npressure = 1e300\n",
            "support[0].pressure",
            "1e+10",
        ),
        ("[water]\npressure = {bedding = 1e11}\n", "water.pressure.bedding", "1e+11 Pa"),
        ("[water]\ndensity = 1e6\npressure = {bedding = 1}\n", "water.density", "1e+06"),
        ("[initial_stress]\ntype = 'uniform'\nzz = -1e300\n", "initial_stress.zz", "magnitude"),
        ("[initial_stress]\ntype = 'overburden'\ndensity = 0.5\n", "initial_stress.density", "0.5"),
        (
            "[[bolts]]\npoint = [0.5, 0.5, 3]\nplunge = 90\ntrend = 0\nlength = 2.5\n"
            "capacity = 1e5\nstiffness = 1e300\n",
            "bolts[0].stiffness",
            "at most 1e+12 N/m",
        ),
        (
            "[[bolts]]\npoint = [0.5, 0.5, 3]\nplunge = 90\ntrend = 0\nlength = 2.5\n"
            "capacity = 1e5\nstiffness = 1e7\nshear_stiffness = 1e13\nshear_capacity = 1\n",
            "bolts[0].shear_stiffness",
            "at most 1e+12 N/m",
        ),
        (
            "[[stages]]\ntype = 'boundary'\nregion = {type = 'all'}\ncondition = 'velocity'\n"
            "velocity = [1e300, 1e300, 0]\n",
            "stages[0].velocity",
            "1.41421e+300 m/s",
        ),
        ("[[stages]]\ntype = 'properties'\nks = 1e300\n", "stages[0].ks", "Pa/m"),
    ],
)
def test_loads_beyond_any_model_are_named_with_their_range(extra, field, words):
    e = error_of(BASE + FIX_BASE + extra)
    assert e.field == field, str(e)
    assert words in str(e)
    assert "outside the range a model takes" in str(e)


def test_ranges_that_need_the_blocks():
    # the overburden's stress at the bottom, density x gravity x depth x k0
    for extra, field in [
        ("[initial_stress]\ntype = 'overburden'\nsurface = 1e300\n", "initial_stress.surface"),
        ("[initial_stress]\ntype = 'overburden'\nk0 = 1e7\n", "initial_stress"),
    ]:
        e = error_of(BASE + FIX_BASE + extra, prepare=True)
        assert e.field == field, str(e)
        assert "the overburden's stress at the lowest face" in str(e)
    # 2000 x 9.81 x 3 m, k0 1e5: 5.9e9 Pa, in range
    pm.prepare(model("[initial_stress]\ntype = 'overburden'\nk0 = 1e5\n"))
    # a domain in millimetres read as metres, a thousand times over
    huge = BASE.replace("max = [1, 1, 3]", "max = [1e7, 1e7, 3e7]")
    huge = huge.replace("origin = [0, 0, 1]", "origin = [0, 0, 1e7]").replace(
        "spacing = 1", "spacing = 1e7"
    )
    e = error_of(huge + FIX_BASE, prepare=True)
    assert e.field == "domain"
    assert "the blocks span 3.32e+07 m" in str(e)


EDGES = {
    "density": "1e5",
    "kn": "1e15",
    "ks": "1e15",
    "gravity": "-1e4",
    "water_density": "1e5",
    "water_pressure": "1e10",
    "support": "1e10",
}

EDGE_MODEL = (
    (BASE + FIX_BASE)
    .replace("{", "{{")
    .replace("}", "}}")
    .replace("density = 2000", "density = {density}")
    .replace("kn = 1e9", "kn = {kn}")
    .replace("ks = 1e8", "ks = {ks}")
    + "[mechanics]\ngravity = [0, 0, {gravity}]\n"
    + "[water]\ndensity = {water_density}\npressure = {{bedding = {water_pressure}}}\n"
    + "[[support]]\nregion = {{type = 'all'}}\npressure = {support}\nface = 'top'\n"
    + "[[stages]]\ntype = 'cycle'\nsteps = 50\n"
)


def test_at_the_ranges_edges_the_engine_runs_and_beyond_them_it_is_refused():
    from penedge.model.engine import Engine
    from penedge.model.run import Runner

    # every range at its edge at once: the engine's products stay finite
    runner = Runner(pm.prepare(EDGE_MODEL.format(**EDGES)), Engine)
    runner.run()
    assert np.isfinite(runner.engine.ratio)
    assert np.isfinite(runner.engine.positions()).all()
    # ten times beyond each edge is refused, naming the field
    fields = {
        "density": "rock.density",
        "kn": "joint_properties.default.kn",
        "ks": "joint_properties.default.ks",
        "gravity": "mechanics.gravity",
        "water_density": "water.density",
        "water_pressure": "water.pressure.bedding",
        "support": "support[0].pressure",
    }
    for key, field in fields.items():
        e = error_of(EDGE_MODEL.format(**{**EDGES, key: repr(float(EDGES[key]) * 10)}))
        assert e.field == field, str(e)
        assert "outside the range a model takes" in str(e)


def test_numbers_too_large_are_named():
    e = error_of(BASE + FIX_BASE + "[mechanics]\nmax_steps = 1e20\n")
    assert e.field == "mechanics.max_steps"
    assert "at most" in str(e)
    e = error_of(BASE.replace("density = 2000", "density = " + "9" * 400) + FIX_BASE)
    assert e.field == "rock.density"
    assert "too large" in str(e)
