r"""Scenarios: the same arm carrying different loads (payloads, scaled link masses).

A :class:`Scenario` changes only the mass distribution of a :class:`~springbalance.model.mechanism.Mechanism`:

- a :class:`Payload` adds a point mass (optionally with a rotational inertia about its
  centre) fixed in a named body: mass ``m`` [kg] at body-frame point ``p`` [m];
- ``mass_scale`` multiplies link masses and inertias by ``β`` (all moving bodies, or the
  bodies named in a mapping), e.g. ``β·limb + device`` for a rehabilitation device that
  carries a fraction ``β`` of the limb's weight.

Scaling is applied first, then payloads. Kinematics are unchanged: a scenario changes the
gravity torque ``g(q)`` and potential ``V_g(q)`` of each workspace sample, nothing else
(docs/model.md §8). :class:`ScenarioWorkspace` stacks the workspace once per scenario, so that a
design problem over several scenarios is an ordinary problem over ``N·S`` samples whose
sample ``i`` of block ``s`` sees scenario ``s``'s gravity.

Note on ``mass_scale`` with a mapping: Pinocchio merges links welded by fixed joints into
the body of their moving joint, so scaling body ``B`` scales everything that moves with
``B``'s joint (``B`` and the links fixed to it).
"""

from __future__ import annotations

import dataclasses
from typing import Any, Iterable, Mapping, Sequence

import numpy as np
import pinocchio as pin

from springbalance.errors import InputError
from springbalance.model.kinematics import StackedKinematics
from springbalance.model.mechanism import Mechanism
from springbalance.model.workspace import Workspace


@dataclasses.dataclass(frozen=True)
class Payload:
    """A point mass ``mass`` [kg] at ``point`` [m] in the frame of ``body`` (URDF link).

    ``inertia``: optional 3×3 rotational inertia about the point, body frame [kg·m²].
    """

    body: str
    mass: float
    point: tuple = (0.0, 0.0, 0.0)
    inertia: tuple | None = None

    def __post_init__(self) -> None:
        mass = float(self.mass)
        if not np.isfinite(mass) or mass < 0:
            raise InputError(f"payload on {self.body!r}: mass must be a finite number ≥ 0 [kg], got {self.mass!r}")
        point = np.asarray(self.point, dtype=float).reshape(-1)
        if point.shape != (3,) or not np.all(np.isfinite(point)):
            raise InputError(f"payload on {self.body!r}: point must be three finite numbers [m], got {self.point!r}")
        object.__setattr__(self, "mass", mass)
        object.__setattr__(self, "point", tuple(point.tolist()))
        if self.inertia is not None:
            inertia = np.asarray(self.inertia, dtype=float)
            if inertia.shape != (3, 3) or not np.all(np.isfinite(inertia)):
                raise InputError(f"payload on {self.body!r}: inertia must be a finite 3×3 matrix [kg·m²]")
            object.__setattr__(self, "inertia", tuple(map(tuple, inertia.tolist())))

    def to_dict(self) -> dict:
        record: dict[str, Any] = {"body": self.body, "mass": self.mass, "point": list(self.point)}
        if self.inertia is not None:
            record["inertia"] = [list(row) for row in self.inertia]
        return record


