"""The one module that calls the mechanics engine (``penedge.Simulation``, the rigid-block
DEM of docs/mechanics.md): everything else (stages, factor of safety, outputs) talks to an
:class:`Engine`, so a change of the engine's API changes this file only.

An :class:`Engine` is built from a checked :class:`~penedge.model.Setup`; it refuses, before
any step, what the engine cannot do yet (:func:`unsupported`).
"""

from __future__ import annotations

import copy
from typing import Any

import numpy as np

from penedge.model.fields import ModelError
from penedge.model.schema import JointProperties, Model


class EngineMissingError(Exception):
    """This build of penedge has no mechanics engine (``penedge.Simulation``)."""


def simulation_class() -> Any:
    """``penedge.Simulation``, or :exc:`EngineMissingError`."""
    import penedge

    simulation = getattr(penedge, "Simulation", None)
    if simulation is None:
        raise EngineMissingError(
            "this build of penedge has no mechanics engine (penedge.Simulation, the "
            "rigid-block DEM): the model was read and checked, but it cannot be run"
        )
    return simulation


#: Model features that the engine does not run yet: (field, why). A model using one of
#: them is read and checked, and its run refused with this message before any step.
NOT_SUPPORTED = {
    "initial_stress": "initial stresses are not supported yet by the engine",
    "water": "water pressure in the joints is not supported yet by the engine",
    "bolts": "rock bolts are not supported yet by the engine",
    "excavate": "excavation is not supported yet by the engine",
    "residual": "residual values other than the defaults (residual_friction = friction, "
    "residual cohesion and tension 0) are not supported yet by the engine",
}


def has_residual(props: JointProperties) -> bool:
    """Whether `props` has residual values other than the engine's (friction unchanged,
    cohesion and tension lost)."""
    residual = props.friction if props.residual_friction is None else props.residual_friction
    return residual != props.friction or bool(props.residual_cohesion or props.residual_tension)


def unsupported(model: Model) -> list[tuple[str, str]]:
    """The features of `model` the engine cannot run: ``(field, message)`` pairs."""
    found = []
    if model.initial_stress is not None:
        found.append(("initial_stress", NOT_SUPPORTED["initial_stress"]))
    if model.water is not None:
        found.append(("water", NOT_SUPPORTED["water"]))
    if model.bolts:
        found.append(("bolts", NOT_SUPPORTED["bolts"]))
    for i, stage in enumerate(model.stages):
        if stage.kind == "excavate":
            found.append((f"stages[{i}]", NOT_SUPPORTED["excavate"]))
        if stage.kind == "properties" and any(k.startswith("residual_") for k in stage.changes):
            found.append((f"stages[{i}]", NOT_SUPPORTED["residual"]))
    named = {"default": model.default_properties, **model.properties}
    for name, props in named.items():
        if has_residual(props):
            found.append((f"joint_properties.{name}", NOT_SUPPORTED["residual"]))
            break
    return found


def refuse_unsupported(model: Model) -> None:
    """Raises a :exc:`ModelError` for the first feature the engine cannot run."""
    for field, message in unsupported(model):
        raise ModelError(field, message)


