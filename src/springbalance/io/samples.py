"""Explicit workspace samples of a config: rows of joint values, or a ``.npy`` / ``.csv`` file of them.

A sample is one row of ``nv`` joint values [rad or m] in the mechanism's joint order (a ``.csv``
header of joint names may reorder the columns). Every problem is a
:class:`~springbalance.errors.ConfigError` naming the key path, the file and the line.
"""

from __future__ import annotations

import csv
import math
from pathlib import Path
from typing import Any

import numpy as np

from springbalance.errors import ConfigError
from springbalance.io.config_errors import one_line
from springbalance.model import budget
from springbalance.model.mechanism import Mechanism


def value_rows(mechanism: Mechanism, values: Any, where: str) -> np.ndarray:
    """The rows of ``values`` (a list of rows of nv numbers; a list of numbers when nv = 1) as an N×nv array."""
    shape = f"a list of rows of {mechanism.nv} numbers ({', '.join(mechanism.joint_names)})"
    if not isinstance(values, list) or not values:
        raise ConfigError(f"{where}: expected {shape}, got {values!r}")
    if mechanism.nv == 1 and all(_is_number(v) for v in values):
        return np.array(values, dtype=float)[:, None]
    for index, row in enumerate(values):
        if not isinstance(row, list) or len(row) != mechanism.nv or not all(_is_number(v) for v in row):
            raise ConfigError(
                f"{where}[{index}]: expected {mechanism.nv} numbers ({', '.join(mechanism.joint_names)}), got {row!r}"
            )
    return np.array(values, dtype=float)


def read_samples_file(mechanism: Mechanism, path: Path, where: str) -> np.ndarray:
    """Samples from ``.npy`` (N×nv array) or ``.csv`` (optional header of joint names)."""
    if not path.is_file():
        raise ConfigError(f"{where}: samples file {str(path)!r} does not exist")
    suffix = path.suffix.lower()
    per_byte = budget.NPY_BYTES_PER_BYTE if suffix == ".npy" else budget.CSV_BYTES_PER_BYTE
    budget.require(budget.file_bytes(path) * per_byte, f"{where}: reading samples file {str(path)!r}")
    if suffix == ".npy":
        return _read_npy(mechanism, path, where)
    if suffix != ".csv":
        raise ConfigError(f"{where}: samples file {str(path)!r} must end in .csv or .npy")
    try:
        lines = path.read_text(encoding="utf-8").splitlines()
    except (OSError, UnicodeDecodeError) as error:
        raise ConfigError(f"{where}: cannot read {str(path)!r}: {one_line(error)}") from None
    numbered = [
        (number, line)
        for number, line in enumerate(lines, start=1)
        if line.strip() and not line.lstrip().startswith("#")
    ]
    if not numbered:
        raise ConfigError(f"{where}: {str(path)!r} holds no samples")
    rows = list(csv.reader(line for _, line in numbered))
    columns, width = list(range(mechanism.nv)), mechanism.nv
    if not all(_parses_as_float(cell) for cell in rows[0]):
        names = [cell.strip() for cell in rows[0]]
        unknown = [name for name in names if name not in mechanism.joint_names]
        missing = [name for name in mechanism.joint_names if name not in names]
        if unknown or missing or len(names) != len(set(names)):
            raise ConfigError(
                f"{where}: header of {str(path)!r} must name each joint once "
                f"({', '.join(mechanism.joint_names)}), got {', '.join(names)}"
            )
        columns, width = [names.index(name) for name in mechanism.joint_names], len(names)
        rows, numbered = rows[1:], numbered[1:]
    values = []
    for (number, _), row in zip(numbered, rows):
        if len(row) != width:
            raise ConfigError(
                f"{where}: {str(path)!r} line {number}: expected {mechanism.nv} values "
                f"({', '.join(mechanism.joint_names)}), got {len(row)}"
            )
        try:
            numbers = [float(row[column]) for column in columns]
        except ValueError:
            raise ConfigError(f"{where}: {str(path)!r} line {number}: not a number in {row!r}") from None
        if not all(math.isfinite(v) for v in numbers):
            raise ConfigError(f"{where}: {str(path)!r} line {number}: values must be finite, got {row!r}")
        values.append(numbers)
    if not values:
        raise ConfigError(f"{where}: {str(path)!r} holds no samples")
    return np.array(values)


def _read_npy(mechanism: Mechanism, path: Path, where: str) -> np.ndarray:
    """Samples from a ``.npy`` array (N×nv; a 1-D array for a mechanism of one joint), finite numbers only."""
    try:
        values = np.load(path, allow_pickle=False)
    except (OSError, ValueError) as error:
        raise ConfigError(f"{where}: cannot read {str(path)!r} as a NumPy array: {one_line(error)}") from None
    if values.ndim == 1 and mechanism.nv == 1:
        values = values[:, None]
    try:
        values = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise ConfigError(f"{where}: {str(path)!r} does not hold numbers (dtype {values.dtype})") from None
    if not np.all(np.isfinite(values)):
        raise ConfigError(f"{where}: {str(path)!r} holds values that are not finite numbers")
    return values


def _is_number(value: Any) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _parses_as_float(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True
