"""Pictures of concave blocks (convex parts sharing a body id, docs/concave-blocks.md): a
concave block is one block of the picture, in the PNG (matplotlib) and the HTML view
(plotly) alike: one colour in every colouring (its whole body's joint set, one colour of
its own, its whole body's volume), counted once in the legends, and one block of
``max_blocks`` (whole bodies drawn; the note counts bodies).

References: the parts' faces and volumes from ``BlockSystem.arrays``, summed per body here
(face areas by Newell's formula, polygon by polygon); the choice of blocks checked by its
rule (whole bodies, the outside ones first, then the largest), not by a list."""

import io
import json
import re
from pathlib import Path

import numpy as np
import pytest

import penedge
from penedge import pictures
from penedge.pictures.scene import SET_COLORS, build_scene, shown_note, volume_scale

from cli_run import run, squeeze

pytest.importorskip("matplotlib")

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
# Generated with joint sets, each with concave blocks around an excavation or under the
# ground, some of whose parts have different sets of most of their own face area.
CONCAVE = ["tunnel_circular", "cavern", "slope_topography"]


def generated(name):
    system, _ = penedge.generate(EXAMPLES / f"{name}.toml")
    return system


def bodies_of(system):
    """The body (0..B-1, ascending id) of each part, and the body ids."""
    ids, body = np.unique(np.asarray(system.body_ids), return_inverse=True)
    return body, ids


def body_volumes(system):
    body, _ = bodies_of(system)
    return np.bincount(body, weights=np.asarray(system.volumes, dtype=float))


def body_sets(system):
    """Per body, the joint set holding most of the face area of its parts' faces that are
    not internal (ties to the first set), -1 without a joint face."""
    a = system.arrays()
    body, _ = bodies_of(system)
    vertices = np.asarray(a.vertices, dtype=float).reshape(-1, 3)
    loops, corners = np.asarray(a.loop_offsets), np.asarray(a.face_vertices)
    area = {}
    for f, (part, kind, s, inside) in enumerate(
        zip(a.face_block, a.face_origin_kind, a.face_origin_set, a.face_internal, strict=True)
    ):
        if kind != 2 or inside:
            continue
        p = vertices[corners[loops[f] : loops[f + 1]]]
        newell = np.cross(p, np.roll(p, -1, axis=0)).sum(axis=0)
        key = (int(body[part]), int(s))
        area[key] = area.get(key, 0.0) + np.linalg.norm(newell) / 2
    out = np.full(body.max() + 1, -1)
    for b in range(len(out)):
        mine = {s: v for (bb, s), v in area.items() if bb == b and v > 0}
        if mine:
            out[b] = max(sorted(mine), key=lambda s: mine[s])  # ties: the first set
    return out


def hex_rgb(color):
    return np.array([int(color[k : k + 2], 16) / 255 for k in (1, 3, 5)])


def drawn_parts(system, explode, elev=24.0, azim=-56.0, max_blocks=None):
    """The part of each of plot_system's collections (one per part drawn, in part order,
    each the part's faces turned towards the viewer)."""
    scene = build_scene(system, explode, max_blocks)
    e, z = np.radians(elev), np.radians(azim)
    view = np.array([np.cos(e) * np.cos(z), np.cos(e) * np.sin(z), np.sin(e)])
    faces = np.flatnonzero(scene.face_normals @ view > -0.1)
    return np.unique(scene.face_block[faces])


def unit_rows(colors):
    """Colours scaled to unit length: a colour shaded by a face's light is a multiple of
    its block's colour, so the faces of one block give one row."""
    rgb = np.asarray(colors, dtype=float)[:, :3]
    return rgb / np.linalg.norm(rgb, axis=1, keepdims=True)


