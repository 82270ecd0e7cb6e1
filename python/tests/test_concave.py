"""Concave blocks from Python: bodies of convex parts, their mass properties and their
contacts per pair of bodies, in contact regions (docs/concave-blocks.md). References by hand."""

import json

import numpy as np
import pytest

import penedge

cuboid = penedge.Block.cuboid


def u_block():
    """A U-block [0, 3] x [0, 1] x [0, 2] less the notch [1, 2] x [0, 1] x [1, 2], in 3 parts."""
    return [
        cuboid([0, 0, 0], [3, 1, 1]),
        cuboid([0, 0, 1], [1, 1, 2]),
        cuboid([2, 0, 1], [3, 1, 2]),
    ]


def test_a_block_in_a_notch_touches_it_in_three_regions():
    system = penedge.BlockSystem([*u_block(), cuboid([1, 0, 1], [2, 1, 2.5])])
    found = system.with_bodies([0, 0, 0, 1]).detect_bodies()
    assert len(found) == 3
    assert found.bodies.tolist() == [[0, 1]] * 3
    assert found.regions.tolist() == [0, 1, 2]
    assert set(found.types.tolist()) == {penedge.FACE_FACE}
    assert np.allclose(found.areas, 1.0)
    normals = sorted(map(tuple, np.round(found.normals, 12).tolist()))
    assert normals == [(-1.0, 0.0, 0.0), (0.0, 0.0, 1.0), (1.0, 0.0, 0.0)]
    # Each region is one part contact here; the part of body 0 comes first.
    assert found.piece_offsets.tolist() == [0, 1, 2, 3]
    assert sorted(found.piece_parts[:, 1].tolist()) == [3, 3, 3]


def test_a_face_face_contact_across_a_glue_face_is_one_region_of_the_total_area():
    # The floor cut at x = 1.5 under a block lying across the cut.
    parts = [cuboid([0, 0, 0], [1.5, 1, 1]), cuboid([1.5, 0, 0], [3, 1, 1])]
    system = penedge.BlockSystem([*parts, cuboid([1, 0, 1], [2, 1, 2])])
    assert len(system.detect()) == 3  # as separate blocks: three part contacts
    found = system.with_bodies([0, 0, 1]).detect_bodies()
    assert len(found) == 1
    assert found.types.tolist() == [penedge.FACE_FACE]
    assert found.areas.tolist() == pytest.approx([1.0])
    assert found.piece_offsets.tolist() == [0, 2]
    assert found.piece_point_offsets[-1] == len(found.piece_points) == 8


def test_body_ids_internal_faces_and_mass_properties():
    system = penedge.BlockSystem(u_block()).with_bodies([5, 5, 5])
    assert system.body_ids.tolist() == [5, 5, 5]
    glue = system.internal_faces()
    assert glue["parts"].tolist() == [[0, 1], [0, 2]]
    assert glue["areas"].tolist() == pytest.approx([1.0, 1.0])
    m = system.body_mass_properties()
    assert m["bodies"].tolist() == [5]
    assert m["volumes"].tolist() == pytest.approx([5.0])
    # Centroid by hand: slab 3 at (1.5, 0.5, 0.5), arms 1 each at (0.5 | 2.5, 0.5, 1.5).
    assert m["centroids"][0] == pytest.approx([1.5, 0.5, (1.5 + 3.0) / 5.0])
    assert m["inertia"].shape == (1, 3, 3)
    assert np.allclose(m["inertia"][0], m["inertia"][0].T)
    # Convex blocks by default: each block its own body.
    assert penedge.BlockSystem(u_block()).body_ids.tolist() == [0, 1, 2]


def test_bad_parts_are_named():
    apart = penedge.BlockSystem([cuboid([0, 0, 0], [1, 1, 1]), cuboid([2, 0, 0], [3, 1, 1])])
    with pytest.raises(penedge.InputError, match=r"body 0.*glued face to face") as e:
        apart.with_bodies([0, 0])
    assert e.value.kind == "concave"
    overlapping = penedge.BlockSystem(
        [cuboid([0, 0, 0], [1, 1, 1]), cuboid([0.5, 0, 0], [2, 1, 1])]
    )
    with pytest.raises(penedge.InputError, match="overlap"):
        overlapping.with_bodies([0, 0])
    with pytest.raises(penedge.InputError) as e:
        apart.with_bodies([0])
    assert e.value.kind == "body_ids"
    with pytest.raises(penedge.InputError):
        apart.with_bodies([0, -1])


