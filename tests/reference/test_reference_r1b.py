"""R1b of docs/reference_cases.md: Arakelian & Ghazaryan (2007), rotating link balanced by a
zero-free-length spring that carries its own mass, coupled to its stiffness (docs/model.md §5).

urdf/single_link_r1.urdf: the joint angle is the paper's phi, measured from the upward
vertical; the ground point B = (0, Y_B) is the world point (0, 0, 0.16), the link point A at
r = 0.3 m the link-frame point (0, 0, 0.3). Coil: G = 81 GPa, rho = 7800 kg/m³, D = 0.04 m,
n = 80, L_w = 10.38 m. Published: k ≈ 324 N/m (paper 324.5), spring mass ≈ 0.81 kg (paper
0.8), residual ≈ 0; tolerance 1 %.

Physics: half the spring's mass sits at A, on the line through the centre of mass, so the
moment to balance is (m1 s1 + r m_s/2) g sin(phi), and a zero-free-length spring balances it
exactly when k Y_B r = (m1 s1 + r m_s(k)/2) g, with m_s(k) = rho π L_w sqrt(D³ n k/(2G)).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq

import springbalance as sb

URDF = Path(__file__).resolve().parents[2] / "urdf"
M1, S1, G = 8.0, 0.183, 9.81
Y_B, R_A = 0.16, 0.3
SHEAR, RHO, COIL, COILS, WIRE = 81e9, 7800.0, 0.04, 80, 10.38


def spring_mass(k):
    return RHO * np.pi * WIRE * np.sqrt(COIL**3 * COILS * k / (2 * SHEAR))


def test_r1b_spring_mass_coupled_to_stiffness():
    mechanism = sb.Mechanism.from_urdf(URDF / "single_link_r1.urdf")
    workspace = sb.Workspace.grid(mechanism, 241, ranges={"pivot": (2 * np.pi / 3, np.pi)})  # every 0.25°
    coil = sb.CoilMass(coil_diameter=COIL, active_coils=COILS, wire_length=WIRE, shear_modulus=SHEAR, density=RHO)
    spring = sb.ZeroFreeLengthSpring(
        sb.Anchor("universe", (0, 0, Y_B)), sb.Anchor("link1", (0, 0, R_A)), stiffness=sb.Free(1, 2000), mass=coil
    )
    result = sb.solve(sb.DesignProblem(mechanism, workspace, [spring]), starts=2)
    record = result.spring("s1")
    k, mass = record["stiffness"], record["mass"]
    peak = result.metrics()["joints"][0]["peak_after"]
    print(f"[R1b] k              project {k:<12.6g} published 324.5 N/m")
    print(f"[R1b] spring mass    project {mass:<12.6g} published 0.8 kg")
    print(f"[R1b] peak residual  project {peak:<12.6g} published 0 N·m")
    assert k == pytest.approx(324, rel=0.01)
    assert mass == pytest.approx(0.81, rel=0.01)
    assert peak < 1e-6 * M1 * G * S1
    # exact balance condition, solved independently
    exact = brentq(lambda kk: kk * Y_B * R_A - (M1 * S1 + R_A * spring_mass(kk) / 2) * G, 1.0, 2000.0)
    assert k == pytest.approx(exact, rel=1e-6)
    assert mass == pytest.approx(spring_mass(exact), rel=1e-6)
    # without the mass the same spring would be R1a's 299 N/m: the mass is worth 8 %
    assert k / (M1 * S1 * G / (Y_B * R_A)) == pytest.approx(1.083, abs=0.002)
