"""The workspace: the finite set of configurations over which a design is judged.

A :class:`Workspace` holds joint coordinates ``θ`` (N×nv, rad or m, one column per
degree of freedom of the mechanism) and knows whether the rows form an ordered path
(needed by the ``energy`` objective). Constructors sample joint ranges on a grid, with a
scrambled Sobol sequence (:mod:`springbalance.model.sobol`: the points of
``scipy.stats.qmc.Sobol``), uniformly at random, or take explicit arrays. Ranges default to
the URDF limits and may be overridden per joint; linear couplings
``lower ≤ Σ_j c_j θ_j ≤ upper`` (for example ``knee - hip in [-60°, 0°]``) reject samples
outside them.
"""

from __future__ import annotations

import dataclasses
import re
from typing import Any, Mapping, Sequence

import numpy as np
import numpy.typing as npt

from springbalance.errors import InputError
from springbalance.model import budget
from springbalance.model.kinematics import WorkspaceKinematics
from springbalance.model.mechanism import Mechanism
from springbalance.model.sobol import sobol_engine

Range = tuple[float, float]
#: the largest joint value a workspace takes [rad or m]: beyond it a number is a typo, and would overflow
MAX_JOINT_VALUE = 1e6


@dataclasses.dataclass(frozen=True)
class Coupling:
    """Linear coupling between joints: ``lower ≤ Σ_j coefficients[j] · θ_j ≤ upper``.

    Bounds are in the joints' units (rad or m), or in degrees with ``degrees=True``.
    ``Coupling.parse("elbow - shoulder", -60, 0, degrees=True)`` reads a sum of joint
    names with optional numeric factors.
    """

    coefficients: Mapping[str, float]
    lower: float
    upper: float
    degrees: bool = False

    @classmethod
    def parse(cls, expression: str, lower: float, upper: float, degrees: bool = False) -> Coupling:
        """Build a coupling from text such as ``"q3 - q2"`` or ``"2*knee + hip"``."""
        text = expression.replace(" ", "")
        terms = re.findall(r"([+-]?)(?:(\d+(?:\.\d*)?(?:[eE][+-]?\d+)?)\*)?([A-Za-z_][\w.\-]*?)(?=[+-]|$)", text)
        rebuilt = "".join(sign + (factor + "*" if factor else "") + name for sign, factor, name in terms)
        if not terms or rebuilt.lstrip("+") != text.lstrip("+"):
            raise InputError(f"cannot read coupling expression {expression!r}; write e.g. 'knee - hip' or '2*a + b'")
        coefficients: dict[str, float] = {}
        for sign, factor, name in terms:
            value = float(factor) if factor else 1.0
            coefficients[name] = coefficients.get(name, 0.0) + (-value if sign == "-" else value)
        return cls(coefficients, lower, upper, degrees)

    def bounds(self) -> Range:
        """``(lower, upper)`` in the joints' units (degrees converted to rad)."""
        scale = np.pi / 180 if self.degrees else 1.0
        return self.lower * scale, self.upper * scale

    def vector(self, mechanism: Mechanism) -> np.ndarray:
        """Coefficients as a vector over the mechanism's joints."""
        row = np.zeros(mechanism.nv)
        for name, value in self.coefficients.items():
            row[mechanism.joint(name).index_v] += value
        return row

    def describe(self) -> str:
        """The coupling as text, e.g. ``1*elbow - 1*shoulder in [-60, 0] deg``."""
        terms = " ".join(f"{'+' if v >= 0 else '-'} {abs(v):g}*{k}" for k, v in self.coefficients.items())
        unit = " deg" if self.degrees else ""
        return f"{terms.lstrip('+ ')} in [{self.lower:g}, {self.upper:g}]{unit}"


