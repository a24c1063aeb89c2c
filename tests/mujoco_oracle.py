"""MuJoCo as the oracle for eomgen's reading of an MJCF file: the same state in both coordinate
conventions, and M, the bias forces, body and site placements and the centre of mass compared.

Coordinates (per joint, in MuJoCo's joint order, which is eomgen's):
- free joint: eomgen/Pinocchio q = [x y z qx qy qz qw] (scalar last), u = [v, ω], both in the body's
  axes; MuJoCo qpos = [x y z qw qx qy qz] (scalar first), qvel = [R v, ω] (the origin's velocity in
  world axes, ω in the body's). So qvel = T u with T = blockdiag(R, 1), and q̈vel = T u̇ + Ṫ u with
  Ṫ u = [R (ω × v), 0].
- ball joint: quaternion scalar last vs scalar first; ω in the child's axes in both.
- hinge and slide: the same number (both measure from the pose where the joint is at 0, the file's pose
  turned back by the joint's `ref`).
MuJoCo's M q̈vel + qfrc_bias = τ_mj with τ_eomgen = Tᵀ τ_mj (same power) gives M_eomgen = Tᵀ M T and
b + g = Tᵀ (M Ṫ u + qfrc_bias). qfrc_bias holds no passive forces (joint springs, dampers, friction
are separate in MuJoCo and refused by eomgen); armature is in M in both.

Centre of mass: eomgen's (as Pinocchio's centerOfMass) is that of the moving bodies; MuJoCo's
subtree_com of the world counts the bodies welded to it too. Compared: subtree_com of a floating root,
else Σ m_i x_i / Σ m_i over the bodies not welded to the world (MuJoCo's body_mass, xipos).

Names: an unnamed site is the k-th of its body "<body>Site_<k>" (of the world: "worldSite_<k>"), as
Pinocchio's parser and eomgen name them (eomgen refuses unnamed bodies)."""
from __future__ import annotations

import mujoco
import numpy as np
from scipy.spatial.transform import Rotation

import eomgen as eg

FREE, BALL = mujoco.mjtJoint.mjJNT_FREE, mujoco.mjtJoint.mjJNT_BALL


def mujoco_state(system, m, q, u):
    """(qpos, qvel, T, Ṫ u) of eomgen's state q, u."""
    qpos, qvel = np.zeros(m.nq), np.zeros(m.nv)
    T, Tdot_u = np.zeros((m.nv, system.nv)), np.zeros(m.nv)
    for body, j in zip([b for b in system.bodies if b.joint.dof], range(m.njnt)):
        a, v, iq, iv = m.jnt_qposadr[j], m.jnt_dofadr[j], body.q_index, body.index
        if m.jnt_type[j] == FREE:
            x, w = q[iq:iq + 3], q[iq + 3:iq + 7]
            R = Rotation.from_quat(w).as_matrix()
            qpos[a:a + 7] = [*x, w[3], *w[:3]]
            vel, omega = u[iv:iv + 3], u[iv + 3:iv + 6]
            qvel[v:v + 6] = [*(R @ vel), *omega]
            T[v:v + 3, iv:iv + 3], T[v + 3:v + 6, iv + 3:iv + 6] = R, np.eye(3)
            Tdot_u[v:v + 3] = R @ np.cross(omega, vel)
        elif m.jnt_type[j] == BALL:
            w = q[iq:iq + 4]
            qpos[a:a + 4] = [w[3], *w[:3]]
            qvel[v:v + 3], T[v:v + 3, iv:iv + 3] = u[iv:iv + 3], np.eye(3)
        else:
            qpos[a], qvel[v], T[v, iv] = q[iq], u[iv], 1
    return qpos, qvel, T, Tdot_u


def names(m):
    """eomgen's names of MuJoCo's bodies (1 …) and sites."""
    bodies = [mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, i) for i in range(m.nbody)]
    sites = []
    for i in range(m.nsite):
        b = m.site_bodyid[i]
        k = sum(1 for s in range(i) if m.site_bodyid[s] == b)
        sites.append(mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_SITE, i) or f"{bodies[b]}Site_{k}")
    return bodies[1:], sites


def assert_equals_mujoco(path, states: int = 3, seed: int = 0, tol: float = 1e-10):
    """M, b + g, every body's and site's placement and the centre of mass at random states."""
    system = eg.from_mjcf(path)
    f = eg.codegen(eg.derive(system))
    m = mujoco.MjModel.from_xml_path(str(path))
    d = mujoco.MjData(m)
    assert m.nv == system.nv and m.njnt == sum(1 for b in system.bodies if b.joint.dof)
    bodies, sites = names(m)
    q, u, _ = eg.random_states(system, states, np.random.default_rng(seed))
    for qk, uk in zip(q, u):
        d.qpos[:], d.qvel[:], T, Tdot_u = mujoco_state(system, m, qk, uk)
        mujoco.mj_forward(m, d)
        M = np.zeros((m.nv, m.nv))
        mujoco.mj_fullM(m, d, M)
        scale = max(1.0, np.abs(M).max())
        np.testing.assert_allclose(f.M(qk), T.T @ M @ T, rtol=0, atol=tol * scale)
        np.testing.assert_allclose(f.b(qk, uk) + f.g(qk), T.T @ (M @ Tdot_u + d.qfrc_bias), rtol=0,
                                   atol=tol * scale * max(1.0, np.abs(uk).max() ** 2))
        moving = m.body_weldid != 0  # eomgen's (and Pinocchio's) centre of mass: of the moving bodies
        com = m.body_mass[moving] @ d.xipos[moving] / m.body_mass[moving].sum()
        np.testing.assert_allclose(f.com(qk), d.subtree_com[1] if system.floating_base else com, rtol=0,
                                   atol=tol)
        for name, p, R in [*zip(bodies, d.xpos[1:], d.xmat[1:]), *zip(sites, d.site_xpos, d.site_xmat)]:
            R_ours, p_ours = f.placement(name, qk)
            np.testing.assert_allclose(p_ours, p, rtol=0, atol=tol, err_msg=name)
            np.testing.assert_allclose(R_ours, R.reshape(3, 3), rtol=0, atol=tol, err_msg=name)
