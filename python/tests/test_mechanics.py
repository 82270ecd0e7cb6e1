"""penedge.Simulation: the rigid-block mechanics through Python (the verification against
analytic solutions is in crates/penedge/tests/mechanics.rs; here the API: arrays, settings,
errors, and two checks against formulas)."""

import math
import os
import signal
import threading
import time

import numpy as np
import pytest

import penedge

G = 9.81


def cube_on_base(density=2500.0, kn=1e9):
    base = penedge.Block.cuboid([-2, -2, -1], [2, 2, 0])
    cube = penedge.Block.cuboid([-0.5, -0.5, 0], [0.5, 0.5, 1])
    sim = penedge.Simulation(penedge.BlockSystem([base, cube]), density=density)
    sim.fix([0])
    sim.set_joint(kn=kn, ks=kn, friction=30.0)
    return sim


def test_a_cube_settles_by_its_weight_over_the_contact_stiffness():
    sim = cube_on_base()
    report = sim.solve()
    assert report["converged"]
    assert report["ratio"] < 1e-5
    # Sunk by m g / (kn A): 2500 * 9.81 / 1e9.
    assert sim.positions[1, 2] == pytest.approx(0.5 - 2500 * G / 1e9, abs=1e-9)
    assert sim.positions[0] == pytest.approx([0.0, 0.0, -0.5], abs=1e-12)
    c = sim.contacts()
    assert c["pairs"].tolist() == [[0, 1]]
    assert c["types"].tolist() == [penedge.FACE_FACE]
    assert c["sub_offsets"].tolist() == [0, 4]
    assert c["areas"].sum() == pytest.approx(1.0)
    # The contact carries the weight, on B (the cube) upwards.
    assert c["normal_forces"].sum() == pytest.approx(2500 * G, rel=1e-5)
    assert sim.contact_forces[1] == pytest.approx([0, 0, 2500 * G], rel=1e-5, abs=1e-6)
    assert set(c["states"].tolist()) == {0}
    assert c["points"].shape == (4, 3)
    assert c["shear_forces"].shape == (4, 3)


def test_state_arrays_have_one_row_per_body_and_are_read_only():
    sim = cube_on_base()
    sim.step(3)
    assert len(sim) == 2
    assert sim.steps == 3
    assert sim.time == pytest.approx(3 * sim.timestep)
    for name, width in [("positions", 3), ("quaternions", 4), ("velocities", 3), ("spins", 3)]:
        array = getattr(sim, name)
        assert array.shape == (2, width), name
        with pytest.raises(ValueError, match="read-only"):
            array[0, 0] = 1.0
    assert np.linalg.norm(sim.quaternions, axis=1) == pytest.approx([1, 1])
    assert sim.masses.tolist() == pytest.approx([16 * 2500, 2500])
    assert sim.inertia[1] == pytest.approx([2500 / 6] * 3)
    assert sim.fixed.tolist() == [True, False]
    assert len(sim.system()) == 2


def test_free_fall_is_a_parabola():
    block = penedge.Block.cuboid([0, 0, 0], [1, 2, 3])
    sim = penedge.Simulation(penedge.BlockSystem([block]), density=1000.0)
    sim.set_joint(kn=1.0, ks=1.0, friction=30.0)  # no contact: only the time step bound
    sim.set_timestep(1e-3)
    sim.set_velocity(0, [1.0, 0.0, 2.0])
    x0 = sim.positions[0].copy()
    sim.step(500)
    t = sim.time
    expected = x0 + np.array([1.0, 0.0, 2.0]) * t + 0.5 * np.array([0, 0, -G]) * t * t
    assert sim.positions[0] == pytest.approx(expected, abs=1e-12)


