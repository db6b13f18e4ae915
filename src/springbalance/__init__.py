"""springbalance: design gravity-balancing springs for robot arms described by URDF.

The subpackages are the data flow, each importing only those before it:
:mod:`~springbalance.model` (mechanism, workspace, kinematics) → :mod:`~springbalance.springs`
(anchors, parameters, spring laws, sizing) → :mod:`~springbalance.design` (problem, objectives,
solvers, exact balance) → :mod:`~springbalance.io` and :mod:`~springbalance.viz` (config files,
exports, Meshcat scenes) → :mod:`~springbalance.results` (:class:`DesignResult`, reports, plots)
→ :mod:`springbalance.cli`.
"""

from springbalance._version import __version__
from springbalance.design import exact
from springbalance.design.objectives import OBJECTIVES
from springbalance.design.problem import DesignProblem, Evaluation
from springbalance.design.clearance import Clearance
from springbalance.design.scenarios import Payload, Scenario, payload_scenarios
from springbalance.errors import ConfigError, InputError, SolverError, SpringBalanceError
from springbalance.model.mechanism import GROUND, Joint, Mechanism
from springbalance.model.workspace import Coupling, Workspace
from springbalance.results.payload import PayloadRange, PayloadSweep, payload_range, residual_vs_payload
from springbalance.results.result import DesignResult
from springbalance.springs import constraints
from springbalance.springs.laws import (CompressionSpring, ConstantForceSpring, ExtensionSpring, GasSpring, Spring,
                                        TorsionalSpring, TwoPointSpring, ZeroFreeLengthSpring)
from springbalance.springs.laws.helical_compression import HelicalCompressionSpring
from springbalance.springs.laws.helical_extension import HelicalExtensionSpring
from springbalance.springs.mass import CoilMass
from springbalance.springs.params import Anchor, Free, Plane, Pulley, Segment
from springbalance.springs.sizing import MATERIALS, Helical, HelicalDesign, Material, size_helical_spring

__all__ = [
    "Anchor", "Clearance", "CoilMass", "CompressionSpring", "ConfigError", "ConstantForceSpring", "Coupling", "DesignProblem",
    "DesignResult", "Evaluation", "ExtensionSpring", "Free", "GROUND", "GasSpring", "Helical", "HelicalCompressionSpring", "HelicalDesign",
    "HelicalExtensionSpring",
    "InputError", "Joint", "MATERIALS", "Material", "Mechanism", "OBJECTIVES", "Payload", "PayloadRange",
    "PayloadSweep", "Plane", "Pulley", "Scenario", "Segment", "SolverError",
    "Spring", "SpringBalanceError", "TorsionalSpring", "TwoPointSpring", "Workspace", "ZeroFreeLengthSpring",
    "__version__", "constraints", "exact", "payload_range", "payload_scenarios", "residual_vs_payload",
    "size_helical_spring",
]
