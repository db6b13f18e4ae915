"""Numeric evaluation of a per-sample function over the workspace samples: all at once
(:class:`SampleEvaluator`) or block by block (:class:`BlockEvaluator`), into NumPy buffers."""

from __future__ import annotations

import ctypes
import queue
import threading
from typing import Iterator

import casadi as ca
import numpy as np

from springbalance.design.block_kernel import block_kernel
from springbalance.design.torque_model.threads import evaluation_threads


class _Outputs:
    """Output buffers of up to ``capacity`` samples, as the evaluators hand them out: output ``i``
    of per-sample shape ``(rows, cols)`` is an ``(n, cols, rows)`` array (a view of the raw
    nonzeros when dense, else a dense array the nonzeros are scattered into)."""

    def __init__(self, function: ca.Function, capacity: int) -> None:
        self.capacity = capacity
        self.raw: list[np.ndarray] = []
        self._shapes: list[tuple[int, int]] = []
        #: per output, None when dense, else (columns, rows, nonzeros) of its sparsity triplet
        self._sparse: list[tuple[np.ndarray, np.ndarray, int] | None] = []
        for i in range(function.n_out()):
            sparsity = function.sparsity_out(i)
            self.raw.append(np.zeros(sparsity.nnz() * capacity))
            self._shapes.append((sparsity.size2(), sparsity.size1()))
            if sparsity.is_dense():
                self._sparse.append(None)
            else:
                triplet_rows, triplet_cols = sparsity.get_triplet()
                self._sparse.append(
                    (np.array(triplet_cols, dtype=int), np.array(triplet_rows, dtype=int), sparsity.nnz())
                )
        self.addresses = (ctypes.c_void_p * max(len(self.raw), 1))(*[raw.ctypes.data for raw in self.raw])
        self._views: dict[int, list[np.ndarray]] = {}

    def views(self, n: int) -> list[np.ndarray]:
        """The outputs of the first ``n`` samples (sparse ones scattered from the raw nonzeros now)."""
        if n not in self._views:
            self._views[n] = [
                raw[: n * (sparse[2] if sparse else shape[0] * shape[1])].reshape(n, *shape)
                if sparse is None
                else np.zeros((n,) + shape)
                for raw, shape, sparse in zip(self.raw, self._shapes, self._sparse)
            ]
        outputs = self._views[n]
        for raw, sparse, out in zip(self.raw, self._sparse, outputs):
            if sparse is not None and sparse[2]:
                cols, rows, nnz = sparse
                out[:, cols, rows] = raw[: n * nnz].reshape(n, nnz)
        return outputs


