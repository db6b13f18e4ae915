r"""Pseudo-bases that ``explore`` proposes when springs alone found no exact design (docs/guides/explore.md).

One candidate per joint :math:`J` that gravity loads (gravity's multilinear coefficients involve :math:`q_J`,
docs/model.md §9.1): a pseudo-base ``pb_<J>`` (:mod:`springbalance.model.pseudo_bases`) that keeps only the
vertical when gravity is along :math:`z` and the arm has leading vertical-axis joints (fewer parallelograms), else
the orientation. The candidates are ranked by the mass they add, lightest first.

**Mass** [kg]. The study's ``mechanism.pseudo_bases`` record for :math:`J`, when it gives one (``mass``, ``com``);
otherwise an estimate of the parallelograms that realise it: per joint its chain undoes, one parallelogram over
the link from that joint's origin to the next one on the path, whose bar (as long as that link, :math:`L`) and two
cranks (:data:`CRANK_LENGTH` each) are tubes of :data:`DENSITY`:
:math:`m = \rho_\ell \sum (L + 2 c)`, put at the joint's origin. A vertical-only pseudo-base next to the arm's
vertical base joint needs no parallelogram: 0 kg (a bracket on the link that carries it). The torque its weight
adds before balancing is :func:`~springbalance.model.pseudo_base_weight.pseudo_base_torques` over
:data:`SAMPLES` Sobol poses within the joint limits.

**Exact or not.** A zero-free-length spring from ``pb_<J>`` to the link :math:`J` moves balances that link with
everything beyond it lumped at its next joint (docs/model.md §1.1), provided the links beyond are balanced the same
way. So the test puts pseudo-bases at :math:`J` and at every loaded joint beyond it, offers per pseudo-base six
springs to its link (anchor :data:`ARM` [m] up on the pseudo-base, :math:`\pm` :data:`ARM` along each axis of the
link), fits their stiffnesses :math:`k \ge 0` to the multilinear coefficients of the potential by non-negative
least squares (as :func:`~springbalance.design.exact.stiffness_fit.fit_stiffnesses`, on the grid
:math:`\{0, 2\pi/3, 4\pi/3\}^n`), and calls the candidate exact when every coefficient that involves a joint of
:math:`J`'s subtree is below :data:`~springbalance.design.exact.multilinear.SPATIAL_EXACT` of gravity's largest.
What is left then depends only on the joints before :math:`J`.
"""

from __future__ import annotations

import dataclasses
import html
import itertools
from typing import Any, Mapping, Protocol, Sequence

import numpy as np
import pinocchio as pin

from springbalance.design.exact.multilinear import GRID, SPATIAL_EXACT, coefficients_of, spring_grid_potential
from springbalance.errors import InputError
from springbalance.model.kinematics import WorkspaceKinematics
from springbalance.model.mechanism import Mechanism
from springbalance.model.pseudo_base_weight import pseudo_base_torques
from springbalance.model.pseudo_bases import PseudoBase, pseudo_base_body
from springbalance.model.workspace import Workspace
from springbalance.springs.laws import ZeroFreeLengthSpring
from springbalance.springs.params import Anchor

__all__ = [
    "ARM",
    "CRANK_LENGTH",
    "DENSITY",
    "SAMPLES",
    "proposal_lines",
    "proposals_for",
    "proposals_html",
    "propose_pseudo_bases",
]

#: linear density [kg/m] of the parallelograms' bars and cranks: an aluminium tube 20 × 2 mm,
#: π/4 (20² − 16²) mm² × 2700 kg/m³ = 0.305 kg/m
DENSITY = 0.3
#: length [m] of a parallelogram's cranks (as drawn by :mod:`springbalance.viz.parallelograms`)
CRANK_LENGTH = 0.05
#: distance [m] of the candidate springs' anchors from the pseudo-base's and the link's origins
ARM = 0.1
#: Sobol poses within the joint limits over which the added torque's peak is taken
SAMPLES = 256
#: most joints the exact test takes (3^n grid poses)
MAX_JOINTS = 7


