"""Block kernels: the per-sample function evaluated for 4 samples at once, one per lane of a vector.

CasADi's generated C evaluates one sample per call. :func:`block_kernel_code` writes, from the
function's instruction list (after ``cse`` merges repeated subexpressions), C that does the same
operations in the same order on 4-double vectors (GCC vector extensions), so that each lane gives
bit for bit CasADi's result; instructions that depend only on the shared input (the design
variables: scaling, constants) run once per call instead of once per sample. An operation the
kernel does not know makes :func:`block_kernel` return None, and the evaluators keep CasADi's map.

The kernel is compiled into a second, small library in the disk cache of
:mod:`~springbalance.design.compile_cache` (same key scheme), and called through ctypes, which
releases the GIL: :class:`~springbalance.design.torque_model.BlockEvaluator` evaluates the next block
in a helper thread while the caller sums the previous one.
"""

from __future__ import annotations

import ctypes
from _ctypes import CFuncPtr
from typing import Literal, cast

import casadi as ca
import numpy as np
import numpy.typing as npt

from springbalance.design.compile_cache import load_or_build

#: samples a block kernel evaluates at once (a vector of 4 doubles: one AVX register; SSE2 uses two)
KERNEL_LANES = 4
#: the evaluators build a block kernel (a second, small compilation, cached like the first) for
#: this many samples or more; below, CasADi's map (a kernel would not pay for its compiler time)
KERNEL_MIN_SAMPLES = 2048
SOURCE_ATTRIBUTE = "_springbalance_source"
_KERNEL_SUFFIX = "_block"

_OPERATIONS = {getattr(ca, name): name[3:] for name in dir(ca) if name.startswith("OP_")}
#: operations done on whole vectors: the same IEEE operation in each lane as CasADi's C code does
_VECTOR = {
    "ADD": "({0}+{1})",
    "SUB": "({0}-{1})",
    "MUL": "({0}*{1})",
    "DIV": "({0}/{1})",
    "NEG": "(-{0})",
    "TWICE": "(2.*{0})",
    "SQ": "({0}*{0})",
    "INV": "(1./{0})",
}
#: operations done lane by lane with CasADi's own C expression (its helper functions, such as
#: ``casadi_fmin``, are copied into the kernel's file: :data:`_HELPERS`)
_LANEWISE = {
    "EXP": "exp({0})",
    "LOG": "log({0})",
    "POW": "pow({0},{1})",
    "CONSTPOW": "pow({0},{1})",
    "SQRT": "sqrt({0})",
    "SIN": "sin({0})",
    "COS": "cos({0})",
    "TAN": "tan({0})",
    "ASIN": "asin({0})",
    "ACOS": "acos({0})",
    "ATAN": "atan({0})",
    "SINH": "sinh({0})",
    "COSH": "cosh({0})",
    "TANH": "tanh({0})",
    "ASINH": "asinh({0})",
    "ACOSH": "acosh({0})",
    "ATANH": "atanh({0})",
    "FLOOR": "floor({0})",
    "CEIL": "ceil({0})",
    "FMOD": "fmod({0},{1})",
    "FABS": "casadi_fabs({0})",
    "SIGN": "casadi_sign({0})",
    "COPYSIGN": "copysign({0},{1})",
    "IF_ELSE_ZERO": "({0}?{1}:0)",
    "LT": "({0}<{1})",
    "LE": "({0}<={1})",
    "EQ": "({0}=={1})",
    "NE": "({0}!={1})",
    "NOT": "(!{0})",
    "AND": "({0}&&{1})",
    "OR": "({0}||{1})",
    "FMIN": "casadi_fmin({0},{1})",
    "FMAX": "casadi_fmax({0},{1})",
    "ERF": "erf({0})",
    "ATAN2": "atan2({0},{1})",
    "HYPOT": "casadi_hypot({0},{1})",
    "LOG1P": "casadi_log1p({0})",
    "EXPM1": "casadi_expm1({0})",
    "REMAINDER": "remainder({0},{1})",
}
#: CasADi's helper functions (as its code generator writes them) that the lane-wise expressions call
_HELPERS = {
    "casadi_fabs": "x>0 ? x : -x;|fabs(x);",
    "casadi_fmin": "x<y ? x : y;|fmin(x, y);",
    "casadi_fmax": "x>y ? x : y;|fmax(x, y);",
    "casadi_hypot": "sqrt(x*x+y*y);|hypot(x, y);",
    "casadi_log1p": "log(1+x);|log1p(x);",
    "casadi_expm1": "exp(x)-1;|expm1(x);",
}


