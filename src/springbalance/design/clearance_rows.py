r"""Linear rows of clearance and mounting, linearised at a design (see :mod:`springbalance.design.clearance`).

For a fixed pose each spring end is affine in the anchor coordinates (docs/model.md §2), so
``P(x) = P_0 + J (x - x_0)`` exactly, and a separating plane ``(w, n)`` gives the row
``n^\top (R P(x) + p - w) - r - m^+ \ge 0`` [m], affine in ``x``. Mounting rows hold an anchor on
its offset surface between tangent planes.
"""

from __future__ import annotations

from typing import Sequence

import numpy as np
import pinocchio as pin

from springbalance.design.clearance import LinearRows
from springbalance.design.mounts import MOUNT_TOLERANCE
from springbalance.design.problem import DesignProblem
from springbalance.design.solvers import FEASIBILITY_TOLERANCE
from springbalance.model.collision import collision_geometry
from springbalance.model.surfaces import surface_distance
from springbalance.springs.laws import Spring


def mount_planes(problem: DesignProblem, x: np.ndarray | Sequence[float], planes: dict | None = None) -> dict:
    """Per mounted anchor (``(spring name, end, scenario)``), its tangent planes ``(w, n)``: those in ``planes``
    and the one at design ``x`` (body frame: closest surface point ``w`` [m], outward unit normal ``n``)."""
    planes = {key: list(value) for key, value in (planes or {}).items()}
    if not problem.mounts:
        return planes
    geometry = collision_geometry(problem.mechanism)
    for spring, end, anchor in problem.mounts:
        for scenario in range(problem.model.n_scenarios):
            P = problem.model.anchor_point(spring, end, x, scenario)
            distance, w, normal = surface_distance(problem.mechanism, geometry, anchor.body, P)
            if distance > 1e-9:
                normal = (P - w) / np.linalg.norm(P - w)
            history = planes.setdefault((spring.name, end, scenario), [])
            if not any(np.allclose(w, old_w) and np.allclose(normal, old_n) for old_w, old_n in history):
                history.append((w, normal))
            else:  # the current plane moves to the end (it is the one the anchor must lie on)
                history.append(
                    history.pop(
                        next(
                            i
                            for i, (old_w, old_n) in enumerate(history)
                            if np.allclose(w, old_w) and np.allclose(normal, old_n)
                        )
                    )
                )
    return planes


def rows_held(problem: DesignProblem, rows: LinearRows | None, x: np.ndarray) -> LinearRows | None:
    """The rows of ``rows`` (over ``problem``'s variables) that design ``x`` [physical units] meets, to
    :data:`~springbalance.design.solvers.FEASIBILITY_TOLERANCE` [m]; None when it meets none."""
    if rows is None or not len(rows):
        return None
    matrix, offset = problem.with_linear_rows(rows).linear_matrix()
    held = matrix @ np.asarray(x, dtype=float) + offset >= -FEASIBILITY_TOLERANCE
    if not np.any(held):
        return None
    labels = [label for label, keep in zip(rows.labels, held) if keep]
    return LinearRows(list(rows.names), rows.matrix[held], rows.offset[held], labels, rows.scale)


def mount_rows(problem: DesignProblem, x: np.ndarray | Sequence[float]) -> LinearRows | None:
    """The rows that hold every ``on: collision`` anchor on its offset surface, linearised at ``x``."""
    return _rows(problem, x, [], [], mount_planes(problem, x))


def _mount_errors(problem: DesignProblem, x: np.ndarray, geometry: pin.GeometryModel) -> dict[str, float]:
    """``"<spring>.<end>"`` → distance [m] of each mounted anchor from its offset surface at ``x``."""
    errors: dict[str, float] = {}
    for spring, end, anchor in problem.mounts:
        for scenario in range(problem.model.n_scenarios):
            point = problem.model.anchor_point(spring, end, x, scenario)
            distance = surface_distance(problem.mechanism, geometry, anchor.body, point)[0]
            key = f"{spring.name}.{end}"
            errors[key] = max(errors.get(key, 0.0), abs(distance - anchor.offset))
    return errors


# ====================================================================== rows
class _AnchorMaps:
    """Per (spring, end, scenario): the anchor point ``P(x) = P0 + J (x - x0)`` (body frame), exact since affine."""

    def __init__(self, problem: DesignProblem) -> None:
        self.problem = problem
        self._jacobians: dict[tuple[str | None, str, int], np.ndarray] = {}

    def jacobian(self, spring: Spring, end: str, scenario: int) -> np.ndarray:
        key = (spring.name, end, scenario)
        if key not in self._jacobians:
            model = self.problem.model
            n = self.problem.variables.size
            zero = np.zeros(n)
            base = model.anchor_point(spring, end, zero, scenario)
            self._jacobians[key] = (
                np.column_stack([model.anchor_point(spring, end, np.eye(n)[k], scenario) - base for k in range(n)])
                if n
                else np.zeros((3, 0))
            )
        return self._jacobians[key]


