"""Loads: applied forces and torques, actuators between two bodies, springs and dampers.

A `Point` is a body (None = the world) and coordinates in that body's frame. Loads only describe;
each method turns them into generalized forces its own way (Jacobians or virtual power)."""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp


@dataclass(frozen=True)
class Point:
    """A point: a body (None = the world) and its coordinates `offset` in that body's frame."""

    body: object | None  # a Body, or None for the world
    offset: sp.Matrix

    def __str__(self) -> str:
        where = "world" if self.body is None else f"body '{self.body.name}'"
        return f"{tuple(self.offset)} on {where}"


@dataclass(frozen=True)
class Force:
    """Force F (world axes, or the body's axes if in_body_frame) applied at `point`."""

    name: str
    point: Point
    force: sp.Matrix
    in_body_frame: bool = False


@dataclass(frozen=True)
class Torque:
    """Pure torque T (world or body axes) on a body."""

    name: str
    body: object
    torque: sp.Matrix
    in_body_frame: bool = False


@dataclass(frozen=True)
class Actuator:
    """Acts on `a.body` and reacts on `b.body`: torque T on a, −T on b (world axes, or a's axes if
    in_body_frame); a scalar force f along the line from b's point to a's point pushes them apart."""

    name: str
    a: Point
    b: Point
    torque: sp.Matrix | None
    force: sp.Expr | None
    in_body_frame: bool = False


@dataclass(frozen=True)
class Spring:
    """Linear spring between two points: U = ½ k (‖r_a − r_b‖ − l0)²."""

    name: str
    a: Point
    b: Point
    stiffness: sp.Expr
    rest_length: sp.Expr = sp.Integer(0)


@dataclass(frozen=True)
class Damper:
    """Linear damper between two points: force −c ℓ̇ along the line, Rayleigh D = ½ c ℓ̇²."""

    name: str
    a: Point
    b: Point
    damping: sp.Expr


@dataclass(frozen=True)
class Motor:
    """A DC motor driving a revolute joint through a gear of ratio N (motor angle = N q):
    armature circuit L di/dt = U − R i − k N q̇, joint torque N k i − N² f q̇, rotor inertia
    N² J_m at the joint (Pinocchio's armature). Electrical power U i goes into the magnetic energy
    ½ L i², the mechanical power and the losses R i² + f (N q̇)²."""

    name: str
    body: object
    current: sp.Symbol
    voltage: sp.Expr
    resistance: sp.Expr
    inductance: sp.Expr
    torque_constant: sp.Expr
    rotor_inertia: sp.Expr
    friction: sp.Expr
    gear_ratio: sp.Expr

    def circuit(self, u) -> list[sp.Expr]:
        """[U − k N q̇, R, L] of L di/dt = U − R i − k N q̇ (u: the system's speeds)."""
        return [self.voltage - self.torque_constant * self.gear_ratio * u[self.body.index], self.resistance,
                self.inductance]