def test_the_parts_of_a_concave_block_take_one_colour_in_every_colouring_png():
    import matplotlib
    from matplotlib.colors import LogNorm, Normalize

    for name in CONCAVE:
        system = generated(name)
        body, _ = bodies_of(system)
        sets, volumes = body_sets(system), body_volumes(system)
        mixed = [b for b in range(len(sets)) if len(set(own_sets(system)[body == b])) > 1]
        assert mixed, name  # parts of one block whose own faces say different sets
        parts = drawn_parts(system, 0.5)
        lo, hi, log = volume_scale(volumes)
        norm = LogNorm(lo, hi) if log else Normalize(lo, hi)
        cmap = matplotlib.colormaps["viridis"]
        for mode in ("set", "block", "volume"):
            ax = pictures.plot_system(system, color_by=mode, max_blocks=None)
            assert len(ax.collections) == len(parts)
            per_body = {}
            for part, collection in zip(parts, ax.collections, strict=True):
                per_body.setdefault(body[part], []).append(unit_rows(collection.get_facecolor()))
            for b, rows in per_body.items():
                rows = np.vstack(rows)
                assert np.allclose(rows, rows[0], atol=1e-9), (name, mode, b)
                if mode == "set":
                    expected = hex_rgb(SET_COLORS[sets[b] % len(SET_COLORS)])
                elif mode == "volume":
                    expected = np.asarray(cmap(norm(np.clip(volumes[b], lo, hi))))[:3]
                else:
                    continue
                assert np.allclose(rows[0], unit_rows([expected])[0], atol=1e-9), (name, mode, b)


def own_sets(system):
    """The set of most of each part's own face area (as if each part were a block)."""
    plain = system.with_bodies(list(range(len(system))))
    return pictures.dominant_sets(plain.arrays())


def test_dominant_sets_are_those_of_the_whole_body():
    for name in CONCAVE:
        system = generated(name)
        body, _ = bodies_of(system)
        assert pictures.dominant_sets(system.arrays()).tolist() == body_sets(system)[body].tolist()


def test_the_set_legend_counts_a_concave_block_once():
    system = generated("tunnel_circular")
    ax = pictures.plot_system(system, color_by="set", max_blocks=None)
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    counts = [int(re.search(r"\((\d+) blocks?\)", label).group(1)) for label in labels]
    sets = body_sets(system)
    assert sorted(counts) == sorted(np.unique(sets, return_counts=True)[1].tolist())
    assert sum(counts) == len(np.unique(system.body_ids)) < len(system)


def test_labels_name_each_block_once_by_its_body_id():
    system = generated("tunnel_circular")
    ax = pictures.plot_system(system, labels=True, max_blocks=None, explode=0.5)
    labels = [t.get_text() for t in ax.texts if t.get_text().isdigit()]
    assert sorted(map(int, labels)) == sorted(np.unique(system.body_ids).tolist())


def mesh_bodies(trace):
    """The body id of each triangle of an HTML block trace (from its hover data) and the
    triangle's colour value (a constant colour, or its intensity)."""
    custom = np.asarray(trace.customdata)
    ids = custom[np.asarray(trace.i), 0].astype(int)
    if trace.intensity is None:
        values = np.full(len(ids), hash(trace.color), dtype=float)
    else:
        values = np.asarray(trace.intensity, dtype=float)
    return ids, values


@pytest.mark.parametrize("name", ["tunnel_circular", "slope_topography"])
def test_the_parts_of_a_concave_block_take_one_colour_in_every_colouring_html(name):
    pytest.importorskip("plotly")
    system = generated(name)
    _, ids = bodies_of(system)
    volumes = body_volumes(system)
    for mode in ("set", "block", "volume"):
        fig = pictures.html_figure(system, color_by=mode, max_blocks=None, edges=False)
        meshes = [t for t in fig.data if t.type == "mesh3d"]
        seen = {}
        for k, trace in enumerate(meshes):
            tri_ids, values = mesh_bodies(trace)
            for b in np.unique(tri_ids):
                assert b not in seen, (mode, b)  # one trace (legend entry) per block
                seen[b] = k
                assert len(np.unique(values[tri_ids == b])) == 1, (mode, b)
            # Hover: the block's body id and its whole volume.
            custom = np.asarray(trace.customdata)
            where = np.searchsorted(ids, custom[:, 0].astype(int))
            assert np.allclose(custom[:, 1], volumes[where], rtol=1e-6)
        assert sorted(seen) == ids.tolist(), mode
        names = [t.name for t in meshes]
        if mode == "set":  # each entry counts its blocks, a concave block once
            counts = [int(re.search(r"\((\d+)\)$", n).group(1)) for n in names]
            assert sum(counts) == len(ids)
        if mode == "block" and len(ids) <= 30:
            assert names == [f"block {i}" for i in ids]


