"""Pictures: the exploded view (matplotlib, headless) and the HTML view (plotly)."""

import io
import re

import numpy as np
import pytest

import penedge
from penedge import pictures
from penedge.pictures.scene import build_scene, shown_note, volume_scale

import shapes

pytest.importorskip("matplotlib")


def test_exploded_faces_move_blocks_away_from_the_centre():
    system = penedge.paper_example(1)
    parts = pictures.exploded_faces(system, explode=0.5)
    assert len(parts) == 8
    for block, (faces, normals, offset) in zip(system.blocks, parts, strict=True):
        assert np.allclose(offset, 0.5 * (block.centroid - [5, 5, 5]))
        assert len(faces) == len(block.faces) == len(normals)
        assert np.allclose(faces[0], block.vertices[block.faces[0]] + offset)
    still = pictures.exploded_faces(system, explode=0.0)
    assert all(np.allclose(offset, 0) for _, _, offset in still)


def test_block_colors_are_distinct():
    colors = pictures.block_colors(26)
    assert colors.shape == (26, 3)
    assert ((colors >= 0) & (colors <= 1)).all()
    assert len({tuple(np.round(c, 3)) for c in colors}) == 26


def test_plot_system_draws_one_collection_per_block():
    ax = pictures.plot_system(penedge.paper_example(3), title="Example 3")
    assert len(ax.collections) == 26
    assert ax.get_title() == "Example 3"


def test_plot_accepts_a_list_of_blocks_and_colours():
    ax = pictures.plot_system([shapes.cube()], colors=["red"], labels=True)
    assert len(ax.collections) == 1
    assert [t.get_text() for t in ax.texts if t.get_text() not in ("0.2 m", "N")] == ["0"]


def test_save_picture_png_to_a_file_object():
    buffer = io.BytesIO()
    pictures.save_picture(penedge.paper_example(2), buffer, format="png", title="Example 2")
    assert buffer.getvalue().startswith(b"\x89PNG\r\n\x1a\n")


def test_save_picture_to_a_path(tmp_path):
    path = tmp_path / "ex.svg"
    pictures.save_picture(penedge.paper_example(1), path)
    assert path.read_text(encoding="utf-8").lstrip().startswith("<?xml")


def test_empty_system_draws_nothing():
    ax = pictures.plot_system(penedge.BlockSystem([]))
    assert len(ax.collections) == 0


def test_write_html(tmp_path):
    pytest.importorskip("plotly")
    path = tmp_path / "ex.html"
    pictures.write_html(penedge.paper_example(1), path, title="Example 1", include_plotlyjs="cdn")
    text = path.read_text(encoding="utf-8")
    assert "Example 1" in text
    assert text.count('"hovertemplate":"block %{customdata[0]}') == 8
    assert f'id="{pictures.HTML_DIV_ID}"' in text


def test_contact_shapes_group_the_contacts_and_follow_the_blocks():
    system = penedge.paper_example(3)
    found = system.detect(geometry=True)
    points, segments, polygons, kinds = pictures.contact_shapes(found)
    assert points.shape == (205, 3)
    assert segments.shape == (78, 2, 3)
    assert len(polygons) == 42
    assert all(p.shape[1] == 3 and len(p) >= 3 for p in polygons)
    assert np.bincount(kinds).tolist() == [0, 205, 78, 42]
    offsets = np.zeros((len(system), 3))
    offsets[:, 2] = np.arange(len(system))  # block i moved up by i
    moved, _, _, _ = pictures.contact_shapes(found, block_offsets=offsets)
    a, b = found.pairs[found.types == 1][0]
    assert moved[0] - points[0] == pytest.approx([0, 0, (a + b) / 2])


def test_contact_shapes_need_the_geometry():
    with pytest.raises(ValueError, match="geometry=True"):
        pictures.contact_shapes(penedge.paper_example(1).detect())


