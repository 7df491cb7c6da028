"""The solved element: displacement, pressure and the ice's reaction on the face."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from friction_model.continuum.model import ElementMesh

__all__ = ["ElementState"]


@dataclass
class ElementState:
    """One static solution of the element model.

    Attributes
    ----------
    mesh : ElementMesh
    displacement : ndarray
        The P2 displacement dofs, m.
    pressure : ndarray
        The P1 hydrostatic pressure dofs (mean stress, tension positive), Pa.
    face_force_N_per_m : ndarray
        Normal reaction of the ice on each face node (compressive, >= 0), per unit width,
        N/m; 0 where the node is not in contact.
    active : ndarray of bool
        Face nodes in contact with the ice.
    indentation_m : float
        How far the ice surface is pushed towards the root, m.
    normal_force_N : float
        The normal force on the whole width, N.
    mu : float
        Friction coefficient of the sliding face (tangential traction mu p).
    model : str
        ``"linear"`` or ``"neo-hookean"``.
    """

    mesh: ElementMesh
    displacement: np.ndarray
    pressure: np.ndarray
    face_force_N_per_m: np.ndarray
    active: np.ndarray
    indentation_m: float
    normal_force_N: float
    mu: float
    model: str

    @property
    def face_ux_m(self) -> np.ndarray:
        """x displacement of the face nodes (leading edge first), m."""
        return self.displacement[self.mesh.face_x]

    @property
    def face_uy_m(self) -> np.ndarray:
        """y displacement of the face nodes, m."""
        return self.displacement[self.mesh.face_y]

    @property
    def face_pressure_Pa(self) -> np.ndarray:
        """Contact pressure at the face nodes (nodal force over its Simpson weight), Pa."""
        return self.face_force_N_per_m / self.mesh.face_weights_m
