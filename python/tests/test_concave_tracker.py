"""The contact tracker on concave blocks: regions of the bodies step by step."""

import numpy as np
import pytest

import penedge


def notch_system():
    """A U-block of three parts (body 0) and a block in its notch (body 1)."""
    c = penedge.Block.cuboid
    u = [c([0, 0, 0], [3, 1, 1]), c([0, 0, 1], [1, 1, 2]), c([2, 0, 1], [3, 1, 2])]
    return penedge.BlockSystem([*u, c([1, 0, 1], [2, 1, 2])]).with_bodies([0, 0, 0, 1])


def moved(system, translations):
    """The system's blocks translated, with its bodies (an independent placement)."""
    blocks = [b.translated(t) for b, t in zip(system.blocks, translations, strict=True)]
    return penedge.BlockSystem(blocks).with_bodies(system.body_ids.tolist())


def same_regions(a, b):
    """The discrete answers are equal, the numbers within 1e-9."""
    assert a.bodies.tolist() == b.bodies.tolist()
    assert a.regions.tolist() == b.regions.tolist()
    assert a.types.tolist() == b.types.tolist()
    assert a.penetrating.tolist() == b.penetrating.tolist()
    assert a.piece_parts.tolist() == b.piece_parts.tolist()
    np.testing.assert_allclose(a.normals, b.normals, atol=1e-9)
    np.testing.assert_allclose(a.areas, b.areas, atol=1e-9)


def test_the_tracker_follows_a_block_leaving_its_notch_region_by_region():
    system = notch_system()
    tracker = penedge.ContactTracker(system, skin=0.1)
    assert tracker.body_contacts.regions.tolist() == [0, 1, 2]
    rotations = np.tile([0.0, 0.0, 0.0, 1.0], (4, 1))
    # Lifted 1 mm: the two walls; 2 mm: the same; pushed 1 mm into the right wall:
    # penetrating, no region; back home: three regions again.
    shifts = [[0, 0, 1e-3], [0, 0, 2e-3], [1e-3, 0, 1e-3], [0, 0, 0]]
    for step, (shift, expected) in enumerate(zip(shifts, [2, 2, 0, 3], strict=True)):
        translations = np.zeros((4, 3))
        translations[3] = shift
        tracker.update(rotations, translations)
        found = tracker.body_contacts
        assert len(found) == expected, step
        assert found.regions.tolist() == list(range(expected))
        assert found.penetrating.tolist() == ([[0, 1]] if expected == 0 else [])
        same_regions(found, moved(system, translations).detect_bodies())
        # The part contacts are those between parts of different bodies.
        assert all(3 in pair for pair in tracker.contacts.pairs.tolist())


def test_parts_of_one_body_must_share_a_pose():
    tracker = penedge.ContactTracker(notch_system(), skin=0.1)
    rotations = np.tile([0.0, 0.0, 0.0, 1.0], (4, 1))
    translations = np.zeros((4, 3))
    translations[1, 2] = 1e-3
    with pytest.raises(penedge.InputError, match="body 0"):
        tracker.update(rotations, translations)
    assert len(tracker.body_contacts) == 3


def test_convex_blocks_tracked_as_bodies_on_request():
    system = penedge.paper_example(1)
    assert penedge.ContactTracker(system).body_contacts is None
    tracker = penedge.ContactTracker(system, skin=0.1, bodies=True)
    found = tracker.body_contacts
    assert found.bodies.tolist() == tracker.contacts.pairs.tolist()
    assert set(found.regions.tolist()) == {0}
    with pytest.raises(penedge.InputError, match="bodies"):
        penedge.ContactTracker(notch_system(), bodies=False)
