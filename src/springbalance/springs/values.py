"""What the spring laws and constraints compute with: numbers, NumPy arrays or CasADi expressions.

The laws are written with plain arithmetic, so one implementation serves CasADi symbols (inside the
optimiser) and NumPy arrays (checks, reports); these aliases name such values in the signatures.
"""

from __future__ import annotations

from typing import Any, Mapping, TypeVar, Union

import casadi as ca
import numpy as np

#: a number, a NumPy array (one entry per workspace sample) or a CasADi expression
Value = Union[float, np.ndarray, ca.SX, ca.MX, ca.DM]
#: one of those kinds, the same for every argument and the result of one call (CasADi does not mix
#: SX and MX); plain numbers (material constants) combine with any of them
ValueT = TypeVar("ValueT", float, np.ndarray, ca.SX, ca.MX, ca.DM)
#: parameter name -> its value: a number, or the expression of its design variable
Parameters = Mapping[str, Any]
