"""Helical spring sizing against a design book, and the exactness of the helical constraints.

Published numbers: Budynas & Nisbett, *Shigley's Mechanical Engineering Design*, 9th ed.
(McGraw-Hill 2011), chapter 10:

- Example 10-1: a compression spring of no. 16 music wire, ``d = 0.037 in``, outside
  diameter ``7/16 in``, squared ends, ``N_t = 12.5`` total turns (``N_a = 10.5``),
  ``G = 11.85 Mpsi``. Book: ``S_ut = 324.6 kpsi`` (A = 201 kpsi·in^m, m = 0.145),
  ``S_sy = 0.45 S_ut = 146.1 kpsi``, ``C = 10.81``, ``K_B = 1.124``, static load at yield
  ``F = 6.46 lbf``, rate ``k = 4.13 lbf/in``.
- Problem 10-3 (solution manual): music wire, ``d = 0.105 in``, outside diameter
  ``1.225 in``, plain-ground ends, ``N_t = 12``; book: ``N_a = 11``, ``L_s = 1.26 in``,
  ``S_ut = 278.7 kpsi``, ``S_sy = 125.4 kpsi``, ``D = 1.120 in``, ``C = 10.67``,
  ``K_B = 1.126``, ``F = 45.2 lbf``, ``G = 11.75 Mpsi``, ``k = 11.55 lbf/in``.

Shigley designs with the Bergsträsser factor ``K_B`` and notes (§10-2) that it and the Wahl
factor ``K_W`` differ by less than 1 %; so the Wahl-corrected stress at the book's yield
load must equal the book's ``S_sy`` to 1 %.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import springbalance as sb
from springbalance.springs import sizing

URDF = Path(__file__).resolve().parents[2] / "urdf"
INCH, KPSI, LBF = 0.0254, 6.894757e6, 4.4482216  # [m], [Pa], [N]

SHIGLEY_CASES = {
    # d [in], OD [in], N_a, G [psi], S_ut [kpsi], S_sy [kpsi], C, K_B, F [lbf], k [lbf/in]
    "example 10-1": (0.037, 7 / 16, 10.5, 11.85e6, 324.6, 146.1, 10.81, 1.124, 6.46, 4.13),
    "problem 10-3": (0.105, 1.225, 11.0, 11.75e6, 278.7, 125.4, 10.67, 1.126, 45.2, 11.55),
}


@pytest.mark.parametrize("case", SHIGLEY_CASES)
def test_shigley_spring_rate_index_and_strength(case):
    d, outside, active, shear_modulus, sut, ssy, index, kb, force, rate = SHIGLEY_CASES[case]
    mean = outside - d  # D = OD - d [in]
    assert mean / d == pytest.approx(index, rel=0.01)
    assert sizing.bergstrasser_factor(mean / d) == pytest.approx(kb, rel=0.01)
    # k = G d^4 / (8 D^3 n) in the book's units [lbf/in]
    assert sizing.spring_rate(shear_modulus, d, mean, active) == pytest.approx(rate, rel=0.01)
    # the same spring in SI units
    assert sizing.spring_rate(shear_modulus * KPSI / 1e3, d * INCH, mean * INCH, active) == pytest.approx(
        rate * LBF / INCH, rel=0.01
    )
    # S_ut = A / d^m of music wire (Table 10-4, SI constants) and 45 % allowable (Table 10-6)
    music_wire = sb.MATERIALS["music_wire"]
    assert music_wire.tensile_strength(d * INCH) / KPSI == pytest.approx(sut, rel=0.01)
    assert music_wire.allowable_stress(d * INCH, "compression") / KPSI == pytest.approx(ssy, rel=0.01)
    # the book's yield load with K_B, and the Wahl-corrected stress at that load
    bergstrasser = sizing.shear_stress(force, d, mean, factor=sizing.bergstrasser_factor)  # [psi]
    assert bergstrasser / 1e3 == pytest.approx(ssy, rel=0.01)
    wahl = sizing.shear_stress(force * LBF, d * INCH, mean * INCH)  # [Pa]
    assert wahl / KPSI == pytest.approx(ssy, rel=0.01)
    assert sizing.wahl_factor(mean / d) == pytest.approx(kb, rel=0.01)


def test_wahl_factor_formula():
    """K_W = (4C - 1)/(4C - 4) + 0.615/C: 1.3105 at C = 5 (19/16 + 0.123), → 1 for large C."""
    assert sizing.wahl_factor(5.0) == pytest.approx(19 / 16 + 0.123, rel=1e-12)
    assert sizing.wahl_factor(1e6) == pytest.approx(1.0, abs=1e-5)


def test_sizing_proposal_realises_the_designed_spring():
    """Problem 10-3's spring as a design target: k, yield load, free length; the proposal must
    have exactly that rate, a Wahl stress within the allowable, an index in 4–15 and a
    solid length below the shortest working length."""
    k = 11.55 * LBF / INCH  # [N/m]
    force = 45.2 * LBF  # [N]
    free_length = 5.17 * INCH  # [m]
    min_length = free_length - force / k  # [m]
    design = sb.size_helical_spring(k, free_length, free_length, force, material="music_wire", kind="compression")
    assert design.feasible, design.reasons
    G = sb.MATERIALS["music_wire"].shear_modulus
    assert sizing.spring_rate(G, design.wire_diameter, design.mean_diameter, design.active_coils) == pytest.approx(
        k, rel=1e-9
    )
    assert design.rate == pytest.approx(k, rel=1e-9)
    assert 4 <= design.index <= 15 and design.index == pytest.approx(design.mean_diameter / design.wire_diameter)
    assert design.stress == pytest.approx(
        sizing.wahl_factor(design.index) * 8 * force * design.mean_diameter / (np.pi * design.wire_diameter**3),
        rel=1e-12,
    )
    assert design.stress <= design.allowable_stress
    assert design.solid_length == pytest.approx(design.wire_diameter * (design.active_coils + 2), rel=1e-12)
    assert design.solid_length <= min_length
    assert design.wire_diameter * 1e3 in [pytest.approx(v * 1e3) for v in sizing.PREFERRED_WIRE_DIAMETERS]
    assert design.mass == pytest.approx(
        7800 * np.pi * design.mean_diameter * design.total_coils * np.pi * design.wire_diameter**2 / 4, rel=1e-12
    )
    assert "music wire" in design.summary()


def test_sizing_reports_infeasibility_plainly():
    too_strong = sb.size_helical_spring(2000.0, 0.2, 0.3, 20000.0, material="music_wire", kind="extension")
    assert not too_strong.feasible and "stress" in too_strong.reasons[0]
    too_short = sb.size_helical_spring(135.5, 0.02, 0.3, 38.0, material="music_wire", kind="extension")
    assert not too_short.feasible and "length" in too_short.reasons[0] and "NOT FEASIBLE" in too_short.summary()
    too_stiff = sb.size_helical_spring(1e9, 0.2, 0.21, 10.0, material="chrome_silicon", kind="compression")
    assert not too_stiff.feasible and "stiff" in too_stiff.reasons[0]


# ---------------------------------------------------------------------- exactness of the constraint
#: Table 10-4 music wire (A [MPa·mm^m], m) and Table 10-5 G used by the library [Pa].
A_MUSIC, M_MUSIC, G_MUSIC = 2211.0, 0.145, 81.0e9


def _exists_by_scan(k, l0, length, force, kind, index=8.0, min_coils=3.0, fraction=0.45):
    """Is there a wire 0.10–6.5 mm with which a music-wire spring of this index works?
    Scans d finely using only the textbook relations."""
    d = np.linspace(0.10e-3, 6.5e-3, 100_001)
    coils = G_MUSIC * d / (8 * index**3 * k)  # n from k = G d / (8 C³ n)
    if kind == "extension":
        fits = 2 * (index * d - d) + d * (coils + 1) <= l0  # hooks + closed body
    else:
        fits = d * (coils + 2) <= length  # solid length
    wahl = (4 * index - 1) / (4 * index - 4) + 0.615 / index
    stress = wahl * 8 * abs(force) * index * d / (np.pi * d**3)  # D = C d
    strong = stress <= fraction * A_MUSIC * 1e6 / (d * 1e3) ** M_MUSIC
    return bool(np.any(fits & strong & (coils >= min_coils)))


@pytest.mark.parametrize("kind", ["extension", "compression"])
def test_helical_rows_are_exact(kind):
    """The rows of HelicalSpringExists are all ≥ 0 exactly when a spring exists."""
    rng = np.random.default_rng(7 if kind == "extension" else 8)
    constraint = sb.springs.constraints.HelicalSpringExists(sb.Helical("music_wire", 8.0, 3.0), kind)
    agree = 0
    for _ in range(200):
        k = 10 ** rng.uniform(1, 4.5)  # [N/m]
        l0 = rng.uniform(0.01, 0.4)  # [m]
        length = rng.uniform(0.01, 0.4)  # [m]
        force = 10 ** rng.uniform(-0.5, 3)  # [N]
        rows = constraint.rows(length, force, {"stiffness": k, "free_length": l0})
        margin = min(float(row) / scale for row, (_, _, scale) in zip(rows, constraint.parts))
        if abs(margin) < 1e-2:
            continue  # on the boundary the scan's resolution decides
        assert (margin >= 0) == _exists_by_scan(k, l0, length, force, kind), (k, l0, length, force, margin)
        agree += 1
    assert agree > 170
    # the rows that random draws rarely make binding: the thickest and the thinnest wire
    for k, room, force, binding in (
        (2000.0, 5.0, 3000.0, "helical_max_wire"),  # 6.5 mm cannot carry 3 kN
        (10.0, 0.001, 0.1, "helical_min_wire"),
    ):  # no 0.1 mm coil fits in 1 mm
        rows = constraint.rows(room, force, {"stiffness": k, "free_length": room})
        names = [name for name, _, _ in constraint.parts]
        assert float(rows[names.index(binding)]) < 0
        assert not _exists_by_scan(k, room, room, force, kind)


def test_helical_option_in_the_optimisation(tmp_path):
    """R2's link (full turn) with an extension spring. Unconstrained, the rms optimum (k ≈ 136 N/m,
    l0 at its 20 mm bound) has no music-wire realisation; with the helical option it has one."""
    mechanism = sb.Mechanism.from_urdf(URDF / "single_link_r2.urdf", gravity=9.8)
    workspace = sb.Workspace.grid(mechanism, 181)

    def design(helical):
        spring = sb.ExtensionSpring(
            sb.Anchor("universe", (0, 0, 0.1)),
            sb.Anchor("link1", (0.2, 0, 0)),
            stiffness=sb.Free(1, 500),
            free_length=sb.Free(0.02, 0.2),
            helical=helical,
        )
        return sb.solve(sb.DesignProblem(mechanism, workspace, [spring], objective="rms"), starts=2)

    def exists(result, relief=1e-3):
        """Existence for 0.1 % less than the largest force: the constrained optimum lies on the
        boundary, where the scan's resolution decides."""
        values = result.spring("s1")
        force = np.max(np.abs(result.evaluation.tensions[:, 0])) * (1 - relief)
        return _exists_by_scan(values["stiffness"], values["free_length"], None, force, "extension")

    free, constrained = design(None), design({"material": "music_wire", "index": 8})
    assert not exists(free)
    assert constrained.evaluation.max_violation <= 1e-6
    assert exists(constrained)
    assert constrained.metrics()["objectives"]["rms"]["after"] > free.metrics()["objectives"]["rms"]["after"]
    proposal = constrained.helical_sizing()["s1"]
    assert proposal.feasible and proposal.stress <= proposal.allowable_stress
    assert "Helical springs" in constrained.table()
    # saved designs carry the option and the proposal, and load back exactly
    saved = json.loads(constrained.save(tmp_path / "design.json").read_text())
    assert saved["springs"][0]["helical"] == {"material": "music_wire", "index": 8.0, "min_active_coils": 3.0}
    assert saved["sizing"]["s1"]["wire_diameter"] == proposal.wire_diameter
    loaded = sb.DesignResult.load(tmp_path / "design.json")
    assert loaded.springs == constrained.springs
    np.testing.assert_array_equal(loaded.evaluation.constraint_rows, constrained.evaluation.constraint_rows)