class _Study(Protocol):
    """What :func:`proposals_for` reads of a study's result (``springbalance.explore.study.StudyResult``)."""

    study: Any

    def exact(self) -> list[dict]: ...


@dataclasses.dataclass
class _Samples:
    mechanism: Mechanism
    configurations: np.ndarray


def proposals_for(result: _Study) -> list[dict[str, Any]]:
    """The proposals of a finished study as JSON records (:func:`propose_pseudo_bases` on its mechanism), or
    none when a design balances exactly."""
    return [] if result.exact() else propose_pseudo_bases(result.study.mechanism)


def propose_pseudo_bases(mechanism: Mechanism, density: float = DENSITY) -> list[dict[str, Any]]:
    """Per joint that gravity loads, a pseudo-base proposal (module documentation), lightest first: ``joint``,
    ``body``, ``link``, ``keep``, ``mass`` [kg], ``mass_from`` (``"config"`` or ``"estimate"``), ``peak_torque``
    (per joint, in ``units``: N·m or N), ``exact`` (bool, or None when the test does not apply), ``residual`` (the largest
    coefficient left on the subtree, relative to gravity's largest), ``with`` (the further pseudo-bases the test
    used) and ``note``; ``density`` [kg/m] of the estimate. A joint that cannot have a pseudo-base (beyond a
    prismatic joint) comes last, with ``mass`` None and why in ``note``. Empty for a mechanism that cannot be
    rebuilt from its source."""
    source = {key: value for key, value in mechanism.source.items() if key != "pseudo_bases"}
    if source.get("kind") not in ("urdf", "urdf_string", "robot"):
        return []
    source["gravity"] = [float(v) for v in mechanism.gravity]
    given = {base.joint: base for base in mechanism.pseudo_bases}
    bare = Mechanism.from_source(source)
    links = {joint["name"]: joint["child"] for joint in bare.summary()["joints"]}
    gravity = np.asarray(bare.gravity, dtype=float)
    keep = "vertical" if np.linalg.norm(gravity[:2]) <= 1e-12 * np.linalg.norm(gravity) else "orientation"
    loaded, note = _loaded_joints(bare)
    proposals: list[dict[str, Any]] = []
    refused: list[dict[str, Any]] = []
    for joint in loaded:
        item = {"joint": joint, "body": pseudo_base_body(joint), "link": links[joint]}
        try:
            proposals.append({**item, **_weight(source, bare, joint, given.get(joint), keep, density)})
        except InputError as error:
            nothing: dict[str, Any] = {"keep": None, "mass": None, "mass_from": None, "peak_torque": {}, "with": []}
            refused.append({**item, **nothing, "exact": None, "residual": None, "note": f"no pseudo-base: {error}"})
    records = {proposal["joint"]: proposal.pop("record") for proposal in proposals}
    for proposal in proposals:
        beyond = [joint for joint in _subtree(bare, proposal["joint"]) if joint in records]
        proposal["with"] = [joint for joint in beyond if joint != proposal["joint"]]
        exact, residual, why = _exact(source, bare, [records[joint] for joint in beyond], links, proposal["joint"])
        proposal.update(exact=exact, residual=residual, note=why or note)
    return sorted(proposals, key=lambda proposal: float(proposal["mass"])) + refused


def _weight(
    source: Mapping[str, Any], bare: Mechanism, joint: str, base: PseudoBase | None, keep: str, density: float
) -> dict[str, Any]:
    """The pseudo-base at ``joint``: what it keeps (vertical only where that skips a joint), its mass [kg] (the
    config's ``base``, else the estimate), the peak torque [N·m or N] its weight adds per joint, and its
    ``record``."""
    record: dict[str, Any] = {"joint": joint, "mass": base.mass, "com": list(base.com)} if base else {"joint": joint}
    single = _with_bases(source, [{**record, "keep": keep}])
    kept = keep if _undone(single, joint) < _ancestors(bare, joint) else "orientation"
    mass = base.mass if base else density * _bar_length(single, joint)
    record = {**record, "mass": mass, "keep": kept}
    single = _with_bases(source, [record])
    torque = pseudo_base_torques(Workspace.sobol(single, n=SAMPLES).kinematics())[pseudo_base_body(joint)]
    peaks = np.max(np.abs(torque), axis=0, initial=0.0)
    return {
        "keep": kept,
        "mass": float(mass),
        "mass_from": "config" if base else "estimate",
        "peak_torque": dict(zip(bare.joint_names, map(float, peaks))),
        "units": {item.name: item.torque_unit for item in bare.joints},
        "record": record,
    }


