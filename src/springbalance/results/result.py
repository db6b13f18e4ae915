"""The result of a design: its numbers (:class:`~springbalance.design.evaluated.EvaluatedDesign`), its
file, and one-line conveniences for its views.

A :class:`DesignResult` is the one source of truth for a design's numbers: the design vector ``x`` of its
problem. Reports, the CLI and exports read from it. Metrics compare the balanced mechanism with the
unbalanced one (gravity only) on the same workspace: peak and RMS of each joint's torque and the
percentage reduction, and every objective of docs/model.md §6 before and after, whichever one was optimised.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy.typing as npt

from springbalance.design.bounds import check_magnitudes
from springbalance.design.clearance import FitRecord
from springbalance.design.evaluated import EvaluatedDesign
from springbalance.design.joint_hold import JointHold
from springbalance.design.objectives import OBJECTIVES
from springbalance.design.problem import DesignProblem
from springbalance.design.solvers.auxiliary import design_from_values
from springbalance.design.standard_wire import checked_wire_sizes
from springbalance.design.tolerance_spec import ToleranceSpec
from springbalance.design.twin import TwinRecord
from springbalance.design.verification_record import VerificationRecord
from springbalance.errors import InputError
from springbalance.export.common import ExportReport
from springbalance.export.mjcf import export_mjcf
from springbalance.export.urdf import export_urdf
from springbalance.files import write_json_atomic
from springbalance.model.mechanism import Mechanism
from springbalance.model.workspace import Workspace
from springbalance.results.clearance import ClearanceReport, clearance
from springbalance.results.design_file import FORMAT, check_design_mechanism, check_design_record, read_design_record
from springbalance.results.flags import Flag, flags
from springbalance.results.html_report import write_report
from springbalance.results.plots import plot_torques
from springbalance.results.pseudo_base_report import pseudo_base_record
from springbalance.results.report import result_table
from springbalance.results.seed_search import SeedSearch
from springbalance.results.tolerance_report import tolerance_record
from springbalance.springs.records import spring_from_dict
from springbalance.viz.live import LiveScene
from springbalance.viz.scene import StaticScene, show

if TYPE_CHECKING:
    from matplotlib.figure import Figure


class DesignResult(EvaluatedDesign):
    """A design evaluated on its problem's workspace (:class:`~springbalance.design.evaluated.EvaluatedDesign`,
    the numbers) with one-line conveniences for its views and its file.

    :func:`springbalance.solve` returns one. The views are functions of the numbers
    (:func:`~springbalance.results.report.result_table`, :func:`~springbalance.results.flags.flags`,
    :func:`~springbalance.results.html_report.write_report`, :func:`~springbalance.results.plots.plot_torques`,
    :func:`~springbalance.results.clearance.clearance`, :func:`~springbalance.viz.scene.show`, the exports);
    each method below calls one of them.
    """

    #: what each seed gave when the design was solved at several (``springbalance.solve(..., seeds=[...])``), the
    #: design being the best of them; None for a design solved at one seed
    seed_search: SeedSearch | None = None
    #: the wire diameters [m] the spring maker draws, given as ``solve.wire_sizes`` (sorted): the sizes the wires
    #: were rounded to and ``off_series_wire`` judges against; None for the preferred series
    wire_sizes: tuple[float, ...] | None = None

    def warnings(self) -> list[Flag]:
        """Every finding about the design, failures first: each :class:`~springbalance.results.flag.Flag`
        has a ``severity``, ``"failure"`` or ``"warning"``. See :func:`springbalance.results.flags.flags`
        for the kinds."""
        return flags(self)

    def failures(self) -> list[Flag]:
        """The findings that make the design fail (``severity == "failure"``): it breaks a constraint,
        its solve or fit did not finish, a coil cannot be wound, a spring overlaps the arm, a weighted
        joint is worse, or it was saved unfinished. Empty for a design that passes."""
        return [flag for flag in self.warnings() if flag.failure]

    @property
    def ok(self) -> bool:
        """True when the design passes every check (:meth:`failures` is empty)."""
        return not self.failures()

    def table(self) -> str:
        """Plain-text report: springs, per-joint torques before/after, objectives."""
        return result_table(self)

    # ---------------------------------------------------------------- seeing the design
    def show(
        self, joint_values: npt.ArrayLike | None = None, static: bool = False, **options: Any
    ) -> LiveScene | StaticScene:
        """Draw the design in Meshcat: the arm, its springs as helices coloured by tension, animated.

        By default the scene goes to a local Meshcat server (127.0.0.1 only, started on
        first use) and a ``LiveScene`` with its ``url`` is returned; it shows inline in
        Jupyter. ``static=True`` returns a self-contained page instead (no server).
        ``joint_values`` (N×nv) is the animation path; default a sweep of each joint.
        See :func:`springbalance.viz.scene.show` for the options.
        """
        return show(self, joint_values, static=static, **options)

    def plot_torques(self, path: str | Path | None = None, points: int = 121) -> Figure:
        """matplotlib figure of each joint's torque along a sweep of that joint, before and after;
        ``path``: also save it as PNG and SVG. See :func:`springbalance.results.plots.plot_torques`."""
        return plot_torques(self, points=points, path=path)

    def report(self, folder: str | Path, scene: bool = True, **scene_options: Any) -> Path:
        """Write ``report.html``, ``scene.html`` and the torque plots into ``folder``; returns
        the report's path. See :func:`springbalance.results.html_report.write_report`."""
        return write_report(self, folder, scene=scene, **scene_options)

    def clearance(
        self, radius: float | None = None, samples: int | None = None, margin: float | None = None
    ) -> ClearanceReport:
        """Smallest distance from each spring (a capsule) to the arm's URDF collision geometry, a
        check of the finished design; see :func:`springbalance.results.clearance.clearance`."""
        return clearance(self, radius=radius, samples=samples, margin=margin)

    # ---------------------------------------------------------------- export
    def to_urdf(self, path: str | Path, resolve_packages: bool = False) -> ExportReport:
        """Write the URDF with a massless link at every spring anchor and the spring records (and
        ``<stem>.springs.json``); returns an :class:`~springbalance.io.export.ExportReport` whose
        ``warnings`` list the springs MuJoCo cannot express exactly. See :func:`springbalance.io.urdf.export_urdf`."""
        return export_urdf(self, path, resolve_packages=resolve_packages)

    def to_mjcf(self, path: str | Path) -> ExportReport:
        """Write the balanced arm as a MuJoCo model (a tendon per spring); returns an
        :class:`~springbalance.io.export.ExportReport`. See :func:`springbalance.io.mjcf.export_mjcf`."""
        return export_mjcf(self, path)

    # ---------------------------------------------------------------- persistence
    def to_dict(self) -> dict[str, Any]:
        """The JSON record that :meth:`save` writes and :meth:`load` reads."""
        problem = self.problem
        workspace = problem.base_workspace  # the poses; scenarios (saved below) are stacked on them
        return {
            "format": FORMAT,
            "mechanism": problem.mechanism.source,
            "workspace": {
                "description": workspace.description,
                "ordered": workspace.ordered,
                "joint_values": workspace.joint_values.tolist(),
            },
            "objective": problem.objective.name,
            "weights": self.problem.weights_by_name(),
            "springs": [spring.to_dict() for spring in problem.springs],
            "variables": self.variables,
            "design": self.springs,
            "sizing": {name: design.to_dict() for name, design in self.helical_sizing().items()},
            "solver": {
                "method": self.method,
                "seed": self.seed,
                "status": self.status,
                "spread": self.spread(),
                "starts": [record.to_dict() for record in self.starts],
                **({"standard_wire": self.wire_rounding.to_dict()} if self.wire_rounding else {}),
                **({"joint_hold": self.joint_hold.to_dict()} if self.joint_hold else {}),
                **({"fit": self.fit.to_dict()} if self.fit else {}),
                **({"verification": self.verification.to_dict()} if self.verification else {}),
                **({"twin": self.twin.to_dict()} if self.twin else {}),
                **({"seeds": self.seed_search.to_dict()} if self.seed_search else {}),
                **({"wire_sizes": list(self.wire_sizes)} if self.wire_sizes else {}),
            },
            "metrics": self.metrics(),
            "spring_mass": self.spring_mass().to_dict(),
            **self.findings_record(),
            **problem.scenarios_record(),
            **tolerance_record(self),
            **pseudo_base_record(self),
        }

    def findings_record(self) -> dict[str, Any]:
        """The findings as ``design.json`` keeps them: ``warnings`` (every finding, failures first, each
        ``{kind, severity, subject, message, hint?}``), ``failures`` (the failures' records again), and,
        for a design saved unfinished, ``partial`` (true) and ``partial_reason``."""
        found = [flag.to_dict() for flag in self.warnings()]
        record: dict[str, Any] = {
            "warnings": found,
            "failures": [entry for entry in found if entry["severity"] == "failure"],
        }
        if self.partial:
            record.update(partial=True, partial_reason=self.partial)
        return record

    def save(self, path: str | Path) -> Path:
        """Write the design as JSON (atomically: no half-written file on failure)."""
        return write_json_atomic(path, self.to_dict())

    @classmethod
    def load(
        cls, path: str | Path, mechanism: Mechanism | None = None, workspace: Workspace | None = None
    ) -> DesignResult:
        """Read a design saved by :meth:`save`; values round-trip exactly.

        ``mechanism`` overrides the saved mechanism source; ``workspace`` evaluates the
        design on other samples (of that mechanism; the twin's record, made for the design's own
        samples, is then left out). A design saved with ``partial: true`` loads with its ``partial``
        reason, so that it reports the ``partial`` failure again.
        """
        path = Path(path)
        label = f"design file {str(path)!r}"
        own_workspace = workspace is None
        record = read_design_record(path)  # JSON without repeated keys, within the memory budget
        check_design_record(record, label)  # types and finite numbers, before anything uses them
        try:
            mechanism = mechanism or Mechanism.from_source(record["mechanism"])
            check_design_mechanism(record, mechanism, label, own_workspace=workspace is None)
            if workspace is None:
                saved = record["workspace"]
                workspace = Workspace(
                    mechanism, saved["joint_values"], ordered=saved["ordered"], description=saved["description"]
                )
            springs = [spring_from_dict(s, f"{path.name}: springs[{i}]") for i, s in enumerate(record["springs"])]
            check_magnitudes(springs)
            objective = record["objective"]
            if OBJECTIVES[objective].needs_path and not workspace.ordered:
                objective = "rms"
            problem = DesignProblem(
                mechanism,
                workspace,
                springs,
                objective=objective,
                weights=record["weights"],
                **DesignProblem.scenario_options(record),
            )
            values = record["variables"]
            auxiliary = problem.model.auxiliary_names  # (a design saved before a coil's fatigue ceiling: filled in)
            missing = [name for name in problem.variables.names if name not in values and name not in auxiliary]
            if missing:
                raise InputError(f"design file {str(path)!r} lacks values of {', '.join(missing)}")
            x = design_from_values(problem, values)
        except KeyError as error:
            raise InputError(f"design file {str(path)!r} lacks key {error}") from None
        except InputError:
            raise
        except (TypeError, ValueError, AttributeError, IndexError) as error:  # a record damaged past the checks
            raise InputError(f"{label} is damaged: {' '.join(str(error).split())[:300]}") from None
        solver = record.get("solver", {})
        partial = (record.get("partial_reason") or "saved as partial") if record.get("partial") else None
        result = cls(
            problem,
            x,
            method=solver.get("method", "evaluate"),
            seed=solver.get("seed"),
            status=solver.get("status", "loaded"),
            fit=FitRecord.from_dict(solver.get("fit")),
            joint_hold=JointHold.from_dict(solver.get("joint_hold")),
            verification=VerificationRecord.from_dict(solver.get("verification")),
            # the twin was solved on the design's own workspace: no reference on another one
            twin=TwinRecord.from_dict(solver.get("twin")) if own_workspace else None,
            partial=partial,
            tolerance=_saved_tolerance(record, label),
        )
        result.seed_search = SeedSearch.from_dict(solver.get("seeds"))
        if solver.get("wire_sizes") is not None:
            result.wire_sizes = checked_wire_sizes(solver["wire_sizes"], f"{label}: solver.wire_sizes")
        return result

    def __repr__(self) -> str:
        return f"DesignResult({self.problem!r}, status={self.status!r})"


def _saved_tolerance(record: dict[str, Any], label: str) -> ToleranceSpec | None:
    """The tolerance spec a design file was saved with (None when it has none)."""
    saved = record.get("tolerance")
    return ToleranceSpec.from_record(saved.get("spec"), f"{label}: tolerance.spec") if isinstance(saved, dict) else None