def test_plot_system_with_contacts_draws_them_over_faint_blocks():
    system = penedge.paper_example(1)
    ax = pictures.plot_system(system, contacts=system.detect(geometry=True))
    # 8 blocks, then face-face polygons, edge-edge superposition lines, vertex-vertex dots
    assert len(ax.collections) == 8 + 3
    legend = [t.get_text() for t in ax.get_legend().get_texts()]
    assert legend == [
        "vertex-vertex (4)",
        "edge-edge-superposition (12)",
        "face-face (12)",
    ]
    assert ax.collections[0].get_facecolor()[:, 3].max() < 0.2


def test_save_picture_with_contacts_has_a_panel_per_contact_type():
    system = penedge.paper_example(3)
    found = system.detect(geometry=True)
    figure = pictures.save_picture(
        system, io.BytesIO(), format="png", title="Example 3", contacts=found
    )
    titles = [ax.get_title() for ax in figure.axes]
    assert titles == [
        "blocks",
        "vertex-vertex (205)",
        "edge-edge-superposition (78)",
        "face-face (42)",
    ]
    assert figure.get_suptitle() == "Example 3"
    dots, lines, polygons = figure.axes[1:]
    # Each panel holds the 26 faint blocks and its own type only: no polygon hides a point.
    assert len(dots.collections) == 26 + 1
    assert len(dots.collections[-1].get_offsets()) == 205
    assert len(lines.collections) == 26 + 1
    assert len(polygons.collections) == 26 + 1
    assert polygons.collections[-1].get_facecolor()[:, 3].max() <= 0.25  # translucent
    assert all(panel.get_legend() is None for panel in (dots, lines, polygons))  # titled


def test_points_and_segments_are_drawn_over_translucent_polygons():
    system = penedge.paper_example(1)
    ax = pictures.plot_system(system, contacts=system.detect(geometry=True))
    by_kind = {type(c).__name__: c for c in ax.collections[8:]}
    polygons = by_kind["Poly3DCollection"]
    lines, dots = by_kind["Line3DCollection"], by_kind["Path3DCollection"]
    assert polygons.get_facecolor()[:, 3].max() <= 0.25
    assert polygons.get_zorder() < lines.get_zorder() < dots.get_zorder()
    assert ax.computed_zorder is False


def test_blocks_as_they_lie_have_real_coordinate_axes_in_the_unit():
    ax = pictures.plot_system(penedge.paper_example(1), explode=0, unit="ft")
    assert ax._axis3don  # what Axes3D.set_axis_on / set_axis_off set (no public getter)
    assert (ax.get_xlabel(), ax.get_ylabel(), ax.get_zlabel()) == (
        "x, east (ft)",
        "y, north (ft)",
        "z, up (ft)",
    )
    for lo, hi in (ax.get_xlim(), ax.get_ylim(), ax.get_zlim()):
        assert lo <= 0 <= 10 <= hi < lo + 11  # the 10 ft cube, where it lies
    assert "N" not in [t.get_text() for t in ax.texts]


def test_an_exploded_view_has_a_scale_bar_and_a_north_arrow():
    ax = pictures.plot_system(penedge.paper_example(1), explode=0.5, unit="m")
    assert not ax._axis3don  # the moved positions are not coordinates
    texts = [t.get_text() for t in ax.texts]
    # The exploded cube spans 15 m (each 5 m block moved out by 2.5 m): a 2 m bar.
    assert "2 m" in texts
    assert "N" in texts
    north = next(t for t in ax.texts if t.get_text() == "N")
    bar = next(t for t in ax.texts if t.get_text() == "2 m")
    assert north.get_position()[1] > bar.get_position()[1]  # the arrow points to +y
    assert pictures.blocks.nice_length(15) == 2
    assert pictures.blocks.nice_length(100) == 20
    assert pictures.blocks.nice_length(0.3) == 0.05


SETS_SPEC = {
    "domain": {"type": "box", "min": [0, 0, 0], "max": [10, 10, 10]},
    "joints": [
        {
            "name": "bedding",
            "type": "set",
            "dip": 0,
            "dip_direction": 0,
            "spacing": 2,
            "origin": [0, 0, 2],
        },
        {
            "name": "joints",
            "type": "set",
            "dip": 90,
            "dip_direction": 90,
            "spacing": 5,
            "origin": [5, 0, 0],
        },
    ],
}


