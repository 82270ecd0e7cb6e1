"""Support pressure on an excavation's walls (docs/models.md, ``[[support]]``): the faces an
``[[excavations]]`` entry leaves are free faces a support pushes on, into the rock; ``face``
may name the excavation to push on its walls only. Checked against the resultant of a
pressure on the tunnel's polygon (computed here from the profile), and in the engine: a
roof block between frictionless joints stays up when the pressure on its area beats its
weight, and falls when it does not."""

import itertools
import math
from pathlib import Path

import numpy as np
import pytest

import penedge.model as pm

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "models"
TUNNEL = EXAMPLES / "tunnel_concave.toml"
TEXT = TUNNEL.read_text()
BASE = TEXT[: TEXT.index("[[monitors]]")]
# The example's geometry: a 16-gon of radius 2 m centred at x = z = 5 (a flat side at the
# bottom), through two slices 2 m long in y (0..2, 2..4); joints at x = 5 and z = 5.
RADIUS, SEGMENTS, SLICE, AXIS = 2.0, 16, 2.0, (5.0, 5.0)
PRESSURE = 1e5


def support(region='{type = "all"}', face=None, pressure=PRESSURE):
    face_line = "" if face is None else f"face = {face}\n"
    return f"[[support]]\nregion = {region}\n{face_line}pressure = {pressure}\n"


def body_loads(setup, forces=None, moments=None, about=None):
    """Per body (by the system's body ids): the support's force and its moment about the
    point `about(body)` (each part's moment plus its force's moment arm from there)."""
    ids = np.asarray(setup.system.body_ids)
    f = setup.layout.support_forces if forces is None else forces
    m = setup.layout.support_moments if moments is None else moments
    c = setup.blocks.centroids
    out = {}
    for b in np.unique(ids):
        parts = ids == b
        point = np.zeros(3) if about is None else about(parts)
        out[int(b)] = (
            f[parts].sum(0),
            m[parts].sum(0) + np.cross(c[parts] - point, f[parts]).sum(0),
        )
    return out