class Workspace:
    """Configurations ``θ_1 … θ_N`` of a mechanism.

    Attributes:
        mechanism: the :class:`~springbalance.model.mechanism.Mechanism` sampled.
        joint_values: N×nv array of joint coordinates [rad or m].
        ordered: True when the rows form a path (grid sweeps, trajectories).
        description: how the samples were made (saved with designs).
    """

    def __init__(
        self,
        mechanism: Mechanism,
        joint_values: npt.ArrayLike,
        ordered: bool = False,
        description: dict[str, Any] | None = None,
    ) -> None:
        values = np.atleast_2d(np.asarray(joint_values, dtype=float))
        if values.ndim != 2 or values.shape[1] != mechanism.nv:
            raise InputError(
                f"workspace array has shape {np.shape(joint_values)}; expected (N, {mechanism.nv}) for joints "
                f"{', '.join(mechanism.joint_names)}"
            )
        if values.shape[0] == 0:
            raise InputError("workspace has no samples")
        if not np.all(np.isfinite(values)):
            row = int(np.argwhere(~np.isfinite(values))[0][0])
            raise InputError(f"workspace sample {row} is not finite: {values[row].tolist()}")
        if np.any(np.abs(values) > MAX_JOINT_VALUE):
            row = int(np.argwhere(np.abs(values) > MAX_JOINT_VALUE)[0][0])
            raise InputError(
                f"workspace sample {row} has a joint value beyond ±{MAX_JOINT_VALUE:g} rad or m: {values[row].tolist()}"
            )
        self.mechanism = mechanism
        self.joint_values = values
        self.ordered = bool(ordered)
        self.description = dict(description or {"kind": "array"})
        self._kinematics: WorkspaceKinematics | None = None

    # ----------------------------------------------------------------- constructors
    @classmethod
    def from_array(
        cls, mechanism: Mechanism, joint_values: npt.ArrayLike, ordered: bool = True, degrees: bool = False
    ) -> Workspace:
        """Explicit samples (rows). A trajectory is ordered; pass ``ordered=False`` for a cloud."""
        values = np.asarray(joint_values, dtype=float)
        if degrees:
            values = _to_radians(mechanism, values)
        return cls(
            mechanism, values, ordered=ordered, description={"kind": "array", "n": int(np.atleast_2d(values).shape[0])}
        )

    @classmethod
    def grid(
        cls,
        mechanism: Mechanism,
        n: int | Mapping[str, int] = 16,
        ranges: Mapping[str, Sequence[float]] | None = None,
        couplings: Sequence[Coupling] = (),
        degrees: bool = False,
    ) -> Workspace:
        """Tensor grid with ``n`` points per joint (an int, or a dict joint → count).

        A joint with a zero-width range, or a count of 1, is held at the range's midpoint.
        The grid is ordered as a raster path (last joint fastest).
        """
        lower, upper = _ranges(mechanism, ranges, degrees)
        counts = []
        for joint in mechanism.joints:
            count = (
                n.get(joint.name, 1 if lower[joint.index_v] == upper[joint.index_v] else 16)
                if isinstance(n, Mapping)
                else n
            )
            count = _count(count, f"grid count for joint {joint.name!r}")
            if lower[joint.index_v] == upper[joint.index_v]:
                count = 1
            counts.append(count)
        if isinstance(n, Mapping):
            for name in n:
                mechanism.joint(name)
        total = int(np.prod(counts, dtype=object))
        budget.require(
            _workspace_bytes(mechanism, "grid", total),
            f"a grid workspace of {' × '.join(map(str, counts))} = {total} samples",
        )
        axes = [
            np.linspace(lo, hi, c) if c > 1 else np.array([(lo + hi) / 2]) for lo, hi, c in zip(lower, upper, counts)
        ]
        values = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, mechanism.nv)
        values = _apply_couplings(mechanism, values, couplings)
        description = {
            "kind": "grid",
            "n": [int(c) for c in counts],
            "lower": lower.tolist(),
            "upper": upper.tolist(),
            "couplings": [_coupling_record(c) for c in couplings],
        }
        return cls(mechanism, values, ordered=True, description=description)

    @classmethod
    def sobol(
        cls,
        mechanism: Mechanism,
        n: int = 1024,
        ranges: Mapping[str, Sequence[float]] | None = None,
        couplings: Sequence[Coupling] = (),
        degrees: bool = False,
        seed: int = 0,
    ) -> Workspace:
        """``n`` scrambled Sobol points over the joint ranges (deterministic given ``seed``)."""
        return cls._sampled(mechanism, n, ranges, couplings, degrees, seed, "sobol")

    @classmethod
    def random(
        cls,
        mechanism: Mechanism,
        n: int = 1024,
        ranges: Mapping[str, Sequence[float]] | None = None,
        couplings: Sequence[Coupling] = (),
        degrees: bool = False,
        seed: int = 0,
    ) -> Workspace:
        """``n`` uniform random points over the joint ranges (deterministic given ``seed``)."""
        return cls._sampled(mechanism, n, ranges, couplings, degrees, seed, "random")

    @classmethod
    def sweep(
        cls,
        mechanism: Mechanism,
        joint: str,
        n: int = 181,
        ranges: Mapping[str, Sequence[float]] | None = None,
        degrees: bool = False,
    ) -> Workspace:
        """Ordered sweep of one joint over its range, the others at their range midpoints."""
        index = mechanism.joint(joint).index_v
        n = _count(n, "sweep point count")
        lower, upper = _ranges(mechanism, ranges, degrees)
        budget.require(_workspace_bytes(mechanism, "sweep", n), f"a sweep of {n} samples")
        values = np.tile((lower + upper) / 2, (n, 1))
        values[:, index] = np.linspace(lower[index], upper[index], n)
        return cls(mechanism, values, ordered=True, description={"kind": "sweep", "joint": joint, "n": n})

    @classmethod
    def _sampled(
        cls,
        mechanism: Mechanism,
        n: int,
        ranges: Mapping[str, Sequence[float]] | None,
        couplings: Sequence[Coupling],
        degrees: bool,
        seed: int,
        kind: str,
    ) -> Workspace:
        n = _count(n, "workspace sample count")
        budget.require(
            _workspace_bytes(mechanism, kind, n), f"a {kind} workspace of {n} samples of {mechanism.nv} joints"
        )
        lower, upper = _ranges(mechanism, ranges, degrees)
        rng = np.random.default_rng(seed)
        sampler = sobol_engine(mechanism.nv, rng) if kind == "sobol" else None
        accepted = np.empty((0, mechanism.nv))
        drawn = 0
        while accepted.shape[0] < n:
            batch = max(n, 64)
            if sampler is not None:
                batch = 1 << int(np.ceil(np.log2(batch)))  # Sobol balance wants powers of two
                unit = sampler.random(batch)
            else:
                unit = rng.random((batch, mechanism.nv))
            drawn += batch
            values = lower + unit * (upper - lower)
            accepted = np.vstack([accepted, _apply_couplings(mechanism, values, couplings, allow_empty=True)])
            if drawn >= 200 * n and accepted.shape[0] < n:
                raise InputError(
                    f"couplings {', '.join(c.describe() for c in couplings)} leave almost no room in the joint "
                    f"ranges: {accepted.shape[0]} of {drawn} samples accepted"
                )
        description = {
            "kind": kind,
            "n": n,
            "seed": seed,
            "lower": lower.tolist(),
            "upper": upper.tolist(),
            "couplings": [_coupling_record(c) for c in couplings],
        }
        return cls(mechanism, accepted[:n], ordered=False, description=description)

    # ----------------------------------------------------------------- data
    @property
    def size(self) -> int:
        """Number of samples N."""
        return self.joint_values.shape[0]

    def __len__(self) -> int:
        return self.size

    @property
    def configurations(self) -> np.ndarray:
        """Pinocchio configurations (N×nq)."""
        return self.mechanism.configurations(self.joint_values)

    def kinematics(self) -> WorkspaceKinematics:
        """The numeric cache of gravity torques, placements and Jacobians (computed once)."""
        if self._kinematics is None:
            model = self.mechanism.model
            budget.require(
                budget.kinematics_bytes(self.size, model.nv, model.nq),
                f"the gravity torques of a workspace of {self.size} samples",
            )
            self._kinematics = WorkspaceKinematics(self)
        return self._kinematics

    def __repr__(self) -> str:
        return f"Workspace({self.description.get('kind')}, N={self.size}, ordered={self.ordered})"