def test_blocks_are_coloured_by_their_dominant_joint_set_with_a_legend():
    system, _ = penedge.generate(SETS_SPEC)
    # 5 bedding layers (z) by 2 slabs (x): each block is 5 x 10 x 2 m. Its bedding faces
    # (z) are 50 m² each, its joint face (x) 20 m²: bedding dominates every block; the
    # top and bottom layers have one bedding face (50 m²) against one joint face (20 m²).
    assert len(system) == 10
    assert pictures.dominant_sets(system.arrays()).tolist() == [0] * 10
    ax = pictures.plot_system(system)  # a generated system: by set
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert labels == ["bedding (10 blocks)"]
    rgb = np.array([int(pictures.SET_COLORS[0][k : k + 2], 16) / 255 for k in (1, 3, 5)])
    for collection in ax.collections:
        shade = collection.get_facecolor()[:, :3] / rgb
        assert np.allclose(shade, shade[:, :1], atol=1e-9)  # the set colour, shaded


def test_dominant_set_follows_the_larger_area():
    spec = {
        **SETS_SPEC,
        "joints": [
            {
                "name": "bedding",
                "type": "set",
                "dip": 0,
                "dip_direction": 0,
                "spacing": 5,
                "origin": [0, 0, 5],
            },
            {
                "name": "joints",
                "type": "set",
                "dip": 90,
                "dip_direction": 90,
                "spacing": 1,
                "origin": [1, 0, 0],
            },
        ],
    }
    system, _ = penedge.generate(spec)
    # 2 layers by 10 slabs, each 1 x 10 x 5 m: their joint faces (10 x 5 = 50 m²) outweigh
    # their bedding face (1 x 10 = 10 m²), the end slabs' one joint face too: all joints.
    expected = []
    for block in system.blocks:
        normals = block.face_normals
        areas = [polygon_area(block.vertices[f]) for f in block.faces]
        inner = [not on_box(block.vertices[f]) for f in block.faces]
        bedding = sum(
            a for a, n, j in zip(areas, normals, inner, strict=True) if j and abs(n[2]) > 0.5
        )
        joints = sum(
            a for a, n, j in zip(areas, normals, inner, strict=True) if j and abs(n[2]) < 0.5
        )
        expected.append(1 if joints > bedding else 0)
    assert len(system) == 20
    assert pictures.dominant_sets(system.arrays()).tolist() == expected == [1] * 20


def polygon_area(points):
    total = np.zeros(3)
    for k in range(1, len(points) - 1):
        total += np.cross(points[k] - points[0], points[k + 1] - points[0])
    return np.linalg.norm(total) / 2


def on_box(points):
    return any(np.allclose(points[:, k], v) for k in range(3) for v in (0, 10))


def test_contacts_are_coloured_by_the_joint_set_of_their_faces():
    system, _ = penedge.generate(SETS_SPEC)
    found = system.detect(geometry=True)
    scene = build_scene(system)
    sets = scene.contact_sets(found)
    a = system.arrays()
    for i, ((x, y), (kx, ky), (fx, fy)) in enumerate(
        zip(found.pairs, found.feature_kinds, found.feature_ids, strict=True)
    ):
        if kx == 2:
            assert sets[i] == a.face_origin_set[a.face_offsets[x] + fx]
        elif ky == 2:
            assert sets[i] == a.face_origin_set[a.face_offsets[y] + fy]
        else:
            assert sets[i] == -1
    face_face = found.types == 7
    counts = {0: int((sets[face_face] == 0).sum()), 1: int((sets[face_face] == 1).sum())}
    assert counts == {0: 8, 1: 5}  # 4 bedding planes x 2 slabs; 1 joint plane x 5 layers
    ax = pictures.plot_system(system, contacts=found)
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert ax.get_legend().get_title().get_text() == "joint set of the contact's face"
    assert labels[:2] == ["bedding (8)", "joints (5)"]
    assert len(labels) == 2 or labels[2].startswith("no joint face (")