class SampleEvaluator:
    """Fast numeric evaluation of a per-sample function over fixed sample data.

    Wraps ``function(x, data) -> outputs`` mapped over the N data columns with ``x``
    shared, and evaluates into preallocated NumPy arrays. An output of per-sample shape
    ``(rows, cols)`` comes back as an array ``(N, cols, rows)`` — the per-sample *transpose*,
    which is CasADi's column-major memory read row-major (a view, no copy, for dense outputs).

    When ``function`` comes from :func:`compiled` and there are :data:`~springbalance.design.block_kernel.KERNEL_MIN_SAMPLES` samples
    or more, its block kernel (:func:`~springbalance.design.block_kernel.block_kernel`; ``kernel=False``: never, ``True``: whatever the
    number of samples) evaluates them, 4 at once, bit for bit CasADi's numbers, reading ``x``
    once. Otherwise the map is CasADi's plain
    serial ``Map`` through its zero-copy buffer interface, which reads each sample's inputs in
    place; ``x`` is then repeated once per sample here (N·n_x numbers). A map with ``x`` as a
    shared ("reduced") input would wrap it in an MX function whose work vector copies the data,
    the repeated ``x`` and the outputs on every call: about twice the memory, and slower.
    """

    def __init__(self, function: ca.Function, data: np.ndarray, kernel: bool | None = None) -> None:
        n = data.shape[1]
        self.n_samples = n
        self.function = function
        self._kernel = None if kernel is False else block_kernel(function, n if kernel is None else None)
        self._data = np.asfortranarray(data).reshape(-1, order="F")  # a view of Fortran-ordered data, no copy
        self._buffers = _Outputs(function, n)
        if self._kernel is not None:
            return
        self._x = np.zeros((n, function.nnz_in(0)))  # row i: the x of sample i (all equal)
        self._buffer, self._trigger = function.map(n, "serial").buffer()
        # casadi's stub asks for a size the SWIG wrapper takes from the buffer, and numpy's stub lacks __buffer__
        self._buffer.set_arg(0, memoryview(self._x.reshape(-1)))  # type: ignore[call-arg, arg-type]
        self._buffer.set_arg(1, memoryview(self._data))  # type: ignore[call-arg, arg-type]
        for i, raw in enumerate(self._buffers.raw):
            self._buffer.set_res(i, memoryview(raw))  # type: ignore[call-arg, arg-type]

    def rebind(self, data: np.ndarray) -> None:
        """Evaluate on other data columns from now on: ``data`` holds ``n_samples`` columns, flat in
        Fortran order (a view, kept alive here)."""
        if data.size != self._data.size:
            raise ValueError(f"{data.size} data values, the evaluator reads {self._data.size}")
        self._data = data
        if self._kernel is None:
            self._buffer.set_arg(1, memoryview(self._data))  # type: ignore[call-arg, arg-type]  # as in __init__

    def __call__(self, x: np.ndarray) -> list[np.ndarray]:
        if self._kernel is not None:
            data = np.ascontiguousarray(self._data)
            self._kernel(self._kernel.shared_input(x), data.ctypes.data, self.n_samples, self._buffers.addresses)
        else:
            self._x[:] = x
            self._trigger()
        return self._buffers.views(self.n_samples)


#: a block of samples of :class:`BlockEvaluator` holds at most about this many bytes of outputs (two
#: such buffers stay in a 2-core machine's last-level cache; fewer, larger blocks cost less Python per pass)
BLOCK_BYTES = 2 * 1024 * 1024


