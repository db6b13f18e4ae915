"""springbalance: design gravity-balancing springs for robot arms described by URDF.

Data flows one way: :class:`Mechanism` → :class:`Workspace` → springs →
:class:`DesignProblem` → solve → :class:`DesignResult` → report.
"""

from . import exact
from .errors import ConfigError, InputError, SolverError, SpringBalanceError
from .mechanism import GROUND, Joint, Mechanism
from .objectives import OBJECTIVES
from .params import Anchor, Free, Plane, Segment
from .payload import PayloadRange, PayloadSweep, payload_range, residual_vs_payload
from .problem import DesignProblem, Evaluation
from .result import DesignResult
from .scenarios import Payload, Scenario, payload_scenarios
from .sizing import MATERIALS, Helical, HelicalDesign, Material, size_helical_spring
from .springs import (CoilMass, CompressionSpring, ConstantForceSpring, ExtensionSpring, GasSpring, Spring,
                      TorsionalSpring, TwoPointSpring, ZeroFreeLengthSpring)
from .workspace import Coupling, Workspace

__version__ = "0.1.0"

__all__ = [
    "Anchor", "CoilMass", "CompressionSpring", "ConfigError", "ConstantForceSpring", "Coupling", "DesignProblem",
    "DesignResult", "Evaluation", "ExtensionSpring", "Free", "GROUND", "GasSpring", "Helical", "HelicalDesign",
    "InputError", "Joint", "MATERIALS", "Material", "Mechanism", "OBJECTIVES", "Payload", "PayloadRange",
    "PayloadSweep", "Plane", "Scenario", "Segment", "SolverError",
    "Spring", "SpringBalanceError", "TorsionalSpring", "TwoPointSpring", "Workspace", "ZeroFreeLengthSpring",
    "payload_range", "payload_scenarios", "residual_vs_payload", "size_helical_spring",
]
