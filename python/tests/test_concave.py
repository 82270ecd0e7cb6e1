"""Concave blocks from Python: bodies of convex parts, their mass properties and their
contacts per pair of bodies, in contact regions (docs/concave-blocks.md). References by hand."""

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
