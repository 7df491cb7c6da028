"""The FE contact of the element seen through a rendered TIR clip and the pipeline (issue 24).

The renderer's element contacts (interval, pressure profile) are replaced, for this test
only, by the neo-Hookean element's face contact (:mod:`friction_model.continuum`): every G3
element of the clip touches the ice as the FE element does. The pipeline
(:mod:`tir_contact`: darkness, segmentation, per-element features) then measures contact
length, lift-off and the front-edge peak from the images alone, and they are checked
against the FE values, not against the renderer's truth table. Tolerances: 1 px (0.1 mm)
for lengths, as the pipeline's own feature tests (measured: 3.801 mm against the FE's 3.794,
lift-off 0.749 against 0.756); the peak within 2 px of the FE's peak, which sits on the
leading corner (measured 0.16 mm behind the edge: the darkness saturates there and the
pipeline's band is a pixel wide).

The hook is a monkeypatch of ``synthetic.footage.element_contacts`` (the renderer is left
as it is).
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from _footage import STEADY_SETTLE_S

pytest.importorskip("skfem")

import synthetic.footage as footage
from friction_model.continuum import ElementSpec, face_contact, solve_element
from friction_model.geometry import reference_block
from synthetic._render_tir import ElementContact
from synthetic.footage import CameraSettings, FootageSpec, iter_frames
from tir_contact.features import BlockLayout, tir_frame_features
from tir_contact.flatfield import darkness, reference_from_frames
from tir_contact.segment import segment_frame

PX, FPS, N_FRAMES = 0.1, 1500.0, 150
MU_G3, N_G3 = 0.2936, 91.0


def fe_contact(spacing_mm: float = 0.0125) -> tuple[ElementContact, dict[str, float]]:
    """The neo-Hookean G3 element's face contact as a renderer ElementContact (mm, Pa)."""
    spec = ElementSpec.from_preset("G3", n_length=8)
    state = solve_element(spec, normal_force_N=N_G3, mu=MU_G3, model="neo-hookean")
    c = face_contact(state)
    x = (state.mesh.face_x_m + state.face_ux_m) * 1e3
    p = state.face_pressure_Pa
    lead = x[0] + c["front_lift_m"] * 1e3
    z_end = c["contact_length_m"] * 1e3
    nodes = np.arange(0.0, z_end + 1e-12, spacing_mm)
    nodes[-1] = z_end
    act = state.active
    prof = np.interp(nodes, x[act] - lead, p[act], right=0.0)
    prof[-1] = 0.0  # the pressure vanishes where the face leaves the ice
    force = float(np.sum(0.5 * (prof[1:] + prof[:-1]) * np.diff(nodes))) * spec.width_m * 1e-3
    centroid = np.sum(0.5 * (prof[1:] * nodes[1:] + prof[:-1] * nodes[:-1]) * np.diff(nodes))
    centroid /= np.sum(0.5 * (prof[1:] + prof[:-1]) * np.diff(nodes))
    ell = spec.length_m * 1e3
    contact = ElementContact(
        zeta_start_mm=0.0, zeta_end_mm=z_end, nodes_mm=nodes, pressure_Pa=prof,
        peak_zeta_mm=float(nodes[np.argmax(prof)]), peak_pressure_Pa=float(prof.max()),
        lever_arm_mm=0.5 * ell - float(centroid), force_N=force)
    return contact, {"contact_length_mm": z_end, "liftoff_mm": ell - z_end,
                     "peak_zeta_mm": float(x[act][np.argmax(p[act])] - lead)}


@pytest.fixture(scope="module")
def measured():
    contact, fe = fe_contact()
    patch = pytest.MonkeyPatch()
    patch.setattr(footage, "element_contacts",
                  lambda frame, params, node_spacing_mm: [contact] * frame.n_elements)
    try:
        spec = FootageSpec(preset="G3", n_frames=N_FRAMES, velocity_mps=1.0,
                           dynamics="steady", settle_s=STEADY_SETTLE_S,
                           camera=CameraSettings(fps=FPS), seed=5)
        frames = list(iter_frames(spec))
    finally:
        patch.undo()
    ref = reference_from_frames((f for _, f, _ in frames), n_total=len(frames))
    g = reference_block("G3")
    layout = BlockLayout.from_meta({
        "mm_per_px": PX, "sliding_direction": "left",
        "center_time_s": (N_FRAMES - 1) / (2 * FPS),
        "block": {"element_lengths_mm": g.element_lengths.tolist(),
                  "sipe_width_mm": g.sipe_width_mm, "height_mm": g.height_mm,
                  "width_mm": g.width_mm},
        "conditions": {"velocity_mps": 1.0},
    })
    rows = []
    for k, image, _ in frames:
        d = darkness(image, ref)
        f = tir_frame_features(d, segment_frame(d), layout, valid=ref.valid, time_s=k / FPS)
        rows.append(f.elements.assign(frame=k))
    el = pd.concat(rows, ignore_index=True)
    return el[el["liftoff_mm"].notna()], fe


@pytest.mark.slow
def test_pipeline_sees_the_fe_contact_length_and_liftoff(measured):
    el, fe = measured
    assert len(el) > 40  # whole elements in view over many frames
    assert (el["contact_length_mm"] - fe["contact_length_mm"]).abs().median() <= 0.1
    assert (el["liftoff_mm"] - fe["liftoff_mm"]).abs().median() <= 0.1
    assert fe["liftoff_mm"] > 0.5  # the neo-Hookean element lifts off measurably (> 5 px)


@pytest.mark.slow
def test_pipeline_front_peak_sits_at_the_fe_leading_edge(measured):
    el, fe = measured
    peak = el[el["front_peak_x_mm"].notna()]
    offset = (peak["front_peak_x_mm"] - peak["front_edge_x_mm"]).abs()
    assert offset.median() == pytest.approx(fe["peak_zeta_mm"], abs=2 * PX)