class Engine:
    """A simulation of a checked model: the engine set up with the model's density,
    gravity (with the seismic load), damping, joint properties per set and boundary
    conditions.

    Parameters
    ----------
    setup : penedge.model.Setup
        The model with its blocks.
    """

    def __init__(self, setup: Any) -> None:
        refuse_unsupported(setup.model)
        simulation = simulation_class()
        model = setup.model
        m = model.mechanics
        self.setup = setup
        self.sim = simulation(setup.system, density=m.density, gap=m.gap, point_width=m.point_width)
        if len(self.sim) != len(setup.system):
            # A concave block is one body of several blocks: the masks below go per block.
            raise ModelError(
                "blocks",
                "concave blocks (blocks of several parts) are not supported yet by the "
                "model's boundary conditions, which are set per block",
            )
        self.sim.gravity = list(model.gravity)
        self.sim.set_damping(local=m.damping)
        self.set_ids = {name: i for i, name in enumerate(model.set_names)}
        self.properties = dict(model.properties)
        self.default = model.default_properties
        self.apply_properties(self.properties)
        layout = setup.layout
        self.apply_boundary(layout.fixed, layout.velocity)
        if m.time_step is not None:
            self.sim.set_timestep(dt=m.time_step)  # checked against the critical step
        if layout.support_forces is not None:
            self.apply_support(layout.support_forces, layout.support_moments)

    def apply_support(self, forces: np.ndarray, moments: np.ndarray | None) -> None:
        """The support pressures as constant forces on the blocks' centroids. The engine
        takes no applied moment yet: a pressure whose resultant is off the centroid is
        refused (a face centred on its block, or symmetric faces, have none)."""
        scale = float(np.abs(forces).max()) * self.setup.blocks.size
        if moments is not None and np.abs(moments).max() > 1e-9 * scale:
            raise ModelError(
                "support",
                "a support pressure whose resultant misses a block's centroid (a moment) is "
                "not supported yet by the engine",
            )
        for i in np.flatnonzero(np.abs(forces).sum(axis=1)):
            self.sim.apply_force(int(i), forces[i].tolist())

    # --- set-up ---------------------------------------------------------------------

    def joint(self, props: JointProperties) -> dict[str, float]:
        """The engine's joint model of `props`."""
        if has_residual(props):
            raise ModelError("joint_properties", NOT_SUPPORTED["residual"])
        return {
            "kn": props.kn,
            "ks": props.ks,
            "friction": props.friction,
            "cohesion": props.cohesion,
            "tension": props.tension,
        }

    def apply_properties(self, properties: dict[str, JointProperties]) -> None:
        """Joint properties per set name (the default stays for contacts of no set)."""
        self.sim.set_joint(**self.joint(self.default), set=None)
        for name, props in properties.items():
            self.properties[name] = props
            self.sim.set_joint(**self.joint(props), set=self.set_ids[name])

    def apply_boundary(self, fixed: np.ndarray, velocity: np.ndarray) -> None:
        """Fixes, frees or drives every block as the masks say."""
        driven = ~np.isnan(velocity[:, 0])
        free = ~fixed & ~driven
        if fixed.any():
            self.sim.fix(np.flatnonzero(fixed).tolist())
        if free.any():
            self.sim.free(np.flatnonzero(free).tolist())
        for i in np.flatnonzero(driven):
            self.sim.prescribe(int(i), velocity[i].tolist())

    def copy(self) -> Engine:
        """An independent copy (state, contacts and shear histories included).

        Raises
        ------
        NotImplementedError
            The engine cannot copy a simulation (the runner then replays the stages)."""
        if not hasattr(self.sim, "copy"):
            raise NotImplementedError("penedge.Simulation has no copy()")
        twin = copy.copy(self)
        twin.sim = self.sim.copy()
        twin.properties = dict(self.properties)
        return twin

    # --- stepping -------------------------------------------------------------------

    def cycle(self, steps: int) -> None:
        """`steps` steps."""
        self.sim.step(steps)

    @property
    def timestep(self) -> float:
        """The time step (s)."""
        return float(self.sim.timestep)

    # --- state ----------------------------------------------------------------------

    @property
    def steps(self) -> int:
        """Steps taken."""
        return int(self.sim.steps)

    @property
    def time(self) -> float:
        """Model time (s)."""
        return float(self.sim.time)

    @property
    def ratio(self) -> float:
        """The unbalanced-force ratio."""
        return float(self.sim.unbalanced_ratio)

    def positions(self) -> np.ndarray:
        """Block centroids now, (n, 3)."""
        return np.array(self.sim.positions, dtype=float)

    def velocities(self) -> np.ndarray:
        """Block velocities now, (n, 3)."""
        return np.array(self.sim.velocities, dtype=float)

    def kinetic_energy(self) -> float:
        """Total kinetic energy of the blocks (J)."""
        return float(self.sim.kinetic_energy())

    def system(self) -> Any:
        """The blocks at their current poses, as a :class:`penedge.BlockSystem`."""
        return self.sim.system()

    def contacts(self) -> Any:
        """The contacts now, for the ParaView series (None when the engine gives none)."""
        return self.sim.contacts()