def on_axis(setup):
    """The point of the tunnel's axis in the middle of the body's slice."""

    def point(parts):
        y = setup.blocks.centroids[parts][:, 1].mean()
        return np.array([AXIS[0], (y // SLICE + 0.5) * SLICE, AXIS[1]])

    return point


def test_a_support_on_the_tunnel_pushes_each_quarter_of_its_wall_into_the_rock():
    setup = pm.prepare(BASE + support(face='"tunnel"'))
    loads = body_loads(setup, about=on_axis(setup))
    pushed = {b: fm for b, fm in loads.items() if np.abs(fm[0]).max() > 0}
    # four concave blocks around the opening in each of the two slices
    assert len(pushed) == 8
    # A pressure on a surface adds up to the pressure times the surface's projection: a
    # quarter of the 16-gon (flat sides centred on the two joints through its centre)
    # projects onto each axis as the apothem r cos(pi/N) times the slice's length, and
    # pushes away from the axis (into the rock) in both x and z.
    component = PRESSURE * RADIUS * math.cos(math.pi / SEGMENTS) * SLICE
    centroids = setup.blocks.centroids
    ids = np.asarray(setup.system.body_ids)
    for b, (force, moment) in pushed.items():
        away = np.sign(centroids[ids == b].mean(0) - [AXIS[0], 0, AXIS[1]])
        assert force == pytest.approx([away[0] * component, 0, away[2] * component], rel=1e-9)
        # every face's normal passes through the axis: no moment about it
        assert np.abs(moment).max() <= 1e-9 * component * RADIUS


def test_the_area_pushed_on_is_the_tunnel_wall_s_less_the_glue_between_parts():
    # the wall of an N-gon of radius r through the 4 m long domain: N 2 r sin(pi/N) L; the
    # part faces on the polygon's planes are larger (they are glued to other parts too)
    wall = SEGMENTS * 2 * RADIUS * math.sin(math.pi / SEGMENTS) * 2 * SLICE
    setup = pm.prepare(BASE + support(face='"tunnel"'))
    assert setup.layout.support_areas == [pytest.approx(wall, rel=1e-9)]
    faces = (setup.blocks.face_kind == 2) & (setup.blocks.face_set == 3)
    assert setup.blocks.face_areas[faces].sum() > 1.5 * wall
    # every free face: the wall and the box's faces (2 x (10 x 4 + 10 x 10 + 4 x 10)),
    # less the tunnel's two openings in the North and South faces (N r² sin(2pi/N) / 2)
    opening = SEGMENTS * RADIUS**2 * math.sin(2 * math.pi / SEGMENTS) / 2
    every = pm.prepare(BASE + support())
    assert every.layout.support_areas == [
        pytest.approx(wall + 2 * (40 + 100 + 40) - 2 * opening, rel=1e-9)
    ]


def test_check_prints_each_support_with_its_area(capsys):
    from penedge import cli

    assert cli.main(["simulate", str(EXAMPLES / "tunnel_support.toml"), "--check"]) == 0
    # the gallery's roof and floor, 2 m wide, and its sides on the joints x = 2 and x = 4,
    # 2.5 m high, all 2 m long: 2 (2 + 2.5) 2 = 18 m²
    assert (
        "support               lining: 75000 Pa on 18 m² of free faces" in capsys.readouterr().out
    )


def test_every_free_face_takes_the_tunnel_walls_and_the_domain_faces():
    walls = pm.prepare(BASE + support(face='"tunnel"'))
    top = pm.prepare(BASE + support(face='"top"'))
    every = pm.prepare(BASE + support())
    sides = [pm.prepare(BASE + support(face=f'"{side}"')) for side in FACE_NAMES]
    expected = walls.layout.support_forces + sum(s.layout.support_forces for s in sides)
    assert np.allclose(every.layout.support_forces, expected, rtol=0, atol=1e-6)
    # the domain's top: its area times the pressure, downwards, on the top row of blocks
    assert top.layout.support_forces.sum(0) == pytest.approx([0, 0, -PRESSURE * 10 * 4])


FACE_NAMES = ("top", "bottom", "east", "west", "north", "south")


def test_an_excavation_is_named_by_its_name_or_its_index():
    by_name = pm.prepare(BASE + support(face='"tunnel"'))
    by_index = pm.prepare(BASE + support(face='"excavations[0]"'))
    assert np.array_equal(by_name.layout.support_forces, by_index.layout.support_forces)
    assert np.array_equal(by_name.layout.support_moments, by_index.layout.support_moments)


def test_an_unknown_face_name_is_an_error_naming_the_field_and_the_choices():
    with pytest.raises(pm.ModelError) as caught:
        pm.prepare(BASE + support(face='"gallery"'))
    assert caught.value.field == "support[0].face"
    assert "no domain face or excavation named 'gallery'" in str(caught.value)
    assert "'tunnel'" in str(caught.value)


def quarter_facets(sx, sz):
    """The pressure on the facets of a quarter of the tunnel's wall (the quadrant of signs
    sx in x, sz in z): per facet its resultant (p times its area, into the rock) and its
    moment about the axis. The facets are the 16-gon's edges, whose outward normals point
    at 0, 22.5, ..., 90 degrees (a flat side at the bottom); the joints through the axis
    halve the two end ones, whose centroids lie a quarter edge off the normal through the
    axis (the others' forces pass through it)."""
    edge = 2 * RADIUS * math.sin(math.pi / SEGMENTS)
    apothem = RADIUS * math.cos(math.pi / SEGMENTS)
    angles = np.radians(np.arange(0, 91, 360 / SEGMENTS))
    weights = np.array([0.5, 1, 1, 1, 0.5])
    normals = np.stack([np.cos(angles), np.zeros(5), np.sin(angles)], axis=1)
    centroids = apothem * normals
    centroids[0, 2] += edge / 4
    centroids[-1, 0] += edge / 4
    sign = np.array([sx, 1, sz])
    forces = PRESSURE * SLICE * edge * weights[:, None] * normals * sign
    return forces, np.cross(centroids * sign, forces)


@pytest.mark.parametrize("height", [5.8, 6.6])
def test_a_region_that_splits_a_concave_block_pushes_on_the_wall_of_its_parts_only(height):
    # A box that takes some parts of the concave blocks above the tunnel and not others:
    # the glue between a part inside and a part outside is no wall. Each side pushes on
    # whole facets of the wall (a subset of the quarter's edges, the other side the rest),
    # with their moments about the axis; the two add up to the whole wall, body by body.
    box = f'{{type = "box", min = [0, 0, {height}], max = [10, 4, 10]}}'
    rest = f'{{type = "below", z = {height}}}'
    inside = pm.prepare(BASE + support(box, '"tunnel"'))
    outside = pm.prepare(BASE + support(rest, '"tunnel"'))
    whole = pm.prepare(BASE + support(face='"tunnel"'))
    ids = np.asarray(whole.system.body_ids)
    mask = inside.layout.regions["support[0].region"]
    split = [b for b in np.unique(ids) if 0 < mask[ids == b].sum() < (ids == b).sum()]
    a, b, w = (body_loads(s, about=on_axis(s)) for s in (inside, outside, whole))
    for body in w:
        assert a[body][0] + b[body][0] == pytest.approx(w[body][0], abs=1e-6)
    areas = [s.layout.support_areas[0] for s in (inside, outside, whole)]
    assert areas[0] + areas[1] == pytest.approx(areas[2], rel=1e-9)
    subsets = [np.array(k) for k in itertools.product([0, 1], repeat=5)]
    pushed = 0
    for body in split:
        sx, _, sz = np.sign(whole.blocks.centroids[ids == body].mean(0) - [AXIS[0], 0, AXIS[1]])
        forces, moments = quarter_facets(sx, sz)
        matches = [k for k in subsets if np.allclose(k @ forces, a[body][0], rtol=0, atol=1e-3)]
        assert len(matches) == 1, (body, a[body][0])
        k = matches[0]
        assert a[body][1] == pytest.approx(k @ moments, abs=1e-3)
        assert b[body][0] == pytest.approx((1 - k) @ forces, abs=1e-3)
        assert b[body][1] == pytest.approx((1 - k) @ moments, abs=1e-3)
        pushed += 0 < k.sum() < 5
    assert pushed  # some split block has wall on both sides of the region's edge


# examples/models/tunnel_support.toml: a box gallery 2 m wide and 2.5 m high under a roof
# block between two frictionless vertical joints (x = 2 and x = 4), below a horizontal joint
# at z = 6 without tension or cohesion: only the support holds the roof block (2 x 2 x
# 2.5 m) up.
GALLERY_TEXT = (EXAMPLES / "tunnel_support.toml").read_text()
GALLERY = GALLERY_TEXT[: GALLERY_TEXT.index("[[support]]")]
ROOF_CENTRE = (3.0, 1.0, 4.75)
ROOF_AREA = 2.0 * 2.0  # the gallery's width times the domain's length in y
ROOF_WEIGHT = 2700 * 9.81 * (2.0 * 2.0 * 2.5)  # N: density g volume


def gallery(pressure):
    return pm.prepare(GALLERY + support(face='"gallery"', pressure=pressure))


def test_the_gallery_support_pushes_its_roof_up_with_the_pressure_times_its_area():
    setup = gallery(1e5)
    roof = setup.blocks.containing(ROOF_CENTRE)
    forces = setup.layout.support_forces
    assert forces[roof] == pytest.approx([0, 0, 1e5 * ROOF_AREA], rel=1e-9)
    assert np.abs(setup.layout.support_moments[roof]).max() < 1e-6
    # the floor is pushed down; nothing else is a wall of the gallery
    assert forces.sum(0) == pytest.approx([0, 0, 0], abs=1e-6)


@pytest.mark.parametrize("margin", [0.1, -0.1])
def test_the_roof_block_holds_when_the_support_beats_its_weight_and_falls_otherwise(margin):
    from penedge.model.engine import Engine

    setup = gallery(ROOF_WEIGHT * (1 + margin) / ROOF_AREA)
    roof = setup.blocks.containing(ROOF_CENTRE)
    engine = Engine(setup)
    start = engine.positions()[engine.body[roof]].copy()
    engine.cycle(2000)
    moved = engine.positions()[engine.body[roof]] - start
    t = engine.time
    # falling freely under g |margin| (local damping 0.8 takes 80 % of an unbalanced force)
    fall = 0.5 * 9.81 * abs(margin) * (1 - 0.8) * t**2
    assert fall > 1e-2  # the run is long enough to tell
    if margin > 0:
        # pressed against the block above: at most the joint's elastic closure
        closure = (ROOF_WEIGHT * margin) / (1e9 * ROOF_AREA)
        assert -1e-9 < moved[2] < 2 * closure  # measured 1.00 of it (2026-11-29)
    else:
        assert moved[2] == pytest.approx(-fall, rel=0.05)  # measured 0.2 % off


def test_the_lining_example_solves_with_the_roof_block_held(tmp_path):
    outcome = pm.simulate(EXAMPLES / "tunnel_support.toml", folder=tmp_path)
    assert outcome.stable
    # the lining's 75 kPa beats the weight: the roof block stays, pressed up against the
    # rock above by the joint's elastic closure, (75 kPa x 4 m² - W) / (kn x 4 m²)
    closure = (75e3 * ROOF_AREA - ROOF_WEIGHT) / (1e9 * ROOF_AREA)
    assert 0 < outcome.max_displacement[0] < 2 * closure


def test_a_bolt_within_one_concave_block_is_refused_naming_the_body_and_its_blocks():
    # from the West wall of the block above the tunnel towards the opening, at z = 6.5:
    # through two of its parts, both ends in rock, and no other body on the way
    bolt = (
        "[[bolts]]\npoint = [2.6, 1, 6.5]\ntrend = 90\nplunge = 0\nlength = 1\n"
        "capacity = 1e5\nstiffness = 1e7\n"
    )
    from penedge.model.engine import Engine

    setup = pm.prepare(BASE + bolt)
    ids = np.asarray(setup.system.body_ids)
    collar, _ = setup.layout.bolts[0]
    blocks = np.flatnonzero(ids == ids[collar])
    with pytest.raises(pm.ModelError) as caught:
        Engine(setup)
    body = np.unique(ids).tolist().index(ids[collar])  # bodies by ascending id
    listed = ", ".join(map(str, blocks.tolist()))
    assert caught.value.field == "bolts[0]"
    assert f"lies in one body (body {body}: the concave block made of blocks {listed})" in str(
        caught.value
    )


def test_the_joint_faces_an_excavation_bares_are_its_walls_too():
    # the gallery's sides lie on the joints x = 2 and x = 4: the columns beside it keep the
    # joints' faces, bare from z = 1 to 3.5 (2.5 m x 2 m), pushed into the rock (away from
    # the gallery) at the bare part's centroid, z = 2.25, not the face's (z = 3)
    p = 1e5
    setup = gallery(p)
    forces, moments = setup.layout.support_forces, setup.layout.support_moments
    for x, side in ((1.0, -1.0), (5.0, 1.0)):
        block = setup.blocks.containing((x, 1.0, 3.0))
        assert forces[block] == pytest.approx([side * p * 5.0, 0, 0], rel=1e-9)
        centroid = setup.blocks.centroids[block]  # the column x 0..2 (4..6), z 0..6
        arm = np.array([3.0 - side, 1.0, 2.25]) - centroid
        expected = np.cross(arm, [side * p * 5.0, 0, 0])
        assert moments[block] == pytest.approx(expected, abs=1e-6)


def galleries(face):
    # two galleries through the 10 m wide box, x 2..4 (adit, 2.5 m high) and x 6..8 (drift,
    # 5 m high: its roof on the joint z = 6, bare as well as its sides)
    text = GALLERY.replace("max = [6, 2, 8]", "max = [10, 2, 8]")
    text = text.replace('name = "gallery"\n', 'name = "adit"\n')
    drift = (
        '[[excavations]]\ntype = "cavern"\nname = "drift"\ncenter = [7, 1, 3.5]\ntrend = 0\n'
        "length = 4\nwidth = 2\nheight = 5\n\n"
    )
    text = text.replace("[rock]", drift + "[rock]")
    return pm.prepare(text + support(face=face))


def test_each_excavation_takes_the_joint_faces_it_bared():
    adit, drift = galleries('"adit"'), galleries('"drift"')
    # adit: roof and floor 2 x 2, sides 2.5 x 2; drift: floor 2 x 2 (cut), roof on the joint
    # z = 6 (bare, 2 x 2) and sides 5 x 2 (bare): every wall 2 m long
    assert adit.layout.support_areas == [pytest.approx(2 * (2 + 2.5) * 2, rel=1e-9)]
    assert drift.layout.support_areas == [pytest.approx(2 * (2 + 5) * 2, rel=1e-9)]
    # the drift's roof: the block above it (x 6..8, z 6..8) pushed up on 4 m²
    above = drift.blocks.containing((7.0, 1.0, 7.0))
    assert drift.layout.support_forces[above] == pytest.approx([0, 0, PRESSURE * 4], rel=1e-9)
    assert adit.layout.support_forces[above] == pytest.approx([0, 0, 0])
    # every free face: the box's (2 (10 x 2 + 10 x 8 + 2 x 8)) less the two openings in the
    # North and South faces, and both galleries' walls
    every = galleries(None)
    box = 2 * (20 + 80 + 16) - 2 * (2 * 2.5 + 2 * 5)
    total = box + adit.layout.support_areas[0] + drift.layout.support_areas[0]
    assert every.layout.support_areas == [pytest.approx(total, rel=1e-9)]
