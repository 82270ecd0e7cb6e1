"""Defects of the mechanics core found by a tester (2026-11-29), through the Python API: a
bolt anchored in excavated rock, viscous damping past its stable step, a gap of 0, and
blocks overlapping in the input. The verification against formulas is in
crates/penedge/tests/bolts.rs and crates/penedge/tests/mechanics.rs."""

import pytest

import penedge

G = 9.81


def hanging_cube():
    """A fixed ceiling, a free 1 m cube 0.1 m below it held by a bolt from the ceiling's top
    to the cube's centroid, and another fixed block far below."""
    ceiling = penedge.Block.cuboid([-1, -1, 1.1], [1, 1, 2])
    cube = penedge.Block.cuboid([-0.5, -0.5, 0], [0.5, 0.5, 1])
    far = penedge.Block.cuboid([-5, -5, -30], [5, 5, -29])
    sim = penedge.Simulation(penedge.BlockSystem([ceiling, cube, far]), density=2500.0)
    sim.fix([0, 2])
    return sim


def test_a_bolt_in_excavated_rock_stops_holding():
    sim = hanging_cube()
    sim.add_bolt([0, 0, 2], [0, 0, -1], 1.5, stiffness=1e7, capacity=1e5)
    assert sim.solve(ratio=1e-7, max_steps=200_000)["converged"]
    report = sim.excavate([0])
    # The bolt's pull on the cube (its weight) is the load released.
    assert report["loaded"].tolist() == [1]
    assert report["forces"][0] == pytest.approx([0, 0, 2500.0 * G], rel=1e-6)
    assert len(sim.bolts()["pairs"]) == 0
    z0, v = sim.positions[1, 2], sim.velocities[1, 2]
    n = 2000
    sim.step(n)
    dt = sim.timestep
    # The leapfrog's free fall from the half-step velocity v.
    expected = z0 + n * dt * v - 0.5 * G * dt * dt * n * (n + 1)
    assert sim.positions[1, 2] == pytest.approx(expected, abs=1e-9)


def test_a_bolt_into_excavated_rock_is_refused():
    sim = hanging_cube()
    sim.excavate([0])
    with pytest.raises(penedge.MechanicsError, match="excavated body 0") as info:
        sim.add_bolt([0, 0, 2], [0, 0, -1], 1.5, stiffness=1e7, capacity=1e5)
    assert info.value.kind == "bolt"
    # Upwards from the cube into the excavated ceiling.
    with pytest.raises(penedge.MechanicsError, match="body 0, which was excavated"):
        sim.add_bolt([0, 0, 0.5], [0, 0, 1], 1.0, stiffness=1e7, capacity=1e5)


@pytest.mark.parametrize("beta", [2.5e4, 1e5])
def test_viscous_damping_never_makes_a_free_block_gain_energy(beta):
    box = penedge.Block.cuboid([0, 0, 0], [1, 1, 1])
    sim = penedge.Simulation(penedge.BlockSystem([box]), density=2500.0)
    sim.gravity = [0, 0, 0]
    undamped = sim.critical_timestep
    sim.set_damping(viscous=beta)
    # The step reflects the damping: never above 2 / beta, less than before for a large one.
    assert beta * sim.critical_timestep <= 2.0
    assert sim.timestep == pytest.approx(0.5 * sim.critical_timestep, rel=1e-15)
    sim.set_velocity(0, [1.0, 0, 0])
    energy = sim.kinetic_energy()
    for _ in range(50):
        sim.step()
        assert sim.kinetic_energy() <= energy
        energy = sim.kinetic_energy()
    # A step above the damped bound is refused.
    if beta * undamped > 2.5:
        with pytest.raises(penedge.MechanicsError) as info:
            sim.set_timestep(2.5 / beta)
        assert info.value.kind == "time_step"


def test_a_gap_of_zero_is_refused_with_the_reason():
    base = penedge.Block.cuboid([-2, -2, -1], [2, 2, 0])
    cube = penedge.Block.cuboid([-0.5, -0.5, 0], [0.5, 0.5, 1])
    with pytest.raises(penedge.MechanicsError, match="overlapping") as info:
        penedge.Simulation(penedge.BlockSystem([base, cube]), density=2500.0, gap=0.0)
    assert info.value.kind == "parameter"
    assert "(0, 0.01)" in str(info.value)


def test_blocks_overlapping_in_the_input_are_named_so():
    base = penedge.Block.cuboid([-2, -2, -1], [2, 2, 0])
    cube = penedge.Block.cuboid([-0.5, -0.5, -0.2], [0.5, 0.5, 0.8])
    sim = penedge.Simulation(penedge.BlockSystem([base, cube]))
    sim.fix([0])
    with pytest.raises(penedge.MechanicsError) as info:
        sim.step()
    assert info.value.kind == "penetration"
    assert "bodies 0 and 1 overlap in the input by 0.2," in str(info.value)
    assert "contact law" not in str(info.value)