def _workspace_bytes(mechanism: Mechanism, kind: str, n: int) -> int:
    """Memory [bytes] to sample ``n`` poses and compute their gravity torques (what every use of a
    workspace does next), :mod:`springbalance.model.budget`."""
    return budget.sampling_bytes(kind, n, mechanism.nv) + budget.kinematics_bytes(n, mechanism.nv, mechanism.model.nq)


def _count(n: object, what: str) -> int:
    """``n`` as an int ≥ 1 (an integral float such as ``1e4`` counts); InputError naming ``what`` otherwise."""
    if isinstance(n, (bool, np.bool_)) or not isinstance(n, (int, float, np.integer, np.floating)):
        raise InputError(f"{what} must be an integer ≥ 1, got {n!r}")
    if isinstance(n, (float, np.floating)) and not (np.isfinite(n) and float(n).is_integer()):
        raise InputError(f"{what} must be an integer ≥ 1, got {n!r}")
    count = int(n)
    if count < 1:
        raise InputError(f"{what} must be ≥ 1, got {count}")
    return count


def _ranges(
    mechanism: Mechanism, ranges: Mapping[str, Sequence[float]] | None, degrees: bool
) -> tuple[np.ndarray, np.ndarray]:
    lower = np.array([joint.lower for joint in mechanism.joints])
    upper = np.array([joint.upper for joint in mechanism.joints])
    for name, bounds in (ranges or {}).items():
        joint = mechanism.joint(name)
        values = np.atleast_1d(np.asarray(bounds, dtype=float))
        if values.size == 1:
            values = np.array([values[0], values[0]])
        if values.size != 2 or not np.all(np.isfinite(values)):
            raise InputError(f"range of joint {name!r} must be [lower, upper] with finite numbers, got {bounds!r}")
        if np.any(np.abs(values) > MAX_JOINT_VALUE):
            raise InputError(f"range of joint {name!r} must lie within ±{MAX_JOINT_VALUE:g} rad or m, got {bounds!r}")
        if degrees and joint.kind != "prismatic":
            values = np.deg2rad(values)
        if values[0] > values[1]:
            raise InputError(f"range of joint {name!r}: lower {bounds[0]!r} > upper {bounds[1]!r}")
        lower[joint.index_v], upper[joint.index_v] = values
    return lower, upper