def test_volume_distribution_marks_v10_v50_v90():
    system = penedge.paper_example(3)
    ax = pictures.plot_volume_distribution(system)
    assert ax.get_xscale() == "log"
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert labels[2:] == ["V10 = 20.83", "V50 = 41.67", "V90 = 125"]
    stats = system.statistics()
    assert [pictures.passing_volume(system.volumes, x) for x in (10, 50, 90)] == [
        stats["v10"],
        stats["v50"],
        stats["v90"],
    ]


def test_volume_distribution_leaves_out_tiny_slivers_and_says_so():
    volumes = np.concatenate([np.full(100, 10.0), [1e-12, 1e-9]])
    ax = pictures.plot_volume_distribution(volumes)
    assert ax.get_xlim()[0] > 1e-3
    notes = [t.get_text() for t in ax.texts]
    assert len(notes) == 1
    assert notes[0].startswith("not shown: 2 smaller blocks, down to v = 1e-12")


def test_volume_distribution_of_equal_blocks_and_of_none():
    ax = pictures.plot_volume_distribution(np.full(8, 125.0))
    lo, hi = ax.get_xlim()
    assert lo < 125 < hi
    assert hi / lo > 5
    with pytest.raises(ValueError, match="no blocks"):
        pictures.plot_volume_distribution(penedge.BlockSystem([]))


def test_save_volume_distribution_png():
    buffer = io.BytesIO()
    figure = pictures.save_volume_distribution(penedge.paper_example(2), buffer, format="png")
    assert buffer.getvalue().startswith(b"\x89PNG\r\n\x1a\n")
    assert figure.axes[0].get_title() == "Block volume distribution: 8 blocks"


def grid(n):
    """A cube of side n cut into n^3 unit cubes."""
    normals = [[1, 0, 0]] * (n - 1) + [[0, 1, 0]] * (n - 1) + [[0, 0, 1]] * (n - 1)
    offsets = list(range(1, n)) * 3
    return penedge.BlockSystem.from_box_cut([0, 0, 0], [n, n, n], normals, offsets)


def test_scene_triangles_edges_and_polygons_of_a_cube():
    scene = build_scene([shapes.cube()], explode=0.5)
    faces = np.arange(scene.n_faces)
    tris, tri_face = scene.triangles(faces)
    assert tris.shape == (12, 3)
    assert np.bincount(tri_face).tolist() == [2] * 6
    assert len(scene.edges(faces)) == 12
    normals = scene.face_normals[tri_face]
    a, b, c = (scene.vertices[tris[:, k]] for k in range(3))
    assert np.allclose(np.cross(b - a, c - a), normals)  # counter-clockwise from outside
    polygons = scene.polygons()
    assert [p.shape for p in polygons] == [(4, 3)] * 6


def test_scene_explodes_as_exploded_faces():
    system = penedge.paper_example(3)
    scene = build_scene(system, explode=0.7)
    parts = pictures.exploded_faces(system, explode=0.7)
    assert np.allclose(scene.offsets, [offset for _, _, offset in parts])
    by_block = [p for p, b in zip(scene.polygons(), scene.face_block, strict=True) if b == 5]
    assert all(np.allclose(p, q) for p, q in zip(by_block, parts[5][0], strict=True))


def test_a_large_system_keeps_the_blocks_on_the_outside_first():
    system = grid(5)  # 125 cubes, 27 inside
    scene = build_scene(system, max_blocks=100)
    assert (scene.n_blocks, scene.n_shown) == (125, 98 + 2)
    centre = np.asarray(system.centroids)
    inside = (np.abs(centre - 2.5) < 1.5).all(axis=1)
    assert inside.sum() == 27
    assert scene.shown[~inside].all()  # the 98 outer cubes, then 2 of the (equal) inner
    assert set(np.unique(scene.face_block)) == set(np.flatnonzero(scene.shown))
    assert shown_note(scene).startswith("showing 100 of 125 blocks")
    assert shown_note(build_scene(system)) is None
    with pytest.raises(ValueError, match="at least 1"):
        build_scene(system, max_blocks=0)


