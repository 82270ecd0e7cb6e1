# The `mechanics` benchmark's model in YADE's Polyhedra DEM (a peer, not a dependency).
#
#   penedge-bench mechanics --blocks N --export model.txt   # writes the blocks and settings
#   OMP_NUM_THREADS=2 yade -n -j2 -x benches/yade/settle.py model.txt
#
# The same blocks (corners read from the file), the same density, gravity, time step and
# local damping (YADE's NewtonIntegrator damping is Cundall's local non-viscous damping, as
# 3DEC's and penedge's). Stiffness: YADE's volumetric law gives Fn = kn_phys * V, with
# kn_phys = E / 2 for two bodies of one material (Ip2_PolyhedraMat_PolyhedraMat_PolyhedraPhys:
# E1 E2 / (E1 + E2)); a face-face overlap of depth d on an area A has V = A d, so E = 2 kn
# gives penedge's Fn = kn A d. The shear stiffness is a force per displacement for the whole
# contact: ks_phys = E nu / 2, so nu = ks / kn gives ks per m² of contact, penedge's ks on
# the unit faces of this model. Friction angle the same; no cohesion (as the model).
#
# Settled: the same criterion as penedge's `solve`, the largest unbalanced force of a free
# block (contact forces plus weight) over the largest weight, below the model's ratio. It is
# computed in Python by a PyRunner every CHECK steps (default 10; the run may thus go up to
# CHECK - 1 steps past the point), and its own time is measured and reported apart.
#
# With a `speed` above 0 in the model (penedge-bench mechanics --speed V --export ...), the run
# also stops, as settled, at the first check at which the fastest free block is slower than
# `speed` (m/s) after one has been faster than `moving`: the physical criterion for the time to
# the same settled state (penedge checks it every step, this script every CHECK steps).
#
# Prints one line `RESULT key=value ...` with: bodies, free, steps, converged, ratio, wall_s,
# check_s (the criterion's own time), cpu_s (CPU time of the process, all threads, while
# stepping, the criterion's taken out) and block_steps_per_cpu_s (the figure that the load of
# a shared machine distorts least), block_steps_per_s (all bodies, criterion time taken
# out), moving_steps and block_steps_per_s_moving (over the check intervals that began with a
# free block faster than the model's `moving` speed), settlement_mm (mean settlement of the
# free blocks), contacts (real interactions at the end), settled_by (ratio or speed),
# fastest_mps (the fastest free block at the end), kinetic_j (kinetic energy of the free
# blocks, translation and rotation) and simulated_s.

import math
import os
import sys
import time
from pathlib import Path

from yade import O, Vector3, log, polyhedra_utils
from yade.wrapper import (
    Bo1_Polyhedra_Aabb,
    ForceResetter,
    Ig2_Polyhedra_Polyhedra_PolyhedraGeom,
    InsertionSortCollider,
    InteractionLoop,
    Ip2_PolyhedraMat_PolyhedraMat_PolyhedraPhys,
    Law2_PolyhedraGeom_PolyhedraPhys_Volumetric,
    NewtonIntegrator,
    PolyhedraMat,
    PyRunner,
)

CHECK = int(os.environ.get("CHECK", "10"))
MAX_STEPS = int(os.environ.get("MAX_STEPS", "100000"))
# Bounding boxes widened by this much (m; YADE sets 0 for non-spheres, colliding every step):
# penedge widens by half its skin of 0.05 block sizes.
VERLET = float(os.environ.get("VERLET", "0.025"))


def read_model(path):
    settings, blocks = {}, []
    with Path(path).open() as f:
        for line in f:
            words = line.split()
            if not words:
                continue
            if words[0] in ("0", "1"):
                xyz = [float(w) for w in words[1:]]
                corners = [Vector3(*xyz[i : i + 3]) for i in range(0, len(xyz), 3)]
                blocks.append((words[0] == "1", corners))
            else:
                settings[words[0]] = " ".join(words[1:])
    if len(blocks) != int(settings["blocks"]):
        raise SystemExit(f"{path}: {len(blocks)} blocks, the header says {settings['blocks']}")
    return settings, blocks