def _apply_couplings(
    mechanism: Mechanism, values: np.ndarray, couplings: Sequence[Coupling], allow_empty: bool = False
) -> np.ndarray:
    keep = np.ones(values.shape[0], dtype=bool)
    for coupling in couplings:
        lo, hi = coupling.bounds()
        if lo > hi:
            raise InputError(f"coupling {coupling.describe()}: lower > upper")
        combination = values @ coupling.vector(mechanism)
        keep &= (combination >= lo - 1e-12) & (combination <= hi + 1e-12)
    if not allow_empty and not np.any(keep):
        raise InputError(f"couplings {', '.join(c.describe() for c in couplings)} exclude every sample")
    return values[keep]


def _coupling_record(coupling: Coupling) -> dict:
    return {
        "coefficients": dict(coupling.coefficients),
        "lower": coupling.lower,
        "upper": coupling.upper,
        "degrees": coupling.degrees,
    }


def _to_radians(mechanism: Mechanism, values: np.ndarray) -> np.ndarray:
    values = np.array(np.atleast_2d(values), dtype=float)
    for joint in mechanism.joints:
        if joint.kind != "prismatic" and values.shape[1] == mechanism.nv:
            values[:, joint.index_v] = np.deg2rad(values[:, joint.index_v])
    return values