def test_volume_scale_leaves_slivers_at_its_bottom():
    lo, hi, log = volume_scale(np.concatenate([np.full(100, 10.0), [1e-9, 1e-6]]))
    assert (lo, hi, log) == (pytest.approx(0.1), 10.0, True)  # V10 / 100
    lo, hi, log = volume_scale(np.array([1.0, 50.0, 100.0]))
    assert (lo, hi, log) == (1.0, 100.0, True)
    assert volume_scale(np.array([2.0, 3.0])) == (2.0, 3.0, False)
    assert volume_scale(np.full(3, 125.0)) == (pytest.approx(112.5), pytest.approx(137.5), False)


def test_colour_by_volume_has_a_colour_bar_and_yellow_large_blocks():
    system = penedge.paper_example(3)
    ax = pictures.plot_system(system, color_by="volume")
    bars = [a for a in ax.figure.axes if a is not ax]
    assert len(bars) == 1
    assert bars[0].get_ylabel().startswith("block volume")
    volumes = system.volumes
    brightness = [c.get_facecolor()[:, :3].mean() for c in ax.collections]
    largest, smallest = int(np.argmax(volumes)), int(np.argmin(volumes))
    assert brightness[largest] > brightness[smallest] + 0.2  # viridis: yellow over purple
    by_block = pictures.plot_system(system)
    assert len(by_block.figure.axes) == 1  # no colour bar
    with pytest.raises(ValueError, match="color_by"):
        pictures.plot_system(system, color_by="size")


def test_many_blocks_share_one_collection_and_a_cut_down_system_says_so():
    system = grid(12)  # 1728 blocks
    ax = pictures.plot_system(system, max_blocks=1600)
    assert len(ax.collections) == 1
    faces = len(ax.collections[0].get_facecolor())
    assert faces == 1600 * 3  # the +x, -y and +z faces of each cube face the viewer
    notes = [t.get_text() for t in ax.texts if t.get_text() not in ("2 m", "N")]
    assert notes == [
        "showing 1600 of 1728 blocks: those on the outside of the rock mass first, then the largest"
    ]


def test_html_figure_has_a_mesh_and_edges_per_block_with_hover():
    pytest.importorskip("plotly")
    system = penedge.paper_example(1)
    fig = pictures.html_figure(system, explode=0.5)
    meshes = [t for t in fig.data if t.type == "mesh3d"]
    edges = [t for t in fig.data if t.type == "scatter3d"]
    assert [t.name for t in meshes] == [f"block {i}" for i in range(8)]
    assert [t.legendgroup for t in edges] == [f"block {i}" for i in range(8)]
    assert not any(t.showlegend for t in edges)
    parts = pictures.exploded_faces(system, explode=0.5)
    for i, mesh in enumerate(meshes):
        xyz = np.column_stack([mesh.x, mesh.y, mesh.z])
        corners = np.unique(np.vstack(parts[i][0]), axis=0)
        assert np.allclose(np.unique(xyz, axis=0), corners)
        assert len(mesh.i) == 12  # six squares, two triangles each
        custom = np.asarray(mesh.customdata)
        assert custom[:, :2].tolist() == [[i, 125.0]] * 8
        # The hover gives where each vertex really is, not where the exploded view put it.
        real = np.unique(system[i].vertices, axis=0)
        assert np.array_equal(np.unique(custom[:, 2:], axis=0), real)
        assert mesh.hovertemplate.startswith(
            "block %{customdata[0]}<br>volume %{customdata[1]:.4g} m³<br>vertex at x "
        )
    segments = np.column_stack([edges[0].x, edges[0].y, edges[0].z])
    assert len(segments) == 12 * 3  # 12 edges, each two points and a break
    assert np.isnan(segments[2::3]).all()