def _rows(
    problem: DesignProblem, x: np.ndarray | Sequence[float], object_cuts: list, spring_cuts: list, planes: dict | None
) -> LinearRows | None:
    """Linear rows at design ``x``: mounting rows, then the given cuts.

    ``planes``: per mounted anchor, its tangent planes of the offset surface (:func:`mount_planes`); None:
    no mounting rows (the cuts alone).
    The anchor stays inside every one of them, ``n·(p - w) ≤ offset``: each bounds the convex
    offset body, so none cuts off a point of its surface, and together they keep the anchor on
    the part of the surface they have seen. It lies on the last one: ``n·(p - w) ≥ offset``.

    ``object_cuts``: ``(label, spring, scenario, frames (R_a, p_a, R_b, p_b), contact, radius, target)``;
    ``spring_cuts``: ``(label, (spring_i, frames_i, r_i), (spring_j, frames_j, r_j), scenario, contact, target)``.
    """
    maps = _AnchorMaps(problem)
    model = problem.model
    n = problem.variables.size
    matrix: list[np.ndarray] = []
    offset: list[float] = []
    labels: list[str] = []

    def end_row(
        spring: Spring,
        end: str,
        scenario: int,
        rotation: np.ndarray,
        translation: np.ndarray,
        normal: np.ndarray,
        point: np.ndarray,
    ) -> tuple[np.ndarray, float]:
        """Gradient and value of ``n·(R P(x) + p - w)`` at ``x``."""
        P = model.anchor_point(spring, end, x, scenario)
        gradient = normal @ rotation @ maps.jacobian(spring, end, scenario)
        value = float(normal @ (rotation @ P + translation - point))
        return gradient, value

    identity, zero = np.eye(3), np.zeros(3)
    for spring, end, anchor in problem.mounts if planes is not None else ():
        for scenario in range(model.n_scenarios):
            history = (planes or {})[(spring.name, end, scenario)]
            for index, (w, normal) in enumerate(history):
                gradient, value = end_row(spring, end, scenario, identity, zero, normal, w)
                for sign in (-1.0, 1.0) if index == len(history) - 1 else (-1.0,):
                    matrix.append(sign * gradient)
                    offset.append(sign * (value - anchor.offset) + MOUNT_TOLERANCE - sign * gradient @ x)
                    labels.append(
                        f"{spring.name}.{end} {'on' if sign > 0 else 'within'} the offset surface of {anchor.body}"
                    )
    for label, spring, scenario, frames, contact, radius, target in object_cuts:
        for end, (rotation, translation) in zip(_ends_of(spring), frames):
            gradient, value = end_row(spring, end, scenario, rotation, translation, contact.normal, contact.on_object)
            matrix.append(gradient)
            offset.append(value - radius - target - gradient @ x)
            labels.append(f"{label}, end {end}")
    for label, first, second, scenario, contact, target in spring_cuts:
        middle = (contact.on_capsule + contact.on_object) / 2
        for (spring, frames, radius), sign in ((first, 1.0), (second, -1.0)):
            for end, (rotation, translation) in zip(_ends_of(spring), frames):
                gradient, value = end_row(spring, end, scenario, rotation, translation, sign * contact.normal, middle)
                matrix.append(gradient)
                offset.append(value - radius - target / 2 - gradient @ x)
                labels.append(f"{label}, {spring.name} end {end}")
    if not offset:
        return None
    return LinearRows(list(problem.variables.names), np.array(matrix).reshape(-1, n), np.array(offset), labels)


def _ends_of(spring: Spring) -> tuple[str, str]:
    """The ends of a spring's own body: ``a`` and ``b``, or for a routed spring ``a`` and its first
    pulley (the capsule is its first segment; its cable beyond is not checked)."""
    return getattr(spring, "spring_ends", ("a", "b"))


def _radius(problem: DesignProblem, spring: Spring, x: np.ndarray, default: float) -> float:
    """Capsule radius [m] of ``spring`` at design ``x``: half its coil's outer diameter, or ``default``."""
    values = problem.model.spring_values(spring, x)
    if "mean_diameter" in values and "wire_diameter" in values:
        return 0.5 * (values["mean_diameter"] + values["wire_diameter"])
    return default
