"""Frame placements, the centre of mass and the centroidal momentum as generated functions (NumPy and C
alike; formulas in `eomgen.centroidal`)."""
from __future__ import annotations

import numpy as np
import sympy as sp

from .. import centroidal


def placement(kin, frame: str) -> sp.Matrix:
    """[R | p] (3 × 4) of a frame or body in the world."""
    return sp.Matrix.hstack(*kin.frame_placement(frame))


class KinematicFunctions:
    """Mixed into `NumericEoM`: every function takes one state or N states along axis 0."""

    def placement(self, frame: str, q, params=None) -> tuple[np.ndarray, np.ndarray]:
        """(R, p) of a frame or body in the world (Pinocchio's `oMf` rotation and translation)."""
        self._function(key := f"X:{frame}", lambda: placement(self.eom.kinematics, frame))
        X = self.call(key, q, params=params)
        return X[..., :3], X[..., 3]

    def com(self, q, params=None) -> np.ndarray:
        """Centre of mass c (world), Pinocchio's `centerOfMass`."""
        self._function("com", lambda: centroidal.com(self.eom.kinematics))
        return self.call("com", q, params=params)[..., 0]

    def com_jacobian(self, q, params=None) -> np.ndarray:
        """J_com (3 × n), Pinocchio's `jacobianCenterOfMass`."""
        self._function("J_com", lambda: centroidal.com_jacobian(self.eom.kinematics))
        return self.call("J_com", q, params=params)

    def centroidal_momentum_matrix(self, q, params=None) -> np.ndarray:
        """A_G (6 × n, [linear; angular about the centre of mass], world axes), Pinocchio's `ccrba`."""
        self._function("A_G", lambda: centroidal.centroidal_momentum_matrix(self.eom.kinematics))
        return self.call("A_G", q, params=params)

    def centroidal_momentum(self, q, u, params=None) -> np.ndarray:
        """h_G = A_G u (6,): linear momentum and angular momentum about the centre of mass."""
        A_G = self.centroidal_momentum_matrix(q, params)
        return np.einsum("...ij,...j->...i", A_G, np.asarray(u, float))