def test_a_block_slides_on_a_slope_steeper_than_friction():
    theta, phi = math.radians(40.0), 30.0
    rot = np.array(
        [[1, 0, 0], [0, math.cos(theta), -math.sin(theta)], [0, math.sin(theta), math.cos(theta)]]
    )
    base = penedge.Block.cuboid([-5, -5, -1], [5, 5, 0])
    # In normal equilibrium from the start: sunk by m g cos θ / (kn A).
    sink = 2500 * 0.3 * G * math.cos(theta) / 1e8
    slab = penedge.Block.cuboid([-0.5, -0.4, -sink], [0.5, 0.4, 0.3 - sink])
    tilt = [penedge.Block(b.vertices @ rot.T, b.faces) for b in (base, slab)]
    sim = penedge.Simulation(penedge.BlockSystem(tilt), density=2500.0)
    sim.fix([0])
    sim.set_joint(kn=1e8, ks=1e8, friction=phi)
    sim.run_until(0.05)  # past the release's elastic transient (see mechanics.rs)
    before = sim.velocities[1].copy()
    sim.step()
    v1 = (before + sim.velocities[1]) / 2
    x1, t1 = sim.positions[1].copy(), sim.time
    sim.run_until(0.4)
    a = G * (math.sin(theta) - math.cos(theta) * math.tan(math.radians(phi)))
    down = rot @ np.array([0.0, -1.0, 0.0])
    t = sim.time - t1
    moved = (sim.positions[1] - x1) @ down
    assert moved == pytest.approx(v1 @ down * t + 0.5 * a * t * t, rel=0.01)


def sliced_box(planes=5):
    """A box cut by `planes` vertical planes: a system whose joint sets are 0 .. planes - 1
    (each plane its own spec entry)."""
    normals = [[1.0, 0.0, 0.0]] * planes
    offsets = [(k + 1) / (planes + 1) for k in range(planes)]
    system = penedge.BlockSystem.from_box_cut([0, 0, 0], [1, 1, 1], normals, offsets)
    sim = penedge.Simulation(system)
    sim.set_joint(kn=1e9, ks=1e9, friction=30.0)
    return sim


def test_joint_properties_per_set_and_default():
    sim = sliced_box()
    sim.set_joint(kn=2e9, ks=1e9, friction=35.0, cohesion=1e5, tension=5e4, set=3)
    assert sim.joint(set=3) == {
        "kn": 2e9,
        "ks": 1e9,
        "friction": 35.0,
        "cohesion": 1e5,
        "tension": 5e4,
        "residual_friction": 35.0,  # the friction angle unless given
        "residual_cohesion": 0.0,
    }
    sim.set_joint(kn=2e9, ks=1e9, friction=35.0, set=4, residual_friction=25.0, residual_cohesion=1)
    assert (sim.joint(set=4)["residual_friction"], sim.joint(set=4)["residual_cohesion"]) == (25, 1)
    with pytest.raises(penedge.MechanicsError, match="residual_friction"):
        sim.set_joint(kn=1e9, ks=1e9, friction=30.0, residual_friction=95.0)
    assert sim.joint()["kn"] == 1e9
    assert sim.joint(set=2)["kn"] == 1e9  # a set without its own: the default
    sim.set_damping(local=0.7)
    assert sim.damping == (0.7, 0.0)
    sim.gravity = [0.0, 0.0, -1.0]
    assert sim.gravity.tolist() == [0.0, 0.0, -1.0]


@pytest.mark.parametrize(
    ("call", "kind"),
    [
        (lambda s: s.set_joint(kn=0.0, ks=1.0, friction=30.0), "stiffness"),
        (lambda s: s.set_joint(kn=1.0, ks=-1.0, friction=30.0), "stiffness"),
        (lambda s: s.set_joint(kn=1.0, ks=1.0, friction=90.0), "friction"),
        (lambda s: s.set_joint(kn=1.0, ks=1.0, friction=30.0, cohesion=-1.0), "strength"),
        (lambda s: s.set_timestep(1.0), "time_step"),
        (lambda s: s.set_damping(local=1.0), "damping"),
        (lambda s: s.set_density(-1.0), "density"),
        (lambda s: s.fix([5]), "unknown_body"),
        (lambda s: setattr(s, "gravity", [math.nan, 0, 0]), "not_finite"),
        (lambda s: (s.fix([1]), s.step()), "no_free_body"),
    ],
)
def test_bad_input_raises_a_mechanics_error(call, kind):
    sim = cube_on_base()
    with pytest.raises(penedge.MechanicsError) as info:
        call(sim)
    assert info.value.kind == kind
    assert isinstance(info.value, ValueError)