class Unsupported(ValueError):
    """A function the block kernel cannot evaluate (the evaluators then keep CasADi's map)."""


def _helper_code(helper: str) -> str:
    if helper == "casadi_sign":
        return "static double casadi_sign(double x) { return x<0 ? -1 : x>0 ? 1 : x;}"
    old, new = _HELPERS[helper].split("|")
    arguments = "double x, double y" if "y" in new else "double x"
    return (
        f"static double {helper}({arguments}) {{\n#if __STDC_VERSION__ < 199901L\n  return {old}\n"
        f"#else\n  return {new}\n#endif\n}}"
    )


def _kernel_source(function: ca.Function) -> ca.Function:
    """The SX function the kernel is generated from: ``function`` with common subexpressions merged
    (the same operations on the same operands, so the same numbers), when CasADi can."""
    if not isinstance(function, ca.Function) or not function.is_a("SXFunction"):
        raise Unsupported("not an SX function")
    if function.n_in() != 2 or any(
        not function.sparsity_in(i).is_dense() or function.size2_in(i) != 1 for i in range(2)
    ):
        raise Unsupported("not a function f(x, data) of two dense vectors")
    if function.has_free():
        raise Unsupported("free variables")
    try:
        arguments = function.sx_in()
        return ca.Function(
            function.name(), arguments, function.call(arguments), function.name_in(), function.name_out(), {"cse": True}
        )
    except RuntimeError:  # a CasADi without the option: the function as it is
        return function


def _literal(value: float) -> str:
    value = float(value)
    if value != value:
        return "NAN"
    if value in (float("inf"), float("-inf")):
        return "INFINITY" if value > 0 else "(-INFINITY)"
    return repr(value)  # the shortest decimal that reads back as the same double


