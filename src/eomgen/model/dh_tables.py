"""Published DH tables with dynamic parameters (SI units), standard DH, as Peter Corke's Robotics
Toolbox for Python ships them (roboticstoolbox/models/DH): com in DH frame i, inertia about the com in
DH frame i, motor inertia J_m at the motor side and gear ratio G (armature G² J_m).

Puma 560: P. Corke and B. Armstrong-Hélouvry, "A search for consensus among model parameters reported
for the PUMA 560 robot", Proc. IEEE ICRA 1994, pp. 1608-1613, which consolidates B. Armstrong,
O. Khatib and J. Burdick, "The explicit dynamic model and inertial parameters of the PUMA 560 arm",
Proc. IEEE ICRA 1986, pp. 510-518 (and Tarn et al., Paul). The base height d1 = 26.45 in is the
pedestal of the Python Toolbox. Link 1 has m = 0 and only I_yy = 0.35 (its moment about the joint axis,
the only one that enters the dynamics); that and link 3's (0.066, 0.086, 0.0125) break the triangle
inequality of principal moments, hence `strict=False`.

Stanford arm: kinematics from Stanford AIM-177 (fig. 2.3) and V. Scheinman; dynamics from
R. P. Paul, "Robot Manipulators: Mathematics, Programming and Control", MIT Press 1981, tables 6.5
and 6.6, as the Toolbox gives them (G = 1, J_m the armature already reflected). Copied as published,
including link 5's inertia (0.003, 0.0004, 0), which breaks the triangle inequality, and the com
offsets of links 2, 3 and 6 (−1.054, −6.447 and 1.554 m), large for the arm but the Toolbox's values."""
from __future__ import annotations

import sympy as sp

from .dh import DHLink

INCH = 0.0254


def puma560() -> list[DHLink]:
    """The Unimation Puma 560 (6 revolute joints), Corke & Armstrong-Hélouvry 1994."""
    half = sp.pi / 2
    rows = [  # d, a, alpha, mass, com, (Ixx, Iyy, Izz), Jm, G
        (26.45 * INCH, 0, half, 0, (0, 0, 0), (0, 0.35, 0), 200e-6, -62.6111),
        (0, 0.4318, 0, 17.4, (-0.3638, 0.006, 0.2275), (0.13, 0.524, 0.539), 200e-6, 107.815),
        (0.15005, 0.0203, -half, 4.8, (-0.0203, -0.0141, 0.070), (0.066, 0.086, 0.0125), 200e-6, -53.7063),
        (0.4318, 0, half, 0.82, (0, 0.019, 0), (1.8e-3, 1.3e-3, 1.8e-3), 33e-6, 76.0364),
        (0, 0, -half, 0.34, (0, 0, 0), (0.3e-3, 0.4e-3, 0.3e-3), 33e-6, 71.923),
        (0, 0, 0, 0.09, (0, 0, 0.032), (0.15e-3, 0.15e-3, 0.04e-3), 33e-6, 76.686),
    ]
    return [DHLink(d=d, a=a, alpha=alpha, mass=m, com=c, inertia=sp.diag(*I), motor_inertia=Jm, gear_ratio=G)
            for d, a, alpha, m, c, I, Jm, G in rows]


def stanford() -> list[DHLink]:
    """The Stanford arm (revolute, revolute, prismatic, three revolute), Paul 1981 via Corke."""
    half = sp.pi / 2
    rows = [  # kind, d or theta, a, alpha, mass, com, (Ixx, Iyy, Izz), Jm
        ("revolute", 0.412, 0, -half, 9.29, (0, 0.0175, -0.1105), (0.276, 0.255, 0.071), 0.953),
        ("revolute", 0.154, 0, half, 5.01, (0, -1.054, 0), (0.108, 0.018, 0.100), 2.193),
        ("prismatic", -half, 0.0203, 0, 4.25, (0, 0, -6.447), (2.51, 2.51, 0.006), 0.782),
        ("revolute", 0, 0, -half, 1.08, (0, 0.092, -0.054), (0.002, 0.001, 0.001), 0.106),
        ("revolute", 0, 0, half, 0.630, (0, 0.566, 0.003), (0.003, 0.0004, 0), 0.097),
        ("revolute", 0, 0, 0, 0.51, (0, 0, 1.554), (0.013, 0.013, 0.0003), 0.020),
    ]
    return [DHLink(kind=kind, **{"d" if kind == "revolute" else "theta": dt}, a=a, alpha=alpha, mass=m,
                   com=c, inertia=sp.diag(*I), motor_inertia=Jm)
            for kind, dt, a, alpha, m, c, I, Jm in rows]