def shown_ok(system, shown, max_blocks):
    """`shown` (per part) is whole bodies, `max_blocks` of them, the outside ones (a face
    on the domain's surface) first, then the largest by the body's volume."""
    a = system.arrays()
    body, _ = bodies_of(system)
    n_bodies = body.max() + 1
    chosen = np.zeros(n_bodies, dtype=bool)
    chosen[body[shown]] = True
    assert (shown == chosen[body]).all()  # whole bodies
    assert chosen.sum() == min(max_blocks, n_bodies)
    outside = np.zeros(n_bodies, dtype=bool)
    outside[body[np.asarray(a.face_block)[np.asarray(a.face_origin_kind) == 1]]] = True
    volumes = body_volumes(system)
    if (outside & ~chosen).any():
        assert not (chosen & ~outside).any()
    for group in (outside, ~outside):
        if (group & chosen).any() and (group & ~chosen).any():
            assert volumes[group & chosen].min() >= volumes[group & ~chosen].max()
    return chosen


@pytest.mark.parametrize("name", CONCAVE)
def test_max_blocks_counts_bodies_and_draws_whole_ones(name):
    system = generated(name)
    n_bodies = len(np.unique(system.body_ids))
    cut = 0
    for max_blocks in range(1, n_bodies + 1):
        scene = build_scene(system, 0.5, max_blocks)
        chosen = shown_ok(system, scene.shown, max_blocks)
        drawn = np.unique(scene.face_block)
        assert np.isin(drawn, np.flatnonzero(scene.shown)).all()
        note = shown_note(scene)
        if max_blocks < n_bodies:
            assert note.startswith(f"showing {chosen.sum()} of {n_bodies} blocks")
            cut += 1
        else:
            assert note is None  # every body: every part
    assert cut == n_bodies - 1


def test_the_pictures_say_how_many_blocks_they_show():
    pytest.importorskip("plotly")
    system = generated("tunnel_circular")
    n_bodies = len(np.unique(system.body_ids))
    fig = pictures.html_figure(system, max_blocks=5)
    note = fig.layout.annotations[0].text
    assert f"showing 5 of {n_bodies} blocks" in note
    drawn = set()
    for trace in fig.data:
        if trace.type == "mesh3d":
            drawn |= set(mesh_bodies(trace)[0].tolist())
    assert len(drawn) == 5
    figure = pictures.save_picture(system, io.BytesIO(), format="png", max_blocks=5)
    texts = [t.get_text() for t in figure.texts]
    assert any(f"showing 5 of {n_bodies} blocks" in t for t in texts)


def test_show_counts_and_draws_whole_blocks(tmp_path):
    system = generated("tunnel_circular")
    system.write_json(tmp_path / "b.json")
    n_parts, n_bodies = len(system), len(np.unique(system.body_ids))
    result = run("show", "b.json", "--max-blocks", "5", "-o", "b.png", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    lines = squeeze(result.stdout)
    assert lines[0] == f"b.json: {n_bodies} blocks ({n_parts} convex parts)"
    assert (
        f"note: drew 5 of {n_bodies} blocks, those on the outside of the rock mass first "
        "(--max-blocks 0 draws every block)"
    ) in lines
    data = run("show", "b.json", "--max-blocks", "5", "--json", "-o", "c.png", cwd=tmp_path)
    assert data.returncode == 0, data.stderr
    summary = json.loads(data.stdout)
    shown = build_scene(system, 0.5, 5).shown
    shown_ok(system, shown, 5)
    assert (summary["blocks"], summary["bodies"]) == (n_parts, n_bodies)
    assert (summary["shown_blocks"], summary["shown_bodies"]) == (int(shown.sum()), 5)
