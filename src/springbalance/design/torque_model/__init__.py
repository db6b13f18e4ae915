r"""Residual torque as a CasADi function of the design variables only.

Pinocchio stays numeric: for each workspace sample the :class:`~springbalance.model.kinematics.WorkspaceKinematics`
cache supplies ``g(q)``, ``V_g(q)`` and, for every moving body that carries a spring end,
its placement ``(R, t)`` and Jacobian ``J`` (LOCAL_WORLD_ALIGNED); the workspace supplies
the coordinates ``q_i`` of the joints that carry torsional springs. These numbers form the
*sample data* column. For a fixed sample each spring end is affine in its anchor
coordinates (docs/model.md §2):

.. math::
    r = R\,p,\quad x = t + r,\quad J_p^T f = J_{lin}^T f + J_{ang}^T (r \times f),

so the per-sample CasADi function ``sample(x, data) -> (tau, V, L, F, C)`` is small and exact,
and ``sample.map(N)`` evaluates it over the workspace with exact derivatives. Each spring
element (:class:`~springbalance.springs.laws.Spring`) adds its own share through
:meth:`~springbalance.springs.Spring.contribution`, given a :class:`SampleContext`:

.. math:: \tau = g + \sum_s \tau_s,\qquad V = V_g + \sum_s V_s,

with :math:`\tau_s = F_s(L_s)\,(J_{p_b} - J_{p_a})^T u_s` (plus the weight of the spring's
own mass) for a two-point spring and :math:`\tau_s = (k (q_i - q_0) + \tau_0)\, e_i` for a
torsional spring.

Scenarios (:mod:`springbalance.design.scenarios`): the samples of S load cases are stacked, and the data
column ends with S selectors (1 for the sample's scenario, else 0). A per-scenario variable has S
copies in ``x``; the springs see :math:`\sum_s \mathrm{sel}_s\, x_{copy_s}`, i.e. their own
scenario's copy. Without scenarios nothing is added.

Outputs per sample: ``tau`` (nv) [N·m or N], ``V`` (1) [J], spring states ``L`` (n_s: length
[m] or joint angle [rad]), generalised forces ``F`` (n_s: tension [N] or torque [N·m]), and
the constraint rows ``C`` (≥ 0 when feasible): the springs' practical constraints, then, with
``joint_limits`` (``no_joint_worse``), one row :math:`(P_j^2 - \tau_j^2)/P_j` per limited joint, and
with ``max_spring_mass`` one row :math:`M - \sum_s m_s` [kg] that depends on no sample.

The modules, one concept each: :mod:`~springbalance.design.torque_model.model` (:class:`TorqueModel`, the
per-sample symbolic model), :mod:`~springbalance.design.torque_model.variables` (the design vector and the
constraint rows' bookkeeping), :mod:`~springbalance.design.torque_model.context` (what a spring element sees
of one sample), :mod:`~springbalance.design.torque_model.evaluators` (numeric evaluation over the samples,
block by block), :mod:`~springbalance.design.torque_model.compilation` (C compilation) and
:mod:`~springbalance.design.torque_model.threads` (threads of a block pass). This package re-exports their
public names.
"""

from __future__ import annotations

from springbalance.design.torque_model.compilation import compiled, compiler_available
from springbalance.design.torque_model.context import PointKinematics, SampleContext
from springbalance.design.torque_model.evaluators import BLOCK_BYTES, BlockEvaluator, SampleEvaluator
from springbalance.design.torque_model.model import TorqueModel
from springbalance.design.torque_model.threads import (
    THREADS_ENV,
    count_from_environment,
    evaluation_threads,
    one_thread,
    use_one_thread,
)
from springbalance.design.torque_model.variables import ConstraintBlock, DesignVariables

__all__ = [
    "BLOCK_BYTES",
    "THREADS_ENV",
    "BlockEvaluator",
    "ConstraintBlock",
    "DesignVariables",
    "PointKinematics",
    "SampleContext",
    "SampleEvaluator",
    "TorqueModel",
    "compiled",
    "compiler_available",
    "count_from_environment",
    "evaluation_threads",
    "one_thread",
    "use_one_thread",
]