def needles_json():
    """Two parts of one body of a fine zig-zag slope excavation, as generated (planes
    included, read back bit for bit): prisms 10 m long along y, needles 2.6 m by 2 to 8 mm in
    section, glued along a slope face. The stored plane of that long thin face puts the
    needles' shared tip 1.27e-8 off it, beyond the pair's length threshold (1.03e-8)."""
    x0, x1, x2 = 6.619577447, 6.618327291000001, 7.1446246588908355
    z0, z1, z2 = 6.7027870550000035, 6.688780474999998, 4.175638512728671
    first = {
        "vertices": [
            [x0, 0, z0],
            [x1, 0, z1],
            [x2, 0, z2],
            [x2, 10, z2],
            [x1, 10, z1],
            [x0, 10, z0],
        ],
        "faces": [[0, 1, 2], [3, 4, 5], [2, 1, 4, 3], [5, 4, 1, 0], [2, 3, 5, 0]],
        "planes": [
            [0, -1, 0, 5, 0, 5],
            [0, 1, 0, 5, 10, 5],
            [-0.9787679009252925, 0, -0.20497169589554765, 6.617702213, 5, 6.691765308000001],
            [-0.996040422910225, 0, 0.08890149565007498, 6.6189523690000005, 5, 6.695783765],
            [0.9790918262847176, 0, 0.2034187692973699, 6.620202525000001, 5, 6.699778439999996],
        ],
    }
    u0, u1, u3 = 6.622077759999999, 6.620827602990678, 7.1446306101978
    w0, w1, w3 = 6.710728727000002, 6.69676982489592, 4.175610319778413
    second = {
        "vertices": [
            [u0, 0, w0],
            [u1, 0, w1],
            [x2, 0, z2],
            [u3, 0, w3],
            [u3, 10, w3],
            [x2, 10, z2],
            [u1, 10, w1],
            [u0, 10, w0],
        ],
        "faces": [
            [0, 1, 2, 3],
            [4, 5, 6, 7],
            [3, 2, 5, 4],
            [2, 1, 6, 5],
            [7, 6, 1, 0],
            [3, 4, 7, 0],
        ],
        "planes": [
            [0, -1, 0, 5, 0, 5],
            [0, 1, 0, 5, 10, 5],
            [-0.9784380582140522, 0, -0.20654047118740412, 6.6152019, 5, 6.683657271499988],
            [-0.9790918262847176, 0, -0.2034187692973699, 6.620202525000001, 5, 6.699778439999996],
            [-0.9960134835347997, 0, 0.08920280610425566, 6.621452681499999, 5, 6.703749275999999],
            [0.9794099583739811, 0, 0.2018814836429451, 6.622702838, 5, 6.707696217000001],
        ],
    }
    for body, block in enumerate((first, second)):
        block["body"] = body
        block["origins"] = [{"kind": "unknown"}] * len(block["faces"])
    # The file's length threshold: twice the largest distance of a vertex from its face's
    # plane, over the system's size.
    system = {"format": "penedge-blocks", "version": 2, "length": 2.4636751916705936e-09}
    return json.dumps({**system, "blocks": [first, second]})


def test_needle_parts_that_only_touch_are_glued_not_refused():
    system = penedge.BlockSystem.from_json(needles_json())
    # The detection calls the pair penetrating: no face of the second part holds the tip.
    assert penedge.detect_pair(system.blocks[0], system.blocks[1]).outcome == "penetrating"
    glued = system.with_bodies([0, 0])
    faces = glued.internal_faces()
    assert faces["parts"].tolist() == [[0, 1]]
    assert faces["faces"].tolist() == [[4, 3]]
    # The second part's face, whole: its length across times 10 m.
    tip, end = np.array(system.blocks[1].vertices)[[1, 2]]
    assert faces["areas"][0] == pytest.approx(np.linalg.norm(tip - end) * 10, rel=1e-9)


def test_json_keeps_the_bodies(tmp_path):
    system = penedge.BlockSystem(u_block()).with_bodies([2, 2, 2])
    back = penedge.BlockSystem.from_json(system.to_json())
    assert back.body_ids.tolist() == [2, 2, 2]
    assert len(back.internal_faces()["areas"]) == 2


def test_pictures_draw_a_concave_block_as_one_block():
    from penedge.pictures.scene import build_scene

    system = penedge.BlockSystem([*u_block(), cuboid([5, 0, 0], [6, 1, 1])])
    concave = system.with_bodies([0, 0, 0, 1])
    a = concave.arrays()
    assert a.body_ids.tolist() == [0, 0, 0, 1]
    # The arms' bottoms lie on the slab: inside the block. The slab's top is covered only
    # under the arms: a real face (the notch's floor).
    assert a.face_internal.sum() == 2
    assert a.face_internal[a.face_block == 0].sum() == 0
    scene = build_scene(concave, explode=0.5)
    assert scene.n_faces == 4 * 6 - 2
    assert scene.body_first.tolist() == [0, 0, 0, 3]
    # The parts move together: one offset for the whole U-block.
    assert np.allclose(scene.offsets[:3], scene.offsets[0])
    separate = build_scene(system, explode=0.5)
    assert separate.n_faces == 4 * 6
    assert not np.allclose(separate.offsets[1], separate.offsets[0])


def test_contact_regions_are_written_to_csv_and_vtp(tmp_path):
    system = penedge.BlockSystem([*u_block(), cuboid([1, 0, 1], [2, 1, 2.5])])
    found = system.with_bodies([0, 0, 0, 1]).detect_bodies()
    found.write_csv(tmp_path / "regions.csv")
    rows = (tmp_path / "regions.csv").read_text().splitlines()
    assert rows[0].startswith("body_a,body_b,region,type,area")
    assert [r.split(",")[2] for r in rows[1:]] == ["0", "1", "2"]
    found.write_vtp(tmp_path / "regions.vtp")
    text = (tmp_path / "regions.vtp").read_text()
    assert 'Name="region"' in text
    assert 'NumberOfPolys="3"' in text