class Scenario:
    """One load case of a mechanism: payloads and/or scaled link masses.

    Args:
        name: label used in variable names (``s1.b.s[name]``) and reports.
        payloads: :class:`Payload` objects (or ``{body, mass, point?, inertia?}`` records).
        mass_scale: ``β`` for every moving body, or ``{body: β}``; default none (β = 1).
    """

    def __init__(self, name: str, payloads: Sequence = (), mass_scale: float | Mapping[str, float] | None = None):
        if not isinstance(name, str) or not name:
            raise InputError(f"scenario name must be a non-empty string, got {name!r}")
        self.name = name
        self.payloads = [p if isinstance(p, Payload) else Payload(**p) for p in payloads]
        if mass_scale is not None:
            scales = mass_scale.values() if isinstance(mass_scale, Mapping) else [mass_scale]
            for value in scales:
                if isinstance(value, bool) or not np.isfinite(float(value)) or float(value) < 0:
                    raise InputError(f"scenario {name!r}: mass_scale must be ≥ 0, got {value!r}")
        self.mass_scale = dict(mass_scale) if isinstance(mass_scale, Mapping) else mass_scale

    @property
    def payload_mass(self) -> float:
        """Total payload mass [kg]."""
        return float(sum(p.mass for p in self.payloads))

    def apply(self, mechanism: Mechanism) -> Mechanism:
        """A copy of ``mechanism`` with this scenario's masses (gravity and joints unchanged)."""
        model = mechanism.model.copy()
        if self.mass_scale is not None:
            if isinstance(self.mass_scale, Mapping):
                joints = {}
                for body, beta in self.mass_scale.items():
                    joint_id = model.frames[mechanism.frame_id(body)].parentJoint
                    if joint_id == 0:
                        raise InputError(f"scenario {self.name!r}: mass_scale body {body!r} does not move")
                    joints[joint_id] = float(beta)
            else:
                joints = {j: float(self.mass_scale) for j in range(1, model.njoints)}
            for joint_id, beta in joints.items():
                inertia = model.inertias[joint_id]
                model.inertias[joint_id] = pin.Inertia(beta * inertia.mass, inertia.lever, beta * inertia.inertia)
        for payload in self.payloads:
            frame = model.frames[mechanism.frame_id(payload.body)]
            if frame.parentJoint == 0:
                continue  # a mass on the ground changes no torque
            rotational = np.zeros((3, 3)) if payload.inertia is None else np.array(payload.inertia)
            local = pin.Inertia(payload.mass, np.array(payload.point), rotational)  # in the body frame
            model.inertias[frame.parentJoint] = model.inertias[frame.parentJoint] + frame.placement.act(local)
        source = {**mechanism.source, "scenario": self.to_dict()}
        scenario_mechanism = Mechanism(model, source=source)
        return scenario_mechanism

    def to_dict(self) -> dict:
        record: dict[str, Any] = {"name": self.name}
        if self.payloads:
            record["payloads"] = [p.to_dict() for p in self.payloads]
        if self.mass_scale is not None:
            record["mass_scale"] = self.mass_scale
        return record

    @classmethod
    def from_dict(cls, record: dict) -> Scenario:
        return cls(record["name"], [Payload(**p) for p in record.get("payloads", [])], record.get("mass_scale"))

    def __repr__(self) -> str:
        return f"Scenario({self.name!r}, payload {self.payload_mass:g} kg)"


def payload_scenarios(body: str, masses: Sequence[float], point: Sequence[float] = (0.0, 0.0, 0.0)) -> list[Scenario]:
    """One scenario per payload mass [kg] at ``point`` [m] of ``body``, named ``"<m> kg"``."""
    masses = [float(m) for m in masses]
    if not masses:
        raise InputError("payload_scenarios needs at least one mass")
    return [Scenario(f"{m:g} kg", [Payload(body, m, tuple(point))] if m > 0 else []) for m in masses]


class ScenarioWorkspace(Workspace):
    """The samples of ``workspace`` repeated once per scenario (block ``s`` = scenario ``s``).

    Its :meth:`kinematics` stacks the gravity torque and potential of each scenario's
    mechanism over the same poses, and shares the body placements and Jacobians (which no
    scenario changes).
    """

    def __init__(self, workspace: Workspace, scenarios: Sequence[Scenario]):
        if isinstance(workspace, ScenarioWorkspace):
            raise InputError("a scenario workspace cannot be stacked again")
        self.base = workspace
        self.scenarios = list(scenarios)
        self.mechanisms = [scenario.apply(workspace.mechanism) for scenario in self.scenarios]
        description = {
            "kind": "scenarios",
            "scenarios": [s.name for s in self.scenarios],
            "base": workspace.description,
        }
        super().__init__(
            workspace.mechanism,
            np.tile(workspace.joint_values, (len(self.scenarios), 1)),
            ordered=workspace.ordered,
            description=description,
        )

    @property
    def block_size(self) -> int:
        """Samples per scenario."""
        return self.base.size

    def kinematics(self) -> StackedKinematics:
        """The stacked kinematics of every scenario's samples (computed once)."""
        if self._kinematics is None:
            self._kinematics = StackedKinematics(self, self.base.kinematics(), self.mechanisms)
        assert isinstance(self._kinematics, StackedKinematics)  # the only kinematics this workspace makes
        return self._kinematics


def check_scenarios(mechanism: Mechanism, scenarios: Iterable[Scenario | dict]) -> list[Scenario]:
    """Validated list of scenarios (bodies exist, names unique)."""
    checked = [s if isinstance(s, Scenario) else Scenario.from_dict(s) for s in scenarios]
    if not checked:
        raise InputError("scenarios: give at least one scenario")
    names = [s.name for s in checked]
    if len(set(names)) != len(names):
        raise InputError(f"scenario names must be unique, got {', '.join(names)}")
    for scenario in checked:
        for payload in scenario.payloads:
            if payload.body not in mechanism.body_names:
                raise InputError(
                    f"scenario {scenario.name!r}: unknown payload body {payload.body!r}; "
                    f"bodies: {', '.join(mechanism.body_names)}"
                )
        if isinstance(scenario.mass_scale, Mapping):
            for body in scenario.mass_scale:
                if body not in mechanism.body_names:
                    raise InputError(
                        f"scenario {scenario.name!r}: unknown mass_scale body {body!r}; "
                        f"bodies: {', '.join(mechanism.body_names)}"
                    )
    return checked