def test_a_fixed_block_stays_put_and_falls_freely_once_freed():
    base = penedge.Block.cuboid([-4, -2, -1], [4, 2, 0])
    held = penedge.Block.cuboid([-3, -0.5, 0.5], [-2, 0.5, 1.5])  # 0.5 m above the base
    resting = penedge.Block.cuboid([1, -0.5, 0], [2, 0.5, 1])
    sim = penedge.Simulation(penedge.BlockSystem([base, held, resting]), density=2500.0)
    sim.set_joint(kn=1e9, ks=1e9, friction=30.0)
    sim.fix([0, 1])
    base_at, start = sim.positions[0].copy(), sim.positions[1].copy()
    sim.step(50)
    assert sim.positions[1].tolist() == start.tolist()
    assert sim.velocities[1].tolist() == [0.0, 0.0, 0.0]
    assert sim.fixed.tolist() == [True, True, False]
    sim.free([1])
    assert sim.fixed.tolist() == [True, False, False]
    # Freed at rest at that time, it falls as x0 - g t^2 / 2 from then (central difference
    # started with a half kick is exact on a parabola), and nothing touches it on the way
    # (0.1 m down); its velocity is the leapfrog's, at the half step before the last pose.
    dt = sim.timestep
    steps = int(math.sqrt(2 * 0.1 / G) / dt)
    sim.step(steps)
    t = steps * dt
    assert sim.positions[1] == pytest.approx(start - np.array([0, 0, 0.5 * G * t * t]), abs=1e-12)
    assert sim.velocities[1] == pytest.approx([0, 0, -G * (t - dt / 2)], abs=1e-12)
    assert sim.positions[0].tolist() == base_at.tolist()


def test_overlapping_bodies_stop_the_run_with_the_pair_named():
    base = penedge.Block.cuboid([-2, -2, -1], [2, 2, 0])
    cube = penedge.Block.cuboid([-0.5, -0.5, -0.2], [0.5, 0.5, 0.8])
    sim = penedge.Simulation(penedge.BlockSystem([base, cube]), density=2500.0)
    sim.fix([0])
    with pytest.raises(penedge.MechanicsError, match="bodies 0 and 1") as info:
        sim.step()
    assert info.value.kind == "penetration"


def test_mass_scaling_raises_the_time_step_of_slivers():
    base = penedge.Block.cuboid([-3, -3, -1], [3, 3, 0])
    cube = penedge.Block.cuboid([-2, -0.5, 0], [-1, 0.5, 1])
    sliver = penedge.Block.cuboid([0.5, -0.5, 0], [1.5, 0.5, 0.02])
    sim = penedge.Simulation(penedge.BlockSystem([base, cube, sliver]), density=2500.0)
    sim.fix([0])
    sim.set_joint(kn=1e9, ks=1e9, friction=30.0)
    plain = sim.timestep
    sim.set_mass_scaling(True)
    assert sim.timestep > 2 * plain
    assert sim.solve(ratio=1e-6)["converged"]
    assert sim.positions[2, 2] == pytest.approx(0.01 - 2500 * G * 0.02 / 1e9, abs=1e-9)


def test_a_copy_runs_on_its_own():
    sim = cube_on_base()
    sim.step(10)
    trial = sim.copy()
    trial.set_joint(kn=1e9, ks=1e9, friction=10.0)
    trial.step(20)
    assert trial.steps == 30
    assert sim.steps == 10
    assert sim.joint()["friction"] == 30.0
    sim.step(20)
    # Same state, same steps: the same motion.
    assert sim.positions.tolist() == trial.positions.tolist()


def test_water_below_a_table_lifts_the_cube_by_the_water_force():
    """A water table 2 m above the base: the pressure on the cube's base, 9810 x 2 Pa over
    1 m2, carries part of the weight; the joint closes by (m g - U) / (kn A) only."""
    sim = cube_on_base()
    sim.set_water(level=2.0)
    assert sim.solve()["converged"]
    weight, uplift = 2500.0 * 9.81, 9810.0 * 2.0
    assert 0.5 - sim.positions[1, 2] == pytest.approx((weight - uplift) / 1e9, rel=1e-3)
    # The joint carries the effective force only.
    contacts = sim.contacts()
    assert contacts["normal_forces"].sum() == pytest.approx(weight - uplift, rel=1e-3)
    # The water force of the one face-face contact: the pressure at the base times its area.
    assert contacts["water_forces"] == pytest.approx([9810.0 * (2.0 - contacts["points"][0, 2])])


