r"""The corners of the springs' tolerance box as load cases of one design problem: the robust design
(``tolerance: {robust: true}``, docs/model.md §3.10).

**Which corners.** Spring ``s`` (an extension or compression law, linear) at a corner of its box has
the tension :math:`F' = \sigma T' + k'(L - l_0')` with :math:`k' = k(1 + a\rho)`, :math:`T' = T + b f`,
:math:`l_0' = l_0 + c\lambda - t` (σ = +1 extension, −1 compression; ``T`` the initial tension or
preload; ``t`` the adjuster's setting, 0 without one; ``a, b, c ∈ {−1, +1}``). Its residual change is

.. math:: \delta\tau_s(q) = \big[a\rho k (L_s - l_0) + o + k(1 + a\rho)\,t\big]\, m_s(q),\qquad
          o = \sigma b f - k (1 + a\rho)\, c\lambda ,

``m_s`` its moment arm. For a fixed rate sign ``a`` the residual is affine in the constant ``o`` (and
in ``t``); every objective here (rms, peak, joint_peaks; and its minimum over the adjusters, a partial
minimum of a jointly convex function) is convex in the residual, so its maximum over ``o`` is at an end
of ``o``'s interval: ``(b, c) = (σ, −1)`` (more tension) or ``(−σ, +1)`` (less). Of each spring's
8 corners, 4 bound every objective: the rate ``r = a`` and the force ``p = ±1`` (+: a stronger spring,
more force magnitude), ``(a, b, c) = (r, p, −σp)``. Coordinate by coordinate, the worst over the
:math:`8^n` builds is the worst over these :math:`4^n` ("exact", the default).

A *peak* needs fewer: at each pose and joint the worst residual takes each spring's largest or
smallest force change, and while an extension spring stays in tension (``L ≥ l_0``) or a compression
spring compressed, those are its *strong* ``(r, p) = (+, +)`` and *weak* ``(−, −)`` corners at every
pose. So the :math:`2^n` strong/weak combinations ("strong_weak") give the exact worst peak without
adjusters. The two corners *every spring strong* and *every spring weak* ("uniform") are exact for a
peak only when at every pose and joint all springs' moment arms have one sign (each joint driven by one
spring, say); otherwise, and for an RMS, they give a lower bound: a spring that is steep and weak
tilts the residual in a way neither uniform corner does.

The nominal law is the first case, without adjustment (``t = 0``); each corner has its own adjuster
setting per spring, a design variable ``<spring>.adjuster[<corner>]`` in ``[−travel, +travel]`` [m]
when the spec gives an ``adjuster_travel``. The practical rules (stress, tension, length) hold for the
nominal law: every case checks them with it.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field
from typing import Any, Sequence

import casadi as ca

from springbalance.design.tolerance_spec import ToleranceSpec
from springbalance.errors import InputError
from springbalance.springs.laws import Spring, TwoPointSpring
from springbalance.springs.laws.coil import HelicalCoilSpring
from springbalance.springs.tolerance_grades import PROPORTIONAL_FORCE, alpha_f, k_f, quality_factor

#: the corner sets: name → what it is exact for (docs/model.md §3.10)
CORNER_SETS = {
    "exact": "4^n corners: the worst over the box of any objective convex in the residual",
    "strong_weak": "2^n strong/weak combinations: the worst peak (springs in tension / compressed)",
    "uniform": "2 corners, every spring strong and every spring weak: exact when the arms share a sign",
}
#: the largest number of corner cases a robust problem takes (each one repeats the workspace)
MAX_CORNERS = 64
NOMINAL = "nominal"
#: (rate, force) strength signs of each spring's 4 corners; +: a stiffer / stronger spring
_EXACT = ((1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0))


@dataclass(frozen=True)
class Corner:
    """One case: ``name`` and per toleranced spring its ``(rate, force)`` strength signs (empty: nominal)."""

    name: str
    strengths: dict[str, tuple[float, float]] = field(default_factory=dict)

    def law_signs(self, spring: str, sign: float) -> tuple[float, float, float]:
        """``(a, b, c)``: the signs of the deviations of rate, initial tension (preload), free length."""
        r, p = self.strengths[spring]
        return r, p, -sign * p


def corner_cases(springs: Sequence[str], corners: str) -> list[Corner]:
    """The nominal case, then the corners of set ``corners`` (:data:`CORNER_SETS`) over ``springs``."""
    if corners == "uniform":
        cases = [((1.0, 1.0),) * len(springs), ((-1.0, -1.0),) * len(springs)]
        names = ["strong", "weak"]
    else:
        per_spring = _EXACT if corners == "exact" else ((1.0, 1.0), (-1.0, -1.0))
        cases = list(itertools.product(per_spring, repeat=len(springs)))
        names = [",".join(_label(signs) for signs in case) for case in cases]
    return [Corner(NOMINAL)] + [Corner(name, dict(zip(springs, case))) for name, case in zip(names, cases)]


def _label(signs: tuple[float, float]) -> str:
    """``k+F-``: rate up, force down."""
    return "k" + "+-"[signs[0] < 0] + "F" + "+-"[signs[1] < 0]


def toleranced_springs(springs: Sequence[Spring], spec: ToleranceSpec) -> list[str]:
    """The names of the springs with a box under ``spec`` (extension and compression laws; coils only under
    a grade); InputError for a routed one or when none has a box."""
    names = []
    for spring in springs:
        kind = getattr(spring, "kind", None)
        if not isinstance(spring, TwoPointSpring) or kind not in ("extension", "compression"):
            continue
        if spring.routed:
            raise InputError(
                f"tolerance.robust: spring {spring.name!r} is routed over pulleys; the robust design takes "
                "two-point extension and compression springs only"
            )
        if spec.explicit or isinstance(spring, HelicalCoilSpring):
            names.append(str(spring.name))
    if not names:
        raise InputError(
            "tolerance.robust: no spring has a tolerance box (a grade tolerances helical coils only; "
            "give explicit rate, initial_tension, free_length for ideal laws)"
        )
    return names


def law_symbols(spring: TwoPointSpring, parameters: dict) -> tuple[float, Any, Any, Any]:
    """``(σ, k [N/m], l0 [m], T [N])`` of a linear law, as expressions of its parameters."""
    sign = 1.0 if spring.kind == "extension" else -1.0
    if isinstance(spring, HelicalCoilSpring):
        rate = spring.rate(parameters)
        free = spring.free_length(parameters) if sign > 0 else parameters["free_length"]  # type: ignore[attr-defined]
    else:
        rate, free = parameters["stiffness"], parameters["free_length"]
    tension = parameters.get("initial_tension", parameters.get("preload", 0.0))
    return sign, rate, free, tension


def box_symbols(spring: TwoPointSpring, parameters: dict, rate: Any, tension: Any, spec: ToleranceSpec) -> tuple:
    """``(ρ [1], f [N], λ [m])`` of the spring's box: explicit numbers, or a grade's (as expressions of the coil,
    :func:`springbalance.springs.tolerance_grades.grade_box`)."""
    if spec.explicit:
        return spec.rate or 0.0, spec.initial_tension or 0.0, spec.free_length or 0.0
    assert spec.grade is not None  # not explicit: a grade
    q = quality_factor(spec.grade)
    d, D, n = (parameters[key] for key in ("wire_diameter", "mean_diameter", "active_coils"))
    constant = alpha_f(d, D) * k_f(n) * q  # [N]
    if spring.kind == "extension":
        return PROPORTIONAL_FORCE * q, constant + PROPORTIONAL_FORCE * q * ca.fabs(tension), 0.0
    return PROPORTIONAL_FORCE * q, 0.0, constant / rate


class LawCorners:
    """The corner cases as the torque model sees them (:class:`~springbalance.design.torque_model.TorqueModel`'s
    ``corners``): the cases' names, the adjuster variables, and each case's torque and potential change."""

    def __init__(self, spec: ToleranceSpec, springs: Sequence[Spring], corners: str) -> None:
        self.spec = spec
        self.springs = toleranced_springs(springs, spec)
        self.cases = corner_cases(self.springs, corners)
        if len(self.cases) - 1 > MAX_CORNERS:
            raise InputError(
                f"tolerance.corners: {corners!r} makes {len(self.cases) - 1} corner cases for "
                f"{len(self.springs)} toleranced springs (at most {MAX_CORNERS}); use 'strong_weak' or 'uniform'"
            )
        self.adjusters: dict[tuple[str, int], int] = {}

    @property
    def names(self) -> list[str]:
        return [case.name for case in self.cases]

    def declare(self, variables: Any) -> None:
        """Append the adjuster settings ``<spring>.adjuster[<corner>]`` [m] (one per spring and corner, start 0)
        to the design ``variables`` when the spec gives a travel."""
        travel = self.spec.adjuster_travel
        if travel is None:
            return
        for s, case in enumerate(self.cases[1:], start=1):
            for name in self.springs:
                self.adjusters[(name, s)] = variables.add(f"{name}.adjuster[{case.name}]", "m", -travel, travel, 0.0)

    def deviation(
        self, spring: Spring, context: Any, parameters: dict, points: dict, selectors: ca.SX, x: ca.SX
    ) -> tuple[Any, Any] | None:
        """``(δτ (nv), δV)``: the torque [N·m or N] and potential [J] a sample's case adds to ``spring``'s
        nominal share (None for a spring without a box). ``selectors``: 1 for the sample's case, else 0."""
        if spring.name not in self.springs:
            return None
        assert isinstance(spring, TwoPointSpring)  # only two-point springs have a box
        sign, rate, free, tension = law_symbols(spring, parameters)
        rho, f, lam = box_symbols(spring, parameters, rate, tension, self.spec)
        end_a, end_b = context.point(spring.a.body, points["a"]), context.point(spring.b.body, points["b"])
        d = end_b.position - end_a.position
        length = (d.T @ d) ** 0.5
        arm = end_b.generalized(d / length) - end_a.generalized(d / length)  # m_s = (J_b − J_a)^T u
        force, energy = ca.SX(0), ca.SX(0)
        nominal = sign * tension * (length - free) + 0.5 * rate * (length - free) ** 2
        for s, case in enumerate(self.cases):
            if not case.strengths:
                continue
            a, b, c = case.law_signs(str(spring.name), sign)
            index = self.adjusters.get((str(spring.name), s))
            shift = x[index] if index is not None else 0.0
            k2, l2, t2 = rate * (1 + a * rho), free + c * lam - shift, tension + b * f
            force = force + selectors[s] * (sign * b * f + k2 * (length - l2) - rate * (length - free))
            energy = energy + selectors[s] * (sign * t2 * (length - l2) + 0.5 * k2 * (length - l2) ** 2 - nominal)
        return force * arm, energy