class BlockEvaluator:
    """A per-sample function evaluated over the samples block by block, into buffers of one block.

    ``blocks(x)`` yields ``(start, stop, outputs)`` for consecutive blocks of samples; ``outputs``
    are as :class:`SampleEvaluator`'s for the block's samples and are overwritten by the next block.
    The sample data is read in place (no copy when it is in Fortran order, as
    :meth:`TorqueModel.data_matrix` makes it), and the outputs never exist for all samples at
    once: a caller that reduces each block (``JᵀJ``, ``Jᵀr``) needs memory for one block only.

    With a block kernel (as :class:`SampleEvaluator`) and 2 threads (:func:`evaluation_threads`),
    a helper thread evaluates block k+1 while the caller reduces block k (the kernel runs without
    the GIL, NumPy's BLAS too): the two buffers alternate, and each block's outputs are the same
    numbers, handed out in the same order, as with one thread.

    Args:
        block: samples per block; default: blocks of equal size (to a sample) whose outputs take at
            most about :data:`BLOCK_BYTES`.
        kernel: use the block kernel: None (default) from :data:`~springbalance.design.block_kernel.KERNEL_MIN_SAMPLES` samples on,
            False never (CasADi's map), True whenever ``function`` has one.
    """

    def __init__(
        self, function: ca.Function, data: np.ndarray, block: int | None = None, kernel: bool | None = None
    ) -> None:
        self.function = function
        self.n_samples = n = data.shape[1]
        self._rows = data.shape[0]
        self._data = np.asfortranarray(data).reshape(-1, order="F")
        if block is None:
            per_sample = 8 * max(sum(function.sparsity_out(i).nnz() for i in range(function.n_out())), 1)
            largest = max(BLOCK_BYTES // per_sample, 32)
            block = -(-n // -(-n // largest))  # ceil(n / ceil(n / largest)): the blocks share the samples evenly
        self.block = int(max(1, min(block, n)))
        self._parts: dict[int, SampleEvaluator] = {}
        self._kernel = None if kernel is False else block_kernel(function, n if kernel is None else None)
        self._buffers: list[_Outputs] = []

    def _part(self, size: int) -> SampleEvaluator:
        if size not in self._parts:
            self._parts[size] = SampleEvaluator(
                self.function, self._data[: size * self._rows].reshape(self._rows, size, order="F"), kernel=False
            )
        return self._parts[size]

    def _slot(self, index: int) -> _Outputs:
        while len(self._buffers) <= index:
            self._buffers.append(_Outputs(self.function, self.block))
        return self._buffers[index]

    def blocks(self, x: np.ndarray) -> Iterator[tuple[int, int, list[np.ndarray]]]:
        """``(start, stop, outputs)`` of each block of samples, in order."""
        spans = [(start, min(start + self.block, self.n_samples)) for start in range(0, self.n_samples, self.block)]
        if self._kernel is None:
            for start, stop in spans:
                part = self._part(stop - start)
                part.rebind(self._data[start * self._rows : stop * self._rows])
                yield start, stop, part(x)
            return
        x = self._kernel.shared_input(x)  # a copy: the helper thread reads it while the caller goes on
        if len(spans) < 2 or evaluation_threads() < 2:
            slot = self._slot(0)
            for start, stop in spans:
                self._evaluate(x, start, stop, slot)
                yield start, stop, slot.views(stop - start)
            return
        yield from self._pipelined(x, spans)

    def _evaluate(self, x: np.ndarray, start: int, stop: int, slot: _Outputs) -> None:
        kernel = self._kernel
        assert kernel is not None  # only the kernel's path evaluates block by block into slots
        kernel(x, self._data.ctypes.data + 8 * start * self._rows, stop - start, slot.addresses)

    def _pipelined(self, x: np.ndarray, spans: list[tuple[int, int]]) -> Iterator[tuple[int, int, list[np.ndarray]]]:
        """The blocks with a helper thread one block ahead (two buffers; each reply is the helper's
        error or None)."""
        slots = (self._slot(0), self._slot(1))
        requests: queue.SimpleQueue[int | None] = queue.SimpleQueue()
        replies: queue.SimpleQueue[BaseException | None] = queue.SimpleQueue()

        def helper() -> None:
            while True:
                index = requests.get()
                if index is None:
                    return
                try:
                    self._evaluate(x, *spans[index], slots[index % 2])
                    replies.put(None)
                except BaseException as error:  # handed to the caller's thread
                    replies.put(error)

        thread = threading.Thread(target=helper, name="springbalance-blocks", daemon=True)
        thread.start()
        try:
            requests.put(1)
            self._evaluate(x, *spans[0], slots[0])
            for index, (start, stop) in enumerate(spans):
                if index:
                    error = replies.get()
                    if error is not None:
                        raise error
                    if index + 1 < len(spans):  # the caller is done with the other buffer (block index - 1)
                        requests.put(index + 1)
                yield start, stop, slots[index % 2].views(stop - start)
        finally:
            requests.put(None)
            thread.join()

    def evaluate(self, x: np.ndarray) -> list[np.ndarray]:
        """Every output for all samples, ``(N, cols, rows)`` arrays as :class:`SampleEvaluator`'s (new arrays)."""
        full: list[np.ndarray] | None = None
        for start, stop, outputs in self.blocks(x):
            if full is None:
                full = [np.empty((self.n_samples,) + out.shape[1:]) for out in outputs]
            for whole, out in zip(full, outputs):
                whole[start:stop] = out
        if full is None:
            raise ValueError("no samples to evaluate")
        return full