def test_water_lifts_a_light_cube_off_its_joint_and_keeps_pushing_it():
    """A cube lighter than the water it displaces (density 300) on a fixed base under a
    table 3 m above the joint: U = 9810 x 2 x 1 m2 > W, the joint opens, and past the
    detection gap it is an opened joint that keeps its water (docs/mechanics.md, "Opened
    joints"): undamped, the cube rises by (U - W) t^2 / (2 m) while the faces face each
    other (here, up to a block size), no contact left."""
    sim = cube_on_base(density=300.0)
    sim.set_water(level=3.0)
    base = sim.positions[1, 2]
    while sim.time < 0.06:
        sim.step()
    mass = 300.0 * 1.0
    uplift, weight = 9810.0 * (3.0 - 0.0), mass * 9.81
    opened = sim.opened_joints()
    assert sim.contacts()["pairs"].shape == (0, 2)
    assert opened["pairs"].tolist() == [[0, 1]]
    assert opened["water_forces"] == pytest.approx([uplift], rel=1e-12)
    assert opened["normals"][0] == pytest.approx([0.0, 0.0, 1.0])
    assert opened["centres"][0] == pytest.approx([0.0, 0.0, 0.0], abs=1e-12)
    rise = sim.positions[1, 2] - base
    assert rise == pytest.approx((uplift - weight) / mass * sim.time**2 / 2, rel=0.01)


def crack_behind_a_block():
    """A fixed base and back rock, and a free 1 x 1 x 3 m block in front of the back rock
    (the crack at x = 1), under a water table at its top; a small free cube on the base
    away from them."""
    base = penedge.Block.cuboid([-1, 0, -1], [4, 1, 0])
    back = penedge.Block.cuboid([-1, 0, 0], [1, 1, 3])
    block = penedge.Block.cuboid([1, 0, 0], [2, 1, 3])
    cube = penedge.Block.cuboid([3.2, 0, 0], [3.7, 0.5, 0.5])
    sim = penedge.Simulation(penedge.BlockSystem([base, back, block, cube]), density=2500.0)
    sim.fix([0, 1])
    sim.set_joint(kn=1e9, ks=1e9, friction=30.0)
    sim.set_water(level=3.0)
    return sim


def test_a_crack_opening_about_a_hinge_keeps_its_water():
    """The block turned away from the back rock about its toe (a V-shaped crack, as behind a
    toppling block): the pair keeps an edge contact at the hinge, and the crack its water,
    whether the pair's contact is a face-face one (its polygon's water) or not (the opened
    joint's). When it went with the face-face contact, the water was 0 from 0.01 rad on."""
    sim = crack_behind_a_block()
    w = 0.02  # rad/s about y, through the toe (1, 0, 0): velocity of the centroid
    seen = set()
    while sim.time < 1.0:
        sim.set_velocity(2, [1.5 * w, 0, 0.5 * w], [0, w, 0])
        sim.step()
        contacts, opened = sim.contacts(), sim.opened_joints()
        crack = [k for k, p in enumerate(contacts["pairs"].tolist()) if p == [1, 2]]
        kind = int(contacts["types"][crack[0]]) if crack else 0
        water = sum(contacts["water_forces"][k] for k in crack) + sum(
            u
            for p, u in zip(opened["pairs"].tolist(), opened["water_forces"], strict=True)
            if p == [1, 2]
        )
        seen.add(kind)
        assert water > 0.0, (sim.time, kind)
    # It went through a face-face contact and an edge contact (or none) at the hinge.
    assert 7 in seen
    assert seen - {7}