def test_html_figure_draws_each_contact_type_in_its_own_legend():
    pytest.importorskip("plotly")
    system = penedge.paper_example(3)
    found = system.detect(geometry=True)
    fig = pictures.html_figure(system, contacts=found)
    contact = [t for t in fig.data if t.legend == "legend2"]
    shown = [t.name for t in contact if t.showlegend]
    assert shown == ["vertex-vertex (205)", "edge-edge-superposition (78)", "face-face (42)"]
    by_name = {t.name: t for t in contact}
    dots = by_name["vertex-vertex (205)"]
    assert (dots.type, dots.mode, len(dots.x)) == ("scatter3d", "markers", 205)
    lines = by_name["edge-edge-superposition (78)"]
    assert (lines.type, lines.mode, len(lines.x)) == ("scatter3d", "lines", 78 * 3)
    polygons = by_name["face-face (42)"]
    assert polygons.type == "mesh3d"
    pairs = {tuple(p) for p in found.pairs[found.types == 7].tolist()}
    assert {tuple(int(v) for v in row) for row in np.asarray(polygons.customdata)} == pairs
    assert polygons.hovertemplate.startswith("face-face<br>blocks %{customdata[0]} and")
    blocks = [t for t in fig.data if t.type == "mesh3d" and t.legend != "legend2"]
    assert {t.opacity for t in blocks} == {0.3}  # translucent over the contacts


def test_html_axes_are_real_coordinates_or_hidden_when_exploded():
    pytest.importorskip("plotly")
    system = penedge.paper_example(1)
    fig = pictures.html_figure(system, explode=0, unit="km")
    scene = fig.layout.scene
    assert scene.xaxis.title.text == "x, east (km)"
    assert scene.zaxis.title.text == "z, up (km)"
    assert scene.xaxis.showticklabels is not False
    meshes = [t for t in fig.data if t.type == "mesh3d"]
    xyz = np.vstack([np.column_stack([m.x, m.y, m.z]) for m in meshes])
    assert (xyz.min(), xyz.max()) == (0, 10)  # real coordinates
    exploded = pictures.html_figure(system, explode=0.5).layout.scene
    assert exploded.xaxis.showticklabels is False
    assert exploded.xaxis.title.text == "x, east (exploded)"


def test_html_groups_blocks_by_joint_set():
    pytest.importorskip("plotly")
    system, _ = penedge.generate(SETS_SPEC)
    fig = pictures.html_figure(system)
    meshes = [t for t in fig.data if t.type == "mesh3d"]
    assert [m.name for m in meshes] == ["bedding (10)"]
    assert meshes[0].color == pictures.SET_COLORS[0]


def test_html_figure_groups_many_blocks():
    pytest.importorskip("plotly")
    system = grid(4)  # 64 blocks
    fig = pictures.html_figure(system)
    meshes = [t for t in fig.data if t.type == "mesh3d"]
    assert len(meshes) == 20
    assert meshes[0].name == "blocks 0 to 3"
    ids = np.concatenate([np.unique(np.asarray(m.customdata)[:, 0]) for m in meshes])
    assert sorted(ids.astype(int).tolist()) == list(range(64))
    assert len(np.unique(meshes[0].intensity)) == 4  # each block its colour
    by_volume = pictures.html_figure(penedge.paper_example(3).blocks * 2, color_by="volume")
    names = [t.name for t in by_volume.data if t.type == "mesh3d"]
    assert names[0].startswith("volume 20.8 to ")
    assert sum(int(re.search(r"\((\d+)\)$", n).group(1)) for n in names) == 52
    assert by_volume.layout.coloraxis.colorbar.title.text == "block volume"
    assert {t.coloraxis for t in by_volume.data if t.type == "mesh3d"} == {"coloraxis"}


def test_html_stays_small_for_thousands_of_blocks(tmp_path):
    pytest.importorskip("plotly")
    system = grid(20)  # 8000 blocks
    path = tmp_path / "big.html"
    pictures.write_html(system, path, include_plotlyjs=False)
    size = path.stat().st_size
    # Bytes per block: binary arrays, no edges above 5000 blocks; about 130 of them are
    # the hover's real coordinates (three float32 per vertex, base64).
    assert size < 8000 * 700
    text = path.read_text(encoding="utf-8")
    assert '"bdata"' in text
    cut = tmp_path / "cut.html"
    pictures.write_html(system, cut, include_plotlyjs=False, max_blocks=1000)
    assert "showing 1000 of 8000 blocks" in cut.read_text(encoding="utf-8")


def test_write_html_embeds_plotly_js(tmp_path):
    pytest.importorskip("plotly")
    path = tmp_path / "ex.html"
    pictures.write_html(penedge.paper_example(1), path)
    text = path.read_text(encoding="utf-8")
    assert not re.search(r"<script[^>]+src=", text)
    assert len(text) > 1_000_000  # plotly.js itself