def block_kernel_code(function: ca.Function, name: str | None = None, lanes: int = KERNEL_LANES) -> str:
    """C code of ``<name>_block``: ``function(x, data)`` evaluated over ``n`` data columns.

    ``int <name>_block(const double *x, const double *data, long long n, long long ds, double **res)``
    reads the ``n`` columns of ``data`` (``ds`` numbers each, one after the other: Fortran order)
    and writes output ``i`` of sample ``s`` to ``res[i] + s * nnz_i`` (its nonzeros, as CasADi
    orders them): the layout of ``function.map(n, "serial")``'s outputs.

    The code evaluates ``lanes`` samples at once, one per lane of a vector of doubles (GCC/Clang
    vector extensions), with the operations of CasADi's C code in the same order: each lane
    computes what CasADi's code computes for its sample, bit for bit (IEEE +, -, ×, ÷ are exact
    per lane, the functions of ``math.h`` are called lane by lane, and the cache's flags forbid
    fused multiply-adds). The operations that depend on ``x`` only (the scaling of the design
    variables, constants) are done once per call, not once per sample. Without the vector
    extensions (another compiler) the code is left out and the evaluators use CasADi's map.

    Raises:
        Unsupported: ``function`` is not an SX function ``f(x, data)`` of two dense
            vectors, or uses an operation the kernel lacks.
    """
    source = _kernel_source(function)
    if not source.n_out():
        raise Unsupported("no outputs")
    name = name or function.name()
    sizes = [source.nnz_out(i) for i in range(source.n_out())]
    shared: list[str] = []  # x-only statements
    body: list[str] = []  # per-sample statements
    used: dict[str, int] = {}  # x-only values the body reads -> their slot in h
    kind: dict[int, tuple[bool, str]] = {}  # work index -> (is_vector, C name)
    names = iter(range(1, 10**9))

    def operand(work: int) -> str:
        vector, symbol = kind[work]
        if vector:
            return symbol
        if symbol not in used:
            used[symbol] = len(used)
        return f"h[{used[symbol]}]"

    for k in range(source.n_instructions()):
        operation = _OPERATIONS.get(source.instruction_id(k), "?")
        inputs, outputs = source.instruction_input(k), source.instruction_output(k)
        if operation == "OUTPUT":
            i, nz = outputs
            value = operand(inputs[0])
            body += [f"r{i}[{lane * sizes[i] + nz}] = {value}[{lane}];" for lane in range(lanes)]
            continue
        target = outputs[0]
        if operation == "CONST":
            symbol = f"s{next(names)}"
            shared.append(f"const double {symbol} = {_literal(source.instruction_constant(k))};")
            kind[target] = (False, symbol)
        elif operation == "INPUT":
            i, nz = inputs
            if i == 0:
                symbol = f"s{next(names)}"
                shared.append(f"const double {symbol} = x[{nz}];")
                kind[target] = (False, symbol)
            else:
                symbol = f"v{next(names)}"
                body.append(f"const vd {symbol} = {{{', '.join(f'd[{lane}*ds+{nz}]' for lane in range(lanes))}}};")
                kind[target] = (True, symbol)
        elif operation in _VECTOR or operation in _LANEWISE:
            template = _VECTOR.get(operation) or _LANEWISE[operation]
            if not any(kind[w][0] for w in inputs):  # x only: once per call
                symbol = f"s{next(names)}"
                shared.append(f"const double {symbol} = {template.format(*[kind[w][1] for w in inputs])};")
                kind[target] = (False, symbol)
            elif operation in _VECTOR:
                symbol = f"v{next(names)}"
                body.append(f"const vd {symbol} = {template.format(*[operand(w) for w in inputs])};")
                kind[target] = (True, symbol)
            else:
                symbol = f"v{next(names)}"
                lanes_of = [f"{operand(w)}[l]" for w in inputs]
                body.append(
                    f"vd {symbol}; for (int l = 0; l < {lanes}; ++l) {symbol}[l] = {template.format(*lanes_of)};"
                )
                kind[target] = (True, symbol)
        else:
            raise Unsupported(f"operation {operation} in the block kernel")

    results = ", ".join(f"double *restrict r{i}" for i in range(len(sizes)))
    offsets = ", ".join(f"res[{i}] + s * {size}" for i, size in enumerate(sizes))
    code_so_far = "\n".join(body + shared)
    helpers = [_helper_code(helper) for helper in (*_HELPERS, "casadi_sign") if f"{helper}(" in code_so_far]
    lines = [
        f"/* {name}_block: {name} over n samples, {lanes} at once (springbalance.design.torque_model) */",
        "#include <math.h>",
        "#if defined(_WIN32) || defined(__WIN32__) || defined(__CYGWIN__)",
        "#define SPRINGBALANCE_EXPORT __declspec(dllexport)",
        "#else",
        "#define SPRINGBALANCE_EXPORT",
        "#endif",
        "#if defined(__GNUC__) || defined(__clang__)",
        *helpers,
        f"typedef double {name}_vd __attribute__((vector_size({8 * lanes})));",
        f"#define vd {name}_vd",
        f"static __attribute__((noinline)) void {name}_lanes(const vd *restrict h, const double *restrict d, "
        f"long long ds, {results}) {{",
        *("  " + line for line in body),
        "}",
        f"SPRINGBALANCE_EXPORT int {name}{_KERNEL_SUFFIX}(const double *x, const double *d, long long n, "
        f"long long ds, double **res) {{",
        f"  vd h[{max(len(used), 1)}];",
        "  long long s = 0;",
        *("  " + line for line in shared),
        *(f"  h[{index}] = (vd){{0}} + {symbol};" for symbol, index in used.items()),
        f"  for (; s + {lanes} <= n; s += {lanes}) {name}_lanes(h, d + s * ds, ds, {offsets});",
        "  if (s < n) {   /* the last samples: padded with copies of the last one */",
        f"    double pad[{lanes} * ds];",
        *(f"    double t{i}[{lanes * max(size, 1)}];" for i, size in enumerate(sizes)),
        f"    for (int l = 0; l < {lanes}; ++l) for (long long j = 0; j < ds; ++j) "
        "pad[l * ds + j] = d[(s + l < n ? s + l : n - 1) * ds + j];",
        f"    {name}_lanes(h, pad, ds, {', '.join(f't{i}' for i in range(len(sizes)))});",
        *(
            f"    for (long long j = 0; j < (n - s) * {size}; ++j) res[{i}][s * {size} + j] = t{i}[j];"
            for i, size in enumerate(sizes)
            if size
        ),
        "  }",
        "  return 0;",
        "}",
        "#undef vd",
        "#endif",
        "",
    ]
    return "\n".join(lines)


