"""How an NLP's cost and rows depend on the per-sample outputs ``Y = [y_1 … y_N]`` (``m`` outputs per sample) and on
its variables: the structural facts :class:`~springbalance.design.structured_nlp.StructuredNlp` relies on
(docs/model.md §6, "How IPOPT sees the NLP")."""

from __future__ import annotations

from typing import NamedTuple

import casadi as ca
import numpy as np


def samples_of(expression: ca.MX, outputs: ca.MX, m: int) -> np.ndarray:
    """The samples (sorted indices) whose outputs ``expression`` depends on structurally (``outputs``: vec(Y))."""
    used = ca.jacobian(expression, outputs).sparsity().get_col()
    return np.unique(np.asarray(used, dtype=int) // m) if len(used) else np.zeros(0, dtype=int)


def diagonal_curvature(expression: ca.MX, outputs: ca.MX, m: int) -> np.ndarray | None:
    """When ``∂²(λᵀ expression)/∂Y²`` (the cost and the rows, any weights ``λ``; ``Y``: the per-sample
    ``outputs``, ``m`` per sample) is diagonal, the outputs ``k`` of a sample (0 ≤ k < m) where its
    diagonal has entries (none when ``expression`` is linear in ``Y``); else None."""
    weights = ca.MX.sym("lambda", expression.numel())
    gradient = ca.gradient(ca.dot(weights, expression), outputs)
    if not ca.depends_on(gradient, outputs):
        return np.zeros(0, dtype=int)
    rows, columns = ca.jacobian_sparsity(gradient, outputs).get_triplet()
    if rows != columns:
        return None
    return np.array(sorted({row % m for row in rows}), dtype=int)


def linear_in(expression: ca.MX, variables: ca.MX) -> bool:
    """Whether ``expression`` is (structurally) linear in ``variables``."""
    if variables.numel() == 0:
        return True
    second = ca.jacobian(ca.jacobian(expression, variables), variables)
    return second.nnz() == 0 or bool(second.is_zero())


def affine_in(expression: ca.MX, outputs: ca.MX, variables: ca.MX) -> bool:
    """Whether ``expression`` is (structurally) affine in ``outputs`` and ``variables`` together: its gradient along
    any weights depends on neither (cheap: one reverse sweep, where a Jacobian's dependence would take seconds)."""
    weights = ca.MX.sym("lambda", expression.numel())
    weighted = ca.dot(weights, expression)
    gradients = (ca.gradient(weighted, outputs), ca.gradient(weighted, variables))
    return not any(ca.depends_on(gradient, symbols) for gradient in gradients for symbols in (outputs, variables))


def row_structure(rows: ca.MX, outputs: ca.MX, variables: ca.MX, m: int) -> tuple[np.ndarray, tuple | None]:
    """``(first, jacobians)`` of ``rows`` (expressions of ``outputs`` = vec(Y), ``m`` per sample, and of
    ``variables``): the first sample each row depends on (the number of samples for a row of no sample: linear, or of
    the extras only) and, when every row is affine in both (epigraphs, coil and clearance rows), their Jacobians
    ``(∂g/∂Y, ∂g/∂w)`` as constant sparse matrices (else None)."""
    jacobian = ca.jacobian(rows, outputs)
    rows_of, columns_of = jacobian.sparsity().get_triplet()
    first = np.full(rows.numel(), outputs.numel() // m)
    np.minimum.at(first, np.asarray(rows_of, dtype=int), np.asarray(columns_of, dtype=int) // m)
    if not affine_in(rows, outputs, variables):
        return first, None
    constants = ca.Function("row_jacobians", [outputs, variables], [jacobian, ca.jacobian(rows, variables)])(0, 0)
    return first, tuple(constants)


class RestrictedNlp(NamedTuple):
    """The NLP restricted to a working set of rows, as functions of ``(Y_local, w)``: ``Y_local`` the outputs of
    ``samples`` (the samples the cost or the rows use) or of ``row_samples`` (those the rows use), in order."""

    samples: np.ndarray
    row_samples: np.ndarray
    #: the rows in the set
    n_g: int
    #: ``f`` and ``g`` linear in the outputs
    linear: bool
    #: ``∂²L/∂Y²`` diagonal (and not zero)
    diagonal: bool
    #: ``(Y, w) → f``
    cost: ca.Function
    #: ``(Y, w) → (f, ∂f/∂Y, ∂f/∂w)``
    cost_gradient: ca.Function
    #: ``(Y_rows, w) → g``
    rows: ca.Function
    #: ``(Y_rows, w) → (g, (∂g/∂Y_rows)ᵀ, ∂g/∂w)``
    rows_jacobian: ca.Function
    #: ``(Y, w, λ_f, λ_g[, Jᵀ]) → (ȳ = ∂L/∂Y, the curvature or the Gauss–Newton-like term)``
    hessian: ca.Function