def _with_bases(source: Mapping[str, Any], records: list[dict]) -> Mechanism:
    """The arm of ``source`` with the pseudo-bases ``records``."""
    return Mechanism.from_source({**source, "pseudo_bases": records})


def _grid_kinematics(mechanism: Mechanism) -> WorkspaceKinematics:
    angles = np.array(list(itertools.product(GRID, repeat=mechanism.nv))).reshape(-1, mechanism.nv)
    return WorkspaceKinematics(_Samples(mechanism, mechanism.configurations(angles)))


def _testable(mechanism: Mechanism) -> str:
    """Why the grid test does not apply to the bare arm ("" when it does)."""
    if any(joint.kind == "prismatic" for joint in mechanism.joints):
        return "the arm has prismatic joints: the exact test takes revolute joints"
    if mechanism.model.njoints - 1 != mechanism.nv:
        return "the arm has mimic joints of its own: the exact test takes independent joints"
    if mechanism.nv > MAX_JOINTS:
        return f"the arm has {mechanism.nv} joints: the exact test takes at most {MAX_JOINTS}"
    return ""


def _involving(coefficients: np.ndarray, axes: Sequence[int]) -> float:
    """The largest |coefficient| whose index is non-zero on one of ``axes``."""
    mask = np.zeros(coefficients.shape, dtype=bool)
    for axis in axes:
        index: list[Any] = [slice(None)] * coefficients.ndim
        index[axis] = slice(1, None)
        mask[tuple(index)] = True
    return float(np.max(np.abs(coefficients[mask]), initial=0.0))


def _loaded_joints(bare: Mechanism) -> tuple[list[str], str]:
    """The joints gravity loads, in the arm's order (all of them when the grid test does not apply), and why not."""
    why = _testable(bare)
    if why:
        return list(bare.joint_names), why
    gravity = coefficients_of(_grid_kinematics(bare).potential, bare.nv)
    scale = _involving(gravity, range(bare.nv))
    return [name for axis, name in enumerate(bare.joint_names) if _involving(gravity, [axis]) > 1e-9 * scale], ""


def _exact(
    source: Mapping[str, Any], bare: Mechanism, records: list[dict], links: Mapping[str, str], joint: str
) -> tuple[bool | None, float | None, str]:
    """Whether springs from the pseudo-bases ``records`` to their links balance every term of ``joint``'s subtree
    (module documentation): (exact, the largest such coefficient left relative to gravity's largest, why not tested)."""
    from scipy.optimize import nnls  # scipy.optimize stays out of start-up (tests/test_package.py)

    why = _testable(bare)
    if why:
        return None, None, why
    mechanism = _with_bases(source, records)
    kinematics = _grid_kinematics(mechanism)
    up = -ARM * np.asarray(bare.gravity, dtype=float) / np.linalg.norm(bare.gravity)
    columns = []
    for record in records:
        body = pseudo_base_body(record["joint"])
        for direction in np.vstack([np.eye(3), -np.eye(3)]):
            spring = ZeroFreeLengthSpring(
                Anchor(body, up), Anchor(links[record["joint"]], ARM * direction), stiffness=1.0
            )
            columns.append(coefficients_of(spring_grid_potential(kinematics, spring, 1.0), bare.nv).ravel()[1:])
    gravity = coefficients_of(kinematics.potential, bare.nv)
    matrix = np.array(columns).T
    scale = np.maximum(np.max(np.abs(matrix), axis=0), 1e-300)
    scaled, _ = nnls(matrix / scale, -gravity.ravel()[1:], maxiter=50 * matrix.shape[1])
    left = gravity.ravel().copy()
    left[1:] += matrix @ (scaled / scale)
    axes = [bare.joint_names.index(name) for name in _subtree(bare, joint)]
    relative = _involving(left.reshape(gravity.shape), axes) / max(_involving(gravity, range(bare.nv)), 1e-300)
    return relative <= SPATIAL_EXACT, relative, ""


