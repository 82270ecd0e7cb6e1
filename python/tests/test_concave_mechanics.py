"""A concave block (glued convex parts) is one rigid body in ``penedge.Simulation``."""

import numpy as np

import penedge

DENSITY = 2500.0


def l_block(cut):
    """An L-block (a 2 x 1 x 1 slab, a unit cube on its left half) cut into two parts."""
    c = penedge.Block.cuboid
    if cut == 0:
        return [c([0, 0, 0], [2, 1, 1]), c([0, 0, 1], [1, 1, 2])]
    return [c([0, 0, 0], [1, 1, 2]), c([1, 0, 0], [2, 1, 1])]


def test_an_l_block_is_one_body_falling_along_a_parabola():
    # The union's centroid from its two boxes (volumes 2 and 1): x = (2 * 1 + 0.5) / 3.
    centroid = np.array([2.5 / 3, 0.5, 2.5 / 3])
    paths = []
    for cut in (0, 1):
        system = penedge.BlockSystem(l_block(cut)).with_bodies([0, 0])
        sim = penedge.Simulation(system, density=DENSITY)
        assert len(sim) == 1
        np.testing.assert_allclose(sim.masses, [3 * DENSITY], rtol=1e-12)
        np.testing.assert_allclose(sim.positions[0], centroid, atol=1e-12)
        sim.set_joint(kn=1.0, ks=1.0, friction=30.0)
        sim.set_timestep(dt=1e-3)
        sim.step(200)
        t = sim.time
        expected = centroid + 0.5 * np.array([0.0, 0.0, -9.81]) * t * t
        np.testing.assert_allclose(sim.positions[0], expected, atol=1e-12)
        paths.append(sim.system().arrays().vertices)
    # Both cuts occupy the same space: the same bounding box of their parts' vertices.
    boxes = [(p.min(axis=0), p.max(axis=0)) for p in paths]
    np.testing.assert_allclose(boxes[0], boxes[1], atol=1e-12)