def test_no_opened_joint_between_bodies_that_do_not_move():
    """A wet crack whose block is fixed after a step: the pair is no candidate pair any more
    (no contact between two fixed bodies), but its faces touch: no opened joint, and no
    water force left on the fixed bodies."""
    sim = crack_behind_a_block()
    sim.step()
    assert sim.contacts()["water_forces"].max() > 0.0
    sim.fix([2])
    sim.step(2)
    assert sim.opened_joints()["pairs"].shape == (0, 2)
    # The back rock touches only the (now fixed) block.
    assert sim.contact_forces[1].tolist() == [0.0] * 3


def test_a_loaded_simulation_reports_its_opened_joints(tmp_path):
    """The opened joints' forces, not kept in restart files, are computed again on
    reading: the same as before saving."""
    sim = cube_on_base(density=300.0)
    sim.set_water(level=3.0)
    while sim.time < 0.03:
        sim.step()
    before = sim.opened_joints()
    assert before["water_forces"].tolist() == pytest.approx([9810.0 * 3.0])
    path = tmp_path / "opened.json"
    sim.save(path)
    after = penedge.Simulation.load(path)
    for key in ("pairs", "sets", "water_forces", "normals", "centres"):
        assert after.opened_joints()[key].tolist() == before[key].tolist(), key


def test_a_set_the_system_does_not_have_is_refused_with_the_sets_it_has():
    # a typo in a set id must not silently leave the set's contacts at the default properties
    sim = sliced_box(planes=2)
    bridge = dict(kn=1e9, ks=1e9, friction=45.0, cohesion=1e6, tension=1e5)
    for give in [
        lambda s: sim.set_joint(kn=1e9, ks=1e9, friction=30.0, set=s),
        lambda s: sim.set_bridge(**bridge, set=s),
        lambda s: sim.set_water(pressures={s: 1e4}),
    ]:
        give(1)  # the system's sets are accepted
        with pytest.raises(penedge.MechanicsError, match=r"no joint set 2\b.*sets are 0, 1") as e:
            give(2)
        assert e.value.kind == "unknown_set"
    assert sim.joint(set=1)["friction"] == 30.0
    # blocks of no joint have no set at all; the default properties are still theirs to set
    sim = cube_on_base()
    with pytest.raises(penedge.MechanicsError, match=r"no joint set 0: .*no joint sets"):
        sim.set_joint(kn=1e9, ks=1e9, friction=30.0, set=0)
    sim.set_joint(kn=2e9, ks=2e9, friction=30.0)
    assert sim.joint()["kn"] == 2e9


def test_a_restart_file_keeps_a_set_that_cut_no_block(tmp_path):
    # the second plane lies outside the box: its spec entry is a set without faces
    system = penedge.BlockSystem.from_box_cut(
        [0, 0, 0], [1, 1, 1], [[1.0, 0.0, 0.0]] * 2, [0.5, 2.0]
    )
    assert len(system) == 2
    sim = penedge.Simulation(system)
    sim.set_joint(kn=1e9, ks=1e9, friction=30.0)  # the default only: set 1 has no properties
    sim.save(tmp_path / "state.json")
    loaded = penedge.Simulation.load(tmp_path / "state.json")
    loaded.set_joint(kn=1e9, ks=1e9, friction=25.0, set=1)
    loaded.set_water(pressures={1: 1e4})
    assert loaded.joint(set=1)["friction"] == 25.0
    with pytest.raises(penedge.MechanicsError, match=r"no joint set 2\b.*sets are 0, 1"):
        loaded.set_joint(kn=1e9, ks=1e9, friction=30.0, set=2)


def test_bad_water_is_refused_by_name():
    sim = cube_on_base()
    with pytest.raises(penedge.MechanicsError, match="vertical"):
        sim.set_water(point=[0, 0, 0], normal=[1, 0, 0])
    with pytest.raises(penedge.MechanicsError, match="water pressure"):
        sliced_box(planes=1).set_water(pressures={0: -1.0})
    with pytest.raises(penedge.MechanicsError, match="unit_weight"):
        sim.set_water(level=1.0, unit_weight=0.0)
    with pytest.raises(ValueError, match="level"):
        sim.set_water(level=1.0, point=[0, 0, 0], normal=[0, 0, 1])