def _subtree(mechanism: Mechanism, joint: str) -> list[str]:
    """The degrees of freedom of ``joint``'s subtree (itself and every joint beyond it), in the arm's order."""
    model = mechanism.model
    inside = {model.names[index] for index in model.subtrees[model.getJointId(joint)]}
    return [name for name in mechanism.joint_names if name in inside]


def _ancestors(mechanism: Mechanism, joint: str) -> int:
    """How many moving joints lie between the root and ``joint``."""
    model = mechanism.model
    return len(model.supports[model.getJointId(joint)]) - 2  # supports: universe, the ancestors, the joint


def _undone(mechanism: Mechanism, joint: str) -> int:
    """How many mimic joints the chain of the pseudo-base at ``joint`` has."""
    return sum(name.startswith(f"{pseudo_base_body(joint)}__undo_") for name in mechanism.model.names)


def _bar_length(mechanism: Mechanism, joint: str) -> float:
    """Total length [m] of the bars and cranks of the parallelograms realising ``pb_<joint>`` (module
    documentation): over each pair of consecutive joints on its path, the distance between their origins plus two
    cranks."""
    model = mechanism.model
    data = model.createData()
    pin.forwardKinematics(model, data, mechanism.configurations(np.zeros((1, mechanism.nv)))[0])
    names = set(model.names)
    target = model.getJointId(joint)
    path = [
        index
        for index in model.supports[target][1:-1]
        if f"{pseudo_base_body(joint)}__undo_{model.names[index]}" in names
    ]
    points = [data.oMi[index].translation for index in [*path, target]]
    return float(sum(np.linalg.norm(b - a) + 2 * CRANK_LENGTH for a, b in zip(points, points[1:])))


def proposal_lines(proposals: Sequence[Mapping[str, Any]]) -> list[str]:
    """The proposals as lines of the study summary (nothing when there are none)."""
    if not proposals:
        return []
    lines = ["No exact design with springs alone. Pseudo-bases that may balance (docs/model.md §1.1), lightest first:"]
    for item in proposals:
        lines.append(f"  {_sentence(item)}")
    return lines


def _sentence(item: Mapping[str, Any]) -> str:
    if item["mass"] is None:
        return f"{item['body']} at {item['joint']}: {item['note']}"
    peaks = item["peak_torque"]
    largest = max(peaks.values(), default=0.0)
    units = item.get("units", {})
    added = ", ".join(
        f"{joint} {peak:.3g} {units.get(joint, '')}".rstrip()
        for joint, peak in peaks.items()
        if peak > 1e-12 * max(largest, 1e-300)
    )
    beyond = f" (with pb at {', '.join(item['with'])})" if item["with"] else ""
    verdict = {True: "exact", False: f"not exact ({item['residual']:.2g} left)", None: f"not tested: {item['note']}"}
    return (
        f"{item['body']} at {item['joint']} (keeps {item['keep']}): {item['mass']:.3g} kg ({item['mass_from']}), "
        f"weight adds {added or 'nothing'}; springs {item['body']} → {item['link']}{beyond}: {verdict[item['exact']]}"
    )


def proposals_html(proposals: Sequence[Mapping[str, Any]]) -> str:
    """The "Pseudo-bases" section of the study's ``report.html`` ("" when there are no proposals)."""
    if not proposals:
        return ""
    items = "".join(f"<li>{html.escape(_sentence(item))}</li>" for item in proposals)
    return (
        '<h2 id="pseudo-bases">Pseudo-bases</h2><p>No design balances exactly with springs alone. A pseudo-base '
        "(docs/model.md §1.1) at a joint gravity loads, with a spring to that joint's link, balances the link with "
        "everything beyond it lumped at its next joint; lightest first (mass from the config, or an estimate of its "
        f"parallelograms):</p><ul>{items}</ul>"
    )
