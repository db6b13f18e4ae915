"""The per-sample functions compiled to C (:func:`compiled`), cached on disk by
:mod:`~springbalance.design.compile_cache`."""

from __future__ import annotations

import os
import shutil

import casadi as ca

from springbalance.design.block_kernel import SOURCE_ATTRIBUTE
from springbalance.design.compile_cache import compile_function


def compiler_available() -> bool:
    """True when a C compiler is on PATH, so CasADi can JIT-compile the per-sample functions."""
    return shutil.which(os.environ.get("CC", "gcc")) is not None or shutil.which("cc") is not None


def compiled(function: ca.Function) -> ca.Function:
    """``function`` compiled to C when a compiler is available (about 8× faster than CasADi's
    virtual machine for these functions), else ``function`` itself.

    The compiled library is cached on disk (:mod:`springbalance.design.compile_cache`): a second
    process on the same problem loads it without running the compiler. Set
    ``SPRINGBALANCE_JIT=0`` to disable compilation.

    The compiled function keeps ``function`` (an attribute): :class:`BlockEvaluator` and
    :class:`SampleEvaluator` build its block kernel from it when they evaluate it over
    :data:`~springbalance.design.block_kernel.KERNEL_MIN_SAMPLES` samples or more (:func:`~springbalance.design.block_kernel.block_kernel_code`).
    """
    if os.environ.get("SPRINGBALANCE_JIT", "1") == "0" or not compiler_available():
        return function
    try:
        result = compile_function(function)
    except RuntimeError:  # compiler present but unusable: stay on the virtual machine
        return function
    try:
        setattr(result, SOURCE_ATTRIBUTE, function)
    except AttributeError:
        pass
    return result
