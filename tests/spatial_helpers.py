"""A spatial yaw–pitch–roll arm written out by hand, for the spatial exact-balance tests.

Joint 1 (``yaw``) turns about the world z axis (up) at the origin; joint 2 (``pitch``) about the y axis
of link 1, ``H`` above it; link 2 lies along its x axis, its centre of mass ``C2`` out; joint 3
(``roll``) turns about that x axis, ``L2`` out, and link 3's centre of mass is ``C3`` further along
it and ``offset`` off it (along link 3's y). Gravity (0, 0, −g).

Hand derivation. With the pitch angle θ₂ (about y: ``Ry(θ₂) e_x = (cos θ₂, 0, −sin θ₂)``,
``Ry(θ₂) e_z = (sin θ₂, 0, cos θ₂)``) and the yaw about the vertical (no change of height), the heights
of the centres of mass are ``H − C2 sin θ₂`` and ``H − (L2 + C3) sin θ₂ + offset · sin θ₃ cos θ₂``
(link 3's y axis, turned by the roll θ₃ about x, is ``cos θ₃ e_y + sin θ₃ e_z`` in link 2's frame). So

    V_g = const − g (M2 C2 + M3 (L2 + C3)) sin θ₂ + g M3 offset cos θ₂ sin θ₃        [J]

A zero-free-length spring from the ground point (0, 0, H + a) (on the yaw axis, ``a`` above the pitch
joint) to the link-2 point (b, 0, 0) has ``L² = a² + b² + 2 a b sin θ₂``: ``V_s = const + k a b sin θ₂``.
With ``offset = 0`` the arm is balanced exactly when ``k a b = g (M2 C2 + M3 (L2 + C3))``.
"""

from __future__ import annotations

import springbalance as sb

G = 9.81
H, L2, C2, C3 = 0.3, 0.5, 0.2, 0.1  # [m]
M1, M2, M3 = 1.5, 2.0, 0.8  # [kg]
WEIGHT_MOMENT = M2 * C2 + M3 * (L2 + C3)  # [kg·m]

_URDF = """<?xml version="1.0"?>
<robot name="yaw_pitch_roll">
  <link name="ground"/>
  <link name="link1"><inertial><origin xyz="0 0 0.1"/><mass value="{m1}"/>
    <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <link name="link2"><inertial><origin xyz="{c2} 0 0"/><mass value="{m2}"/>
    <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <link name="link3"><inertial><origin xyz="{c3} {offset} 0"/><mass value="{m3}"/>
    <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <joint name="yaw" type="revolute"><parent link="ground"/><child link="link1"/>
    <origin xyz="0 0 0"/><axis xyz="0 0 1"/><limit lower="-3.2" upper="3.2" effort="1" velocity="1"/></joint>
  <joint name="pitch" type="revolute"><parent link="link1"/><child link="link2"/>
    <origin xyz="0 0 {h}"/><axis xyz="0 1 0"/><limit lower="-3.2" upper="3.2" effort="1" velocity="1"/></joint>
  <joint name="roll" type="revolute"><parent link="link2"/><child link="link3"/>
    <origin xyz="{l2} 0 0"/><axis xyz="1 0 0"/><limit lower="-3.2" upper="3.2" effort="1" velocity="1"/></joint>
</robot>
"""


def yaw_pitch_roll_urdf(offset: float = 0.0) -> str:
    """The URDF text of :func:`yaw_pitch_roll` (for configs that name a file)."""
    return _URDF.format(m1=M1, m2=M2, m3=M3, c2=C2, c3=C3, offset=offset, h=H, l2=L2)


def yaw_pitch_roll(offset: float = 0.0) -> sb.Mechanism:
    """The arm of the module documentation (link 3's centre of mass ``offset`` [m] off the roll axis)."""
    return sb.Mechanism.from_urdf_string(yaw_pitch_roll_urdf(offset), gravity=G)
