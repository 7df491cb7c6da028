"""One tread-block element as a plane-strain continuum (finite elements, scikit-fem).

A reference for the beam models of chapter 5 and for what the TIR pipeline measures: the
element clamped at its root (optionally on a compliant base layer), its face on the ice as
a frictional contact (non-penetration; tangential traction mu(v) p while sliding), loaded by
the normal force and dragged. The rubber is nearly incompressible: mixed u-p Taylor-Hood
triangles (P2 displacement, P1 pressure) do not lock. Linear elasticity
(:func:`solve_linear`) and neo-Hookean large strain (:func:`solve_neo_hookean`).

scikit-fem is an optional extra (``pip install 'tir-contact[fem]'``): this package imports
without it and a model build raises one clear ImportError when it is missing.

Public API
----------
Model and solution
    :class:`ElementSpec`, :func:`build_mesh`, :class:`ElementMesh`, :func:`solve_linear`,
    :func:`solve_neo_hookean`, :func:`solve_element`, :class:`ElementState`.
Outputs
    :func:`element_outputs`, :class:`ElementOutputs`, :func:`section_profile`,
    :func:`face_contact`, :func:`modal_frequencies`, :func:`own_modulus_frequency_Hz`,
    :func:`analyse_element`, :class:`ElementAnalysis`.
Against the beam
    :func:`lever_arm_sweep`, :func:`fit_lever_arm_law`, :func:`beam_steady_state`,
    :func:`winkler_contact_length`, :func:`continuum_vs_beam`.
"""

from friction_model.continuum._skfem import require_skfem
from friction_model.continuum.analysis import (
    MODELS,
    ElementAnalysis,
    analyse_element,
    solve_element,
)
from friction_model.continuum.compare import continuum_vs_beam
from friction_model.continuum.hyperelastic import solve_neo_hookean
from friction_model.continuum.lever_law import (
    beam_steady_state,
    fit_lever_arm_law,
    lever_arm_sweep,
    winkler_contact_length,
)
from friction_model.continuum.linear import solve_linear
from friction_model.continuum.model import ElementMesh, ElementSpec, build_mesh
from friction_model.continuum.modes import modal_frequencies, own_modulus_frequency_Hz
from friction_model.continuum.outputs import (
    ElementOutputs,
    element_outputs,
    face_contact,
    section_profile,
)
from friction_model.continuum.state import ElementState

__all__ = [
    "MODELS",
    "ElementAnalysis",
    "ElementMesh",
    "ElementOutputs",
    "ElementSpec",
    "ElementState",
    "analyse_element",
    "beam_steady_state",
    "build_mesh",
    "continuum_vs_beam",
    "element_outputs",
    "face_contact",
    "fit_lever_arm_law",
    "lever_arm_sweep",
    "modal_frequencies",
    "own_modulus_frequency_Hz",
    "require_skfem",
    "section_profile",
    "solve_element",
    "solve_linear",
    "solve_neo_hookean",
    "winkler_contact_length",
]