def _compile_kernel(function: ca.Function) -> _BlockKernel | None:
    """The block kernel of ``function``, compiled or loaded from the disk cache
    (:func:`~springbalance.design.compile_cache.load_or_build`); None when there is none (an operation
    it lacks, no compiler, a compiler without vector extensions)."""
    try:
        code = block_kernel_code(function)
    except Unsupported:
        return None
    try:
        return load_or_build(
            code, f"{function.name()}{_KERNEL_SUFFIX}", lambda library: _load_kernel(function, library)
        )
    except RuntimeError:  # no compiler, or it refuses the code
        return None


def _load_kernel(function: ca.Function, library: str) -> _BlockKernel | None:
    try:
        return _BlockKernel(getattr(ctypes.CDLL(library), function.name() + _KERNEL_SUFFIX), function)
    except (OSError, AttributeError):  # not a usable library, or no kernel in it (no vector extensions)
        return None


class _BlockKernel:
    """A compiled block kernel, called through ctypes (which releases the GIL for the call)."""

    def __init__(self, entry: CFuncPtr, function: ca.Function):
        entry.restype = ctypes.c_int
        entry.argtypes = [ctypes.c_void_p, ctypes.c_void_p, ctypes.c_longlong, ctypes.c_longlong, ctypes.c_void_p]
        self.entry = entry
        self.n_x = function.nnz_in(0)
        self.data_rows = function.nnz_in(1)
        self.sizes = [function.nnz_out(i) for i in range(function.n_out())]

    def __call__(self, x: np.ndarray, data_address: int, n: int, results: ctypes.Array[ctypes.c_void_p]) -> None:
        """Evaluate ``n`` samples whose data start at ``data_address`` into ``results`` (a ctypes
        array of the output addresses). ``x``: float64, contiguous, ``n_x`` values."""
        if n > 0:
            self.entry(x.ctypes.data, data_address, n, self.data_rows, results)

    def shared_input(self, x: npt.ArrayLike) -> np.ndarray:
        """``x`` as the kernel reads it (broadcast like an assignment to an ``n_x`` vector, a new array)."""
        values = np.asarray(x, dtype=float)
        if values.size == self.n_x:
            return values.reshape(-1).copy()
        return np.array(np.broadcast_to(values, (self.n_x,)))


def block_kernel(function: ca.Function, n_samples: int | None = None) -> _BlockKernel | None:
    """The block kernel of a function from :func:`compiled` (built when first asked for), or None:
    for another function, or fewer than :data:`KERNEL_MIN_SAMPLES` samples."""
    source = getattr(function, SOURCE_ATTRIBUTE, None)
    if source is None or (n_samples is not None and n_samples < KERNEL_MIN_SAMPLES):
        return None
    # what an earlier call stored on the function (None: it has no kernel), False before the first call
    kernel = cast("_BlockKernel | None | Literal[False]", getattr(function, "_springbalance_kernel", False))
    if kernel is False:
        kernel = _compile_kernel(source)
        try:
            setattr(function, "_springbalance_kernel", kernel)  # noqa: B010  (casadi.Function declares no such attribute)
        except AttributeError:
            pass
    return kernel