def main():
    # Its intersection code warns "Unhandled switch case" for every pair of boxes that
    # overlap without the polyhedra overlapping (1,500 lines a step for 180 blocks): printing
    # them cost more wall time than the steps. Silenced; counted in no figure.
    log.setLevel("Polyhedra_support.cpp", log.ERROR)
    if len(sys.argv) < 2:
        raise SystemExit("usage: yade -n -j2 -x settle.py MODEL.txt")
    settings, blocks = read_model(sys.argv[1])
    kn, ks = float(settings["kn"]), float(settings["ks"])
    g = float(settings["gravity"])
    target = float(settings["ratio"])
    moving_speed = float(settings["moving"])
    settled_speed = float(settings.get("speed", "0"))
    mat = PolyhedraMat(
        density=float(settings["density"]),
        young=2.0 * kn,
        poisson=ks / kn,
        frictionAngle=math.radians(float(settings["friction_deg"])),
    )
    O.materials.append(mat)
    ids = [O.bodies.append(polyhedra_utils.polyhedra(mat, v=v, fixed=fixed)) for fixed, v in blocks]
    free = [i for i, (fixed, _) in zip(ids, blocks, strict=True) if not fixed]
    O.engines = [
        ForceResetter(),
        InsertionSortCollider([Bo1_Polyhedra_Aabb()], verletDist=VERLET),
        InteractionLoop(
            [Ig2_Polyhedra_Polyhedra_PolyhedraGeom()],
            [Ip2_PolyhedraMat_PolyhedraMat_PolyhedraPhys()],
            [Law2_PolyhedraGeom_PolyhedraPhys_Volumetric()],
        ),
        NewtonIntegrator(damping=float(settings["local_damping"]), gravity=(0, 0, -g)),
    ]
    O.dt = float(settings["dt"])
    weight = {i: O.bodies[i].state.mass * g for i in free}
    reference = max(weight.values())
    z0 = {i: O.bodies[i].state.pos[2] for i in free}

    def ratio_and_speed():
        largest, fastest = 0.0, 0.0
        for i in free:
            f = O.forces.f(i)
            largest = max(largest, (f + Vector3(0, 0, -weight[i])).norm())
            fastest = max(fastest, O.bodies[i].state.vel.norm())
        return largest / reference, fastest

    state = {"ratio": math.inf, "converged": False, "check_s": 0.0, "moving": True}
    state["check_cpu_s"] = 0.0
    state.update(moving_steps=0, moving_s=0.0, last_t=None, last_iter=0)
    state.update(moved=False, settled_by="-", fastest=math.inf)

    def check():
        """Every CHECK steps, after the integrator (this step's forces are still summed)."""
        t, cpu_t = time.perf_counter(), time.process_time()
        if state["moving"] and state["last_t"] is not None:
            state["moving_steps"] += O.iter - state["last_iter"]
            state["moving_s"] += t - state["last_t"]
        ratio, fastest = ratio_and_speed()
        state["ratio"], state["moving"] = ratio, fastest > moving_speed
        state["moved"] = state["moved"] or state["moving"]
        state["fastest"] = fastest
        if ratio < target:
            state["converged"], state["settled_by"] = True, "ratio"
        elif settled_speed > 0 and state["moved"] and fastest < settled_speed:
            state["converged"], state["settled_by"] = True, "speed"
        done = time.perf_counter()
        state["check_s"] += done - t
        state["check_cpu_s"] += time.process_time() - cpu_t
        state["last_t"], state["last_iter"] = done, O.iter

    O.engines = [*O.engines, PyRunner(command="check()", iterPeriod=CHECK)]
    globals()["check"] = check
    start, cpu_start = time.perf_counter(), time.process_time()
    state["last_t"] = start
    # O.step() in the main thread: O.run(n, True) runs in a background thread that the
    # shared, loaded machine starved (wall time 6x its CPU time in a first try).
    while O.iter < MAX_STEPS and not state["converged"]:
        O.step()
    steps = O.iter
    ratio, converged, check_s = state["ratio"], state["converged"], state["check_s"]
    moving_steps, moving_s = state["moving_steps"], state["moving_s"]
    wall = time.perf_counter() - start
    cpu = time.process_time() - cpu_start - state["check_cpu_s"]
    settlement = sum(z0[i] - O.bodies[i].state.pos[2] for i in free) / len(free)
    contacts = O.interactions.countReal()
    kinetic = sum(
        0.5 * O.bodies[i].state.mass * O.bodies[i].state.vel.squaredNorm()
        + 0.5 * O.bodies[i].state.angVel.dot(O.bodies[i].state.angMom)
        for i in free
    )
    bodies = len(ids)
    result = {
        "bodies": bodies,
        "free": len(free),
        "steps": steps,
        "converged": converged,
        "ratio": f"{ratio:.3e}",
        "wall_s": f"{wall:.2f}",
        "check_s": f"{check_s:.2f}",
        "cpu_s": f"{cpu:.2f}",
        "block_steps_per_cpu_s": f"{bodies * steps / cpu:.3e}",
        "block_steps_per_s": f"{bodies * steps / (wall - check_s):.3e}",
        "moving_steps": moving_steps,
        "block_steps_per_s_moving": f"{bodies * moving_steps / moving_s:.3e}" if moving_s else "-",
        "settlement_mm": f"{settlement * 1e3:.4f}",
        "contacts": contacts,
        "settled_by": state["settled_by"],
        "fastest_mps": f"{state['fastest']:.3e}",
        "kinetic_j": f"{kinetic:.3e}",
        "simulated_s": f"{O.time:.4f}",
        "threads": os.environ.get("OMP_NUM_THREADS", "?"),
    }
    print("RESULT " + " ".join(f"{k}={v}" for k, v in result.items()), flush=True)


main()
O.exitNoBacktrace() if hasattr(O, "exitNoBacktrace") else sys.exit(0)
