"""springbalance: design gravity-balancing springs for robot arms described by URDF.

Data flows one way: :class:`Mechanism` → :class:`Workspace` → springs →
:class:`DesignProblem` → solve → :class:`DesignResult` → report.
"""

from .errors import ConfigError, InputError, SolverError, SpringBalanceError
from .mechanism import GROUND, Joint, Mechanism
from .objectives import OBJECTIVES
from .params import Anchor, Free, Plane, Segment
from .problem import DesignProblem, Evaluation
from .result import DesignResult
from .sizing import MATERIALS, Helical, HelicalDesign, Material, size_helical_spring
from .springs import (CoilMass, CompressionSpring, ConstantForceSpring, ExtensionSpring, GasSpring, Spring,
                      TorsionalSpring, TwoPointSpring, ZeroFreeLengthSpring)
from .workspace import Coupling, Workspace

__version__ = "0.1.0"

__all__ = [
    "Anchor", "CoilMass", "CompressionSpring", "ConfigError", "ConstantForceSpring", "Coupling", "DesignProblem",
    "DesignResult", "Evaluation", "ExtensionSpring", "Free", "GROUND", "GasSpring", "Helical", "HelicalDesign",
    "InputError", "Joint", "MATERIALS", "Material", "Mechanism", "OBJECTIVES", "Plane", "Segment", "SolverError",
    "Spring", "SpringBalanceError", "TorsionalSpring", "TwoPointSpring", "Workspace", "ZeroFreeLengthSpring",
    "size_helical_spring",
]