def test_the_update_fraction_carries_touching_pairs_only_when_asked():
    exact, fast = cube_on_base(), cube_on_base()
    assert exact.update_fraction == 0.0  # the default: every touching pair queried
    fast.set_update_fraction(0.5)
    assert fast.update_fraction == 0.5
    for sim in (exact, fast):
        sim.step(200)
    assert exact.timings()["carried"] == 0
    assert fast.timings()["carried"] > 0
    # Carried with the bodies, the contact keeps the settling within the tolerance: the cube
    # ends where the exact run puts it, to well below the 1e-3 gap.
    assert fast.positions[1] == pytest.approx(exact.positions[1], abs=1e-6)
    with pytest.raises(penedge.MechanicsError, match="update fraction"):
        fast.set_update_fraction(-1.0)


def test_dormant_contacts_keep_the_motion_and_skip_open_contacts():
    """A cube falling onto its base from 0.6 mm, carried: while the contact is open (within
    the 1.73 mm detection gap, no force) it is dormant; the motion is the same, bit for bit,
    as with every open contact updated."""
    runs = []
    for dormant in (True, False):
        base = penedge.Block.cuboid([-2, -2, -1], [2, 2, 0])
        cube = penedge.Block.cuboid([-0.5, -0.5, 0.0006], [0.5, 0.5, 1.0006])
        sim = penedge.Simulation(penedge.BlockSystem([base, cube]))
        sim.fix([0])
        sim.set_update_fraction(0.1)
        assert sim.dormant_contacts  # the default
        sim.dormant_contacts = dormant
        assert sim.dormant_contacts == dormant
        sim.step(400)
        runs.append(sim)
    on, off = runs
    assert on.timings()["dormant"] > 0
    assert off.timings()["dormant"] == 0
    assert on.timings()["carried"] == off.timings()["carried"]
    # Same bits: the cube lands at the same step, at the same place and speed.
    assert on.positions.tobytes() == off.positions.tobytes()
    assert on.velocities.tobytes() == off.velocities.tobytes()
    assert on.contacts()["normal_forces"].tobytes() == off.contacts()["normal_forces"].tobytes()


# -- Ctrl-C during a long run -----------------------------------------------------------------


def falling_cube():
    """One free cube falling without contacts: steps never converge and cost little."""
    cube = penedge.Block.cuboid([0, 0, 0], [1, 1, 1])
    return penedge.Simulation(penedge.BlockSystem([cube]))


LONG = 10**7  # steps: far more than the 0.2 s before the signal takes (minutes without a check)


@pytest.mark.parametrize(
    ("run", "steps"),  # the long run; `k` steps of it at once
    [
        (lambda sim: sim.step(LONG), lambda sim, k: sim.step(k)),
        (lambda sim: sim.run_until(LONG * sim.timestep), lambda sim, k: sim.step(k)),
        (
            lambda sim: sim.solve(ratio=1e-5, max_steps=LONG),
            lambda sim, k: sim.solve(ratio=1e-5, max_steps=k),
        ),
    ],
    ids=["step", "run_until", "solve"],
)
def test_ctrl_c_stops_a_long_run_after_a_whole_step(run, steps):
    # The runs release the GIL; they must still look for signals between chunks of steps,
    # or Ctrl-C waits for the whole run.
    if not hasattr(signal, "SIGINT") or threading.current_thread() is not threading.main_thread():
        pytest.skip("SIGINT cannot be delivered to the main thread here")
    sim = falling_cube()

    def run_then_wait():
        run(sim)
        time.sleep(5)  # without the check, the signal would be handled only here

    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    timer = threading.Timer(0.2, os.kill, (os.getpid(), signal.SIGINT))
    try:
        timer.start()
        with pytest.raises(KeyboardInterrupt):
            run_then_wait()
    finally:
        timer.cancel()
        signal.signal(signal.SIGINT, previous)
    taken = sim.steps
    assert 0 < taken < LONG  # interrupted mid-run
    assert sim.damping == (0.0, 0.0)  # solve's 0.8 set back
    # whole steps: the state is that of the same steps taken at once, bit for bit, and the
    # run goes on from it
    again = falling_cube()
    steps(again, taken)
    assert again.time == sim.time
    assert np.array_equal(again.positions, sim.positions)
    assert np.array_equal(again.velocities, sim.velocities)
    sim.step(2)
    assert sim.steps == taken + 2
