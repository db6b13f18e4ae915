"""springbalance: design gravity-balancing springs for robot arms described by URDF.

The subpackages are the data flow, each importing only those before it:
:mod:`~springbalance.model` (mechanism, workspace, kinematics) → :mod:`~springbalance.springs`
(anchors, parameters, spring laws, sizing) → :mod:`~springbalance.design` (problem, objectives,
solvers, exact balance) → :mod:`~springbalance.io` and :mod:`~springbalance.viz` (config files,
exports, Meshcat scenes) → :mod:`~springbalance.results` (:class:`DesignResult`, reports, plots)
→ :mod:`springbalance.cli`.

``import springbalance`` is lazy (the pattern of the Scientific Python SPEC 1): it loads none of
the subpackages nor their dependencies (numpy, casadi, pinocchio, pydantic). Each name of
:data:`__all__` (and each subpackage, ``springbalance.design`` …) is imported on its first use,
``sb.DesignProblem`` or ``from springbalance import Mechanism``, and is the same object as before.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

from springbalance._version import __version__
from springbalance.errors import ConfigError, InputError, SolverError, SpringBalanceError

if TYPE_CHECKING:  # the real imports, for type checkers and IDEs
    from springbalance.design import exact
    from springbalance.design.clearance import Clearance
    from springbalance.design.evaluated import EvaluatedDesign
    from springbalance.design.objectives import OBJECTIVES
    from springbalance.design.problem import DesignProblem, Evaluation
    from springbalance.design.scenarios import Payload, Scenario, payload_scenarios
    from springbalance.design.tolerance_spec import ToleranceSpec
    from springbalance.io.stock_catalogues import load_stock
    from springbalance.model.mechanism import GROUND, Joint, Mechanism
    from springbalance.model.workspace import Coupling, Workspace
    from springbalance.pipeline import solve
    from springbalance.pipeline.payload import payload_range
    from springbalance.results.payload import PayloadRange, PayloadSweep, residual_vs_payload
    from springbalance.results.result import DesignResult
    from springbalance.springs import constraints
    from springbalance.springs.laws import (
        CompressionSpring,
        ConstantForceSpring,
        DirectedForce,
        DirectedGas,
        ExtensionSpring,
        GasSpring,
        Spring,
        TorsionalSpring,
        TwoPointSpring,
        ZeroFreeLengthSpring,
    )
    from springbalance.springs.laws.helical_compression import HelicalCompressionSpring
    from springbalance.springs.laws.helical_extension import HelicalExtensionSpring
    from springbalance.springs.mass import CoilMass
    from springbalance.springs.params import Anchor, Free, Plane, Pulley, Segment
    from springbalance.springs.sizing import MATERIALS, Helical, HelicalDesign, Material, size_helical_spring

__all__ = [
    "Anchor",
    "Clearance",
    "CoilMass",
    "CompressionSpring",
    "ConfigError",
    "ConstantForceSpring",
    "Coupling",
    "DesignProblem",
    "DesignResult",
    "DirectedForce",
    "DirectedGas",
    "EvaluatedDesign",
    "Evaluation",
    "ExtensionSpring",
    "Free",
    "GROUND",
    "GasSpring",
    "Helical",
    "HelicalCompressionSpring",
    "HelicalDesign",
    "HelicalExtensionSpring",
    "InputError",
    "Joint",
    "MATERIALS",
    "Material",
    "Mechanism",
    "OBJECTIVES",
    "Payload",
    "PayloadRange",
    "PayloadSweep",
    "Plane",
    "Pulley",
    "Scenario",
    "Segment",
    "SolverError",
    "Spring",
    "SpringBalanceError",
    "ToleranceSpec",
    "TorsionalSpring",
    "TwoPointSpring",
    "Workspace",
    "ZeroFreeLengthSpring",
    "__version__",
    "constraints",
    "exact",
    "load_stock",
    "payload_range",
    "payload_scenarios",
    "residual_vs_payload",
    "solve",
    "size_helical_spring",
]

#: Where each lazy name of :data:`__all__` lives (the module it is imported from); the names that
#: are modules themselves (``exact``, ``constraints``) are given as ``{name: None}`` under their package.
_SOURCES = {
    "springbalance.design": {"exact": None},
    "springbalance.design.clearance": ("Clearance",),
    "springbalance.design.objectives": ("OBJECTIVES",),
    "springbalance.design.evaluated": ("EvaluatedDesign",),
    "springbalance.design.problem": ("DesignProblem", "Evaluation"),
    "springbalance.design.scenarios": ("Payload", "Scenario", "payload_scenarios"),
    "springbalance.io.stock_catalogues": ("load_stock",),
    "springbalance.design.tolerance_spec": ("ToleranceSpec",),
    "springbalance.model.mechanism": ("GROUND", "Joint", "Mechanism"),
    "springbalance.model.workspace": ("Coupling", "Workspace"),
    "springbalance.pipeline": ("solve",),
    "springbalance.pipeline.payload": ("payload_range",),
    "springbalance.results.payload": ("PayloadRange", "PayloadSweep", "residual_vs_payload"),
    "springbalance.results.result": ("DesignResult",),
    "springbalance.springs": {"constraints": None},
    "springbalance.springs.laws": (
        "CompressionSpring",
        "ConstantForceSpring",
        "DirectedForce",
        "DirectedGas",
        "ExtensionSpring",
        "GasSpring",
        "Spring",
        "TorsionalSpring",
        "TwoPointSpring",
        "ZeroFreeLengthSpring",
    ),
    "springbalance.springs.laws.helical_compression": ("HelicalCompressionSpring",),
    "springbalance.springs.laws.helical_extension": ("HelicalExtensionSpring",),
    "springbalance.springs.mass": ("CoilMass",),
    "springbalance.springs.params": ("Anchor", "Free", "Plane", "Pulley", "Segment"),
    "springbalance.springs.sizing": ("MATERIALS", "Helical", "HelicalDesign", "Material", "size_helical_spring"),
}
_LAZY = {name: module for module, names in _SOURCES.items() for name in names}
#: The subpackages and modules reachable as attributes (``sb.springs.spring_from_dict``), as when
#: the package imported them all.
_SUBMODULES = (
    "cli",
    "design",
    "errors",
    "explore",
    "export",
    "files",
    "io",
    "loaders",
    "model",
    "pipeline",
    "results",
    "springs",
    "viz",
)


def __getattr__(name: str) -> Any:
    module = _LAZY.get(name)
    if module is not None:
        value = (
            importlib.import_module(f"{module}.{name}")
            if isinstance(_SOURCES[module], dict)
            else getattr(importlib.import_module(module), name)
        )
    elif name in _SUBMODULES:
        value = importlib.import_module(f"{__name__}.{name}")
    else:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    globals()[name] = value  # the next access is a plain attribute
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__) | set(_SUBMODULES))