def test_too_many_contacts_are_cut_down_to_those_nearest_the_viewer():
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    system = grid(6)  # 216 cubes
    found = system.detect(geometry=True)
    assert len(found) > 1000
    ax = pictures.plot_system(system)
    blocks = len(ax.collections)
    pictures.plot_contacts(found, ax=ax, max_contacts=100)
    FigureCanvasAgg(ax.figure).draw()
    drawn = 0
    for c in ax.collections[blocks:]:
        if hasattr(c, "get_segments"):
            drawn += len(c.get_segments())
        elif type(c).__name__ == "Path3DCollection":
            drawn += len(c.get_offsets())
        else:
            drawn += len(c.get_paths())
    assert drawn == 100
    notes = [t.get_text() for t in ax.texts if t.get_text() not in ("1 m", "N")]  # scale, north
    assert notes == [f"showing 100 of {len(found)} contacts: those nearest the viewer"]
    legend = [t.get_text() for t in ax.get_legend().get_texts()]
    counts = found.counts()
    assert legend == [f"{name} ({n})" for name, n in counts.items() if n]  # all, not the drawn
    every = pictures.plot_system(system, contacts=found)
    assert [t.get_text() for t in every.texts] == ["1 m", "N"]  # under 3000: every contact


def test_the_spec_unit_labels_the_pictures(tmp_path):
    system, _ = penedge.generate({**SETS_SPEC, "unit": "ft"})
    assert system.unit == "ft"
    assert penedge.generate(SETS_SPEC)[0].unit is None
    system.write_json(tmp_path / "blocks.json")
    again = penedge.BlockSystem.read_json(tmp_path / "blocks.json")
    assert again.unit == "ft"
    ax = pictures.plot_system(again, explode=0)
    assert ax.get_xlabel() == "x, east (ft)"
    assert pictures.plot_system(again, explode=0, unit="yd").get_xlabel() == "x, east (yd)"
    exploded = [t.get_text() for t in pictures.plot_system(again).texts]
    assert "2 ft" in exploded
    assert pictures.plot_volume_distribution(again).get_xlabel() == "block volume v (ft³)"
    with pytest.raises(penedge.SpecError) as info:
        penedge.generate({**SETS_SPEC, "unit": ""})
    assert info.value.field == "unit"


def test_polygons_of_different_sizes_never_reach_matplotlib_unfilled(monkeypatch):
    # matplotlib (3.10+) pads a ragged list of polygons with np.empty and scales the axes to
    # the padding: by chance an overflow (CI failed on one: warnings are errors there) or
    # wrong limits. Here uninitialised memory is the worst case: the largest float.
    import warnings

    system, _ = penedge.generate(
        {
            "domain": {"type": "box", "min": [0, 0, 0], "max": [4, 4, 4]},
            "joints": [
                {"type": "plane", "point": [2, 2, 2], "normal": [1, 0.3, 0.2]},
                {"type": "plane", "point": [2, 1, 2], "normal": [0.1, 1, 0.4]},
                {"type": "plane", "point": [1, 2, 2.5], "normal": [0.3, -0.2, 1]},
            ],
        }
    )
    scene = build_scene(system, 0.0, None)
    sizes = {len(p) for p in scene.polygons()}
    assert len(sizes) > 1, sizes  # ragged: the case matplotlib pads
    found = system.detect(geometry=True)
    empty = np.empty

    def poisoned(*args, **kwargs):
        out = empty(*args, **kwargs)
        if out.dtype.kind == "f":
            out.fill(np.finfo(out.dtype).max)
        return out

    monkeypatch.setattr(np, "empty", poisoned)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for contacts in (None, found):
            ax = pictures.plot_system(system, contacts=contacts, explode=0)
            ax.figure.savefig(io.BytesIO(), format="png")  # projects every face
            for limits in (ax.get_xlim(), ax.get_ylim(), ax.get_zlim()):
                assert -4 < limits[0] < limits[1] < 8, limits
