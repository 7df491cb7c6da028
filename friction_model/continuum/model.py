"""One tread-block element as a plane-strain continuum: geometry, rubber and mesh.

The element (sipe depth d, length l in the sliding direction, width w across it) is a
rectangle in the (x, y) plane: x along the sliding direction, centred on the element's axis,
y from the root (y = 0, where the element leaves the block base) to the face (y = d) that
touches the ice. The width (80 mm, w / l about 17) makes the element bend in plane strain;
forces are reported for the whole width. The root is clamped, or the element stands on a
compliant base layer (the block under the sipes) whose bottom is clamped.

Coordinates: +x is the direction in which the ice moves relative to the element root (the
``r > 0`` of :mod:`friction_model.dynamics.timoshenko`); the leading edge of the sliding
element is at x = -l/2.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from friction_model.compound import REFERENCE_COMPOUND, Compound
from friction_model.continuum._skfem import require_skfem
from friction_model.geometry import reference_block
from tir_common.validate import check_nonnegative, check_range

__all__ = ["ElementMesh", "ElementSpec", "build_mesh"]


@dataclass(frozen=True)
class ElementSpec:
    """Geometry, rubber and mesh density of one element.

    Parameters
    ----------
    height_m : float
        Sipe depth d (root to face), m; default 6 mm (chapter 5).
    length_m : float
        Element length l in the sliding direction, m; default 4.55 mm (a G3 element).
    width_m : float
        Element width w across the sliding direction, m (plane strain); default 80 mm.
    youngs_modulus_Pa : float
        E, Pa; default E0 of the one rubber (Gent, Shore A 60: 3.61 MPa).
    poisson_ratio : float
        nu in [0, 0.5]; 0.5 (incompressible) is allowed by the mixed u-p formulation.
    density_kg_m3 : float
        rho, kg/m^3.
    base_thickness_m : float
        Thickness of a compliant base layer under the root, m; 0 (default) clamps the root.
    base_margin_m : float
        How far the base layer reaches beyond each side of the element, m.
    n_length : int
        Elements (triangle pairs) across the length; the depth gets as many per unit length.
    """

    height_m: float = 6e-3
    length_m: float = 4.55e-3
    width_m: float = 80e-3
    youngs_modulus_Pa: float = REFERENCE_COMPOUND.E0_Pa
    poisson_ratio: float = REFERENCE_COMPOUND.poisson_ratio
    density_kg_m3: float = REFERENCE_COMPOUND.density_kg_m3
    base_thickness_m: float = 0.0
    base_margin_m: float = 2.5e-3
    n_length: int = 8

    def __post_init__(self) -> None:
        check_range("height_m", self.height_m, 1e-5, 1.0, unit="m")
        check_range("length_m", self.length_m, 1e-5, 1.0, unit="m")
        check_range("width_m", self.width_m, 1e-5, 10.0, unit="m")
        check_range("youngs_modulus_Pa", self.youngs_modulus_Pa, 1e3, 1e12, unit="Pa")
        check_range("poisson_ratio", self.poisson_ratio, 0.0, 0.5)
        check_range("density_kg_m3", self.density_kg_m3, 100.0, 3e4, unit="kg/m^3")
        check_nonnegative("base_thickness_m", self.base_thickness_m)
        check_nonnegative("base_margin_m", self.base_margin_m)
        if int(self.n_length) != self.n_length or not 2 <= self.n_length <= 256:
            raise ValueError(f"n_length must be an integer in [2, 256], got {self.n_length!r}")

    @classmethod
    def from_preset(
        cls, name: str = "G3", *, element: int = 0, compound: Compound = REFERENCE_COMPOUND,
        **fields: Any,
    ) -> ElementSpec:
        """The element ``element`` of the reference sample ``name`` with ``compound``'s rubber.

        Examples
        --------
        >>> round(ElementSpec.from_preset("G3").length_m * 1e3, 2)
        4.55
        """
        block = reference_block(name)
        lengths = block.element_lengths
        if not 0 <= element < lengths.size:
            raise ValueError(f"element must lie in [0, {lengths.size - 1}] for {name}")
        spec = cls(
            height_m=block.height_mm * 1e-3,
            length_m=float(lengths[element]) * 1e-3,
            width_m=block.width_mm * 1e-3,
            youngs_modulus_Pa=compound.E0_Pa,
            poisson_ratio=compound.poisson_ratio,
            density_kg_m3=compound.density_kg_m3,
        )
        return replace(spec, **fields)

    @property
    def shear_modulus_Pa(self) -> float:
        """mu = E / (2 (1 + nu)), Pa."""
        return self.youngs_modulus_Pa / (2.0 * (1.0 + self.poisson_ratio))

    @property
    def inverse_lame_Pa(self) -> float:
        """1 / lambda = (1 - 2 nu) / (2 mu nu), 1/Pa (0 when incompressible)."""
        nu = self.poisson_ratio
        if nu == 0.0:
            raise ValueError("poisson_ratio 0 has lambda = 0; use nu > 0 with the mixed model")
        return (1.0 - 2.0 * nu) / (2.0 * self.shear_modulus_Pa * nu)

    @property
    def n_height(self) -> int:
        """Elements along the depth (the element size of the length direction)."""
        return max(2, math.ceil(self.n_length * self.height_m / self.length_m))


@dataclass
class ElementMesh:
    """The mesh, the Taylor-Hood bases and the boundary dofs of one element.

    Attributes
    ----------
    spec : ElementSpec
    mesh : skfem.MeshTri
        Triangles, coordinates in m.
    basis_u, basis_p : skfem.Basis
        P2 vector displacement and P1 pressure (Taylor-Hood), one quadrature.
    basis_scalar : skfem.Basis
        Scalar P2 (the dofs of one displacement component, for probing).
    fixed : ndarray
        Displacement dofs clamped (the root, or the bottom of the base layer).
    face_x, face_y : ndarray
        The x and y displacement dofs of the face nodes, ordered from the leading edge.
    face_x_m : ndarray
        Reference x of those nodes, m.
    face_weights_m : ndarray
        Integration weights of the face nodes (exact for quadratics along the face), m.
    """

    spec: ElementSpec
    mesh: Any
    basis_u: Any
    basis_p: Any
    basis_scalar: Any
    fixed: np.ndarray
    face_x: np.ndarray
    face_y: np.ndarray
    face_x_m: np.ndarray
    face_weights_m: np.ndarray

    @property
    def n_u(self) -> int:
        """Number of displacement dofs."""
        return int(self.basis_u.N)

    @property
    def n_p(self) -> int:
        """Number of pressure dofs."""
        return int(self.basis_p.N)


def _grid(spec: ElementSpec) -> tuple[np.ndarray, np.ndarray]:
    """Node lines in x and y (the base layer adds lines outside the element), m."""
    half = 0.5 * spec.length_m
    h = spec.length_m / spec.n_length
    xs = np.linspace(-half, half, spec.n_length + 1)
    ys = np.linspace(0.0, spec.height_m, spec.n_height + 1)
    if spec.base_thickness_m > 0:
        if spec.base_margin_m > 0:
            nm = max(1, math.ceil(spec.base_margin_m / h))
            side = np.linspace(half, half + spec.base_margin_m, nm + 1)[1:]
            xs = np.concatenate([-side[::-1], xs, side])
        nb = max(1, math.ceil(spec.base_thickness_m / h))
        ys = np.concatenate([np.linspace(-spec.base_thickness_m, 0.0, nb + 1)[:-1], ys])
    return xs, ys


def _face_weights(x: np.ndarray) -> np.ndarray:
    """Simpson weights of P2 nodes along the face (vertex, midside alternating)."""
    w = np.zeros_like(x)
    for i in range(0, x.size - 2, 2):
        h = x[i + 2] - x[i]
        w[i : i + 3] += np.array([1.0, 4.0, 1.0]) * h / 6.0
    return w


def build_mesh(spec: ElementSpec, *, intorder: int = 4) -> ElementMesh:
    """Mesh the element (and its base layer) with P2-P1 Taylor-Hood triangles.

    Parameters
    ----------
    spec : ElementSpec
    intorder : int
        Quadrature order (4 integrates the P2 stiffness exactly on straight triangles).

    Returns
    -------
    ElementMesh

    Examples
    --------
    >>> m = build_mesh(ElementSpec(n_length=4))
    >>> m.face_x_m.size, round(float(m.face_weights_m.sum()) * 1e3, 2)
    (9, 4.55)
    """
    skfem = require_skfem()
    xs, ys = _grid(spec)
    mesh = skfem.MeshTri.init_tensor(xs, ys)
    half = 0.5 * spec.length_m
    tol = 1e-9 * spec.length_m
    if spec.base_thickness_m > 0:
        mid = mesh.p[:, mesh.t].mean(axis=1)
        outside = (mid[1] > 0) & (np.abs(mid[0]) > half)
        mesh = mesh.remove_elements(np.flatnonzero(outside))
    basis_u = skfem.Basis(mesh, skfem.ElementVector(skfem.ElementTriP2()), intorder=intorder)
    basis_p = skfem.Basis(mesh, skfem.ElementTriP1(), quadrature=basis_u.quadrature)
    basis_scalar = skfem.Basis(mesh, skfem.ElementTriP2(), quadrature=basis_u.quadrature)
    y_root = -spec.base_thickness_m if spec.base_thickness_m > 0 else 0.0
    fixed = basis_u.get_dofs(lambda x: np.abs(x[1] - y_root) < tol).all()
    face = basis_u.get_dofs(
        lambda x: (np.abs(x[1] - spec.height_m) < tol) & (np.abs(x[0]) <= half + tol)
    )
    fx = np.concatenate([face.nodal["u^1"], face.facet["u^1"]])
    fy = np.concatenate([face.nodal["u^2"], face.facet["u^2"]])
    fx = fx[np.argsort(basis_u.doflocs[0, fx])]
    fy = fy[np.argsort(basis_u.doflocs[0, fy])]
    x = basis_u.doflocs[0, fx]
    return ElementMesh(
        spec=spec, mesh=mesh, basis_u=basis_u, basis_p=basis_p, basis_scalar=basis_scalar,
        fixed=np.asarray(fixed),
        face_x=fx, face_y=fy, face_x_m=x, face_weights_m=_face_weights(x),
    )
