r"""Bounded Levenberg–Marquardt on the normal equations, for many residuals and few variables.

Minimises :math:`\tfrac12 \|r(z)\|^2` subject to :math:`0 \le z \le 1`. Each iteration
forms :math:`H = J^T J` and :math:`g = J^T r` (n×n and n, cheap when rows ≫ n), frees the
variables that are not held at a bound by the gradient, and solves

.. math:: (H_{ff} + \lambda\,\mathrm{diag}(H_{ff}))\,\delta_f = -g_f ,

then projects ``z + δ`` onto the box. The damping λ follows Nielsen's update (gain ratio).
The damping is what lets the method walk the degenerate directions of the design problem
(a zero-free-length spring only sees ``k·a·b``): along an exactly flat direction the step
has no component, along a nearly flat one it stays short instead of diverging.

Stopping (scaled problems, where the cost at the start is O(1)):
- projected gradient below ``gtol``;
- the relative cost decrease over the last ``window`` accepted steps below ``ftol``
  (a flat valley: further crawling buys nothing measurable);
- ``max_iterations`` evaluations.
"""

from __future__ import annotations

import dataclasses

import numpy as np


@dataclasses.dataclass
class LmResult:
    z: np.ndarray
    cost: float
    iterations: int
    evaluations: int
    status: str


def levenberg_marquardt(evaluate, z0, max_iterations=200, ftol=1e-7, gtol=1e-10, window=5) -> LmResult:
    """``evaluate(z) -> (r, J)``; returns the bounded minimiser of ½|r|² on [0, 1]^n."""
    z = np.clip(np.asarray(z0, dtype=float), 0.0, 1.0)
    r, J = evaluate(z)
    cost = 0.5 * float(r @ r)
    n = z.size
    damping, growth = None, 2.0
    history = [cost]
    evaluations, status = 1, "iteration limit reached"
    for iteration in range(1, max_iterations + 1):
        gradient = J.T @ r
        hessian = J.T @ J
        held = ((z <= 0.0) & (gradient > 0)) | ((z >= 1.0) & (gradient < 0))
        free = ~held
        projected = np.where(free, gradient, 0.0)
        if np.max(np.abs(projected), initial=0.0) <= gtol * max(1.0, cost):
            status = "converged (gradient)"
            break
        diagonal = np.maximum(np.diag(hessian), 1e-12 * max(1.0, np.max(np.diag(hessian), initial=0.0)))
        if damping is None:
            damping = 1e-3
        step = np.zeros(n)
        hff = hessian[np.ix_(free, free)]
        try:
            step[free] = np.linalg.solve(hff + damping * np.diag(diagonal[free]), -gradient[free])
        except np.linalg.LinAlgError:
            damping *= growth
            growth *= 2.0
            continue
        z_trial = np.clip(z + step, 0.0, 1.0)
        actual_step = z_trial - z
        if not np.any(actual_step):
            status = "converged (step at bounds)"
            break
        r_trial, J_trial = evaluate(z_trial)
        evaluations += 1
        cost_trial = 0.5 * float(r_trial @ r_trial)
        predicted = -(gradient @ actual_step + 0.5 * actual_step @ hessian @ actual_step)
        gain = (cost - cost_trial) / predicted if predicted > 0 else -1.0
        if np.isfinite(cost_trial) and cost_trial < cost:
            z, r, J, cost = z_trial, r_trial, J_trial, cost_trial
            damping *= max(1.0 / 3.0, 1.0 - (2.0 * gain - 1.0) ** 3) if gain > 0 else 1.0
            growth = 2.0
            history.append(cost)
            if len(history) > window and history[-1 - window] - cost <= ftol * max(history[-1 - window], 1e-300):
                status = "converged (cost change)"
                break
        else:
            damping *= growth
            growth *= 2.0
            if damping > 1e16:
                status = "converged (no descent step)"
                break
    return LmResult(z, cost, iteration if max_iterations else 0, evaluations, status)
