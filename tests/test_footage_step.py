"""Velocity step and friction relaxation (Eq. 5.12) in the synthetic footage."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from friction_model.compound import REFERENCE_COMPOUND
from friction_model.contact.laws import ExponentialLaw, RelaxedFriction
from friction_model.dynamics import velocity_step
from friction_model.dynamics.rigid import BlockParams, simulate_block_dynamics
from synthetic import footage
from synthetic.footage import CameraSettings, FootageSpec, iter_frames

V1, V2, T_STEP, TAU, FPS, SETTLE = 1.0, 5.0, 0.01, 0.02, 2000.0, 0.05
N_FRAMES = 201  # 0 .. 0.1 s: 10 ms before the step, 90 ms (4.5 tau) after it


def _step_spec(**kw) -> FootageSpec:
    # a small, noise-free side view (the camera follows the block); 2000 frames/s resolves
    # the 20 ms relaxation with 40 samples per tau
    base = {
        "preset": "G3",
        "view": "side",
        "follow_camera": True,
        "velocity_mps": V1,
        "velocity_step_to_mps": V2,
        "step_time_s": T_STEP,
        "friction_relaxation_s": TAU,
        "n_frames": N_FRAMES,
        "settle_s": SETTLE,
        "noise": False,
        "camera": CameraSettings(fps=FPS, width_px=256, height_px=160, n_bubbles=0,
                                 n_dust=0),
    }
    base.update(kw)
    return FootageSpec(**base)


def _truth(spec: FootageSpec, element: int = 0) -> pd.DataFrame:
    rows = [t[t["element"] == element] for _, _, t in iter_frames(spec)]
    return pd.concat(rows, ignore_index=True)


@pytest.fixture(scope="module")
def step_truth() -> pd.DataFrame:
    return _truth(_step_spec())


def test_truth_is_the_rigid_model_with_the_step_and_relaxation(step_truth):
    # independent run of the rigid block model with the same block, law (Eq. 5.7 with the
    # footage's constants, relaxed by Eq. 5.12) and step at settle_s + step_time_s: the
    # rendered tip deflection is the model's at every frame
    params = BlockParams(n_elements=4, height_m=6e-3, element_length_m=(4.55e-3,) * 4,
                         width_m=0.08, sipe_width_m=0.6e-3, contact_model="face",
                         loss_factor=REFERENCE_COMPOUND.loss_factor)
    load = 2.5e5 * 20e-3 * 80e-3
    preload = 6e-3 - load / (params.youngs_modulus_Pa * 4 * 4.55e-3 * 0.08 / 6e-3)
    law = RelaxedFriction(ExponentialLaw(a1=0.15, a2=0.25, a3=-0.8), tau_s=TAU)
    t_end = (round(SETTLE * FPS) + N_FRAMES - 0.75) / FPS
    res = simulate_block_dynamics(params, velocity=velocity_step(V1, V2, SETTLE + T_STEP),
                                  preload=preload, friction=law, t_end_s=t_end,
                                  output_step_s=1 / FPS, solver=footage._SOLVER)
    d = res.data[res.data["element"] == 0]
    expected = d["tip_deflection_mm"].to_numpy()[round(SETTLE * FPS):]
    # the same integration with the same tolerances: equal to rounding of the CSV values
    # (9 significant digits) -- a shifted step (one frame = 0.5 ms) would move the values
    # by up to ~0.02 mm
    np.testing.assert_allclose(step_truth["tip_deflection_mm"], expected, rtol=1e-6,
                               atol=1e-9)


def test_deflection_lags_the_step_by_tau(step_truth):
    t = step_truth["time_s"].to_numpy() - T_STEP
    a = step_truth["deflection_angle_deg"].to_numpy()
    before = a[(t > -0.005) & (t < 0)].mean()
    # the new level: the exponential tail extrapolated (90 ms = 4.5 tau leaves 1.1 % of the
    # change): level = a(end) - (a(end - 10 ms) - a(end)) * q / (1 - q), q = exp(-10/20)
    q = np.exp(-0.010 / TAU)
    a_end, a_prev = a[-1], a[t <= t[-1] - 0.010 + 1e-9][-1]
    after = a_end - (a_prev - a_end) * q / (1 - q)
    assert before - after > 1.0  # 1 -> 5 m/s lowers mu from 0.262 to 0.154: ~3 deg
    # the angle before the step is steady: the lead-in has settled
    assert np.ptp(a[(t > -0.005) & (t < 0)]) < 0.01
    # within one frame after the step the angle has not dropped by more than 10 %: the
    # relaxation, not the element's own ~1 ms response, sets the pace
    frac = (before - a) / (before - after)
    assert frac[t > 0][0] < 0.1
    # 63 % of the change after tau (first-order lag, Eq. 5.12), interpolated between
    # frames; tolerance 10 % of tau: the element follows mu with a lag of ~1/(2 pi 600 Hz)
    # = 0.3 ms, and the angle is not exactly linear in mu (measured: 21.5 ms)
    k = np.flatnonzero((t > 0) & (frac >= 1 - np.exp(-1)))[0]
    t63 = np.interp(1 - np.exp(-1), frac[k - 1 : k + 1], t[k - 1 : k + 1])
    assert t63 == pytest.approx(TAU, rel=0.1)


@pytest.mark.slow
def test_no_relaxation_reaches_the_new_level_within_a_few_ms():
    # the control: without Eq. 5.12 the element settles on the new level within ~8 ms
    # (the element dynamics alone), far faster than tau. The first ms after the step are a
    # stick-slip burst whose phase follows the integrator's step choice (at 5 ms 0.0 %,
    # 12.7 % and 5.2 % of the step off the new level at rtol 1e-4, 1e-5, 1e-6); from 8 ms on
    # every tolerance is within 0.5 %, so 5 % there is a margin of ten
    # A rubber damped at tan(delta) = 0.4: with the one rubber's 0.2 the element at 3 m/s
    # stays in a stick-slip cycle after the step (Eq. 5.7 falls with the velocity) and has no
    # new level to settle on; this control is about the element's settling, not the rubber.
    spec = _step_spec(friction_relaxation_s=0.0, velocity_mps=3.0, n_frames=61,
                      loss_factor=0.4)
    truth = _truth(spec)
    t = truth["time_s"].to_numpy() - T_STEP
    a = truth["deflection_angle_deg"].to_numpy()
    after = a[t > 0.015].mean()
    assert np.all(np.abs(a[t >= 0.008] - after) < 0.05 * abs(a[0] - after))


def test_block_travel_integrates_the_velocity():
    spec = _step_spec()
    # travel per frame: v1 / fps before the step, v2 / fps after (mm)
    d = [spec.travel_since_mm(k / FPS, (k + 1) / FPS) for k in range(N_FRAMES - 1)]
    k_step = round(T_STEP * FPS)
    np.testing.assert_allclose(d[:k_step], V1 / FPS * 1e3, rtol=1e-12)
    np.testing.assert_allclose(d[k_step:], V2 / FPS * 1e3, rtol=1e-12)
    assert spec.velocity_at(T_STEP - 1e-9) == V1 and spec.velocity_at(T_STEP) == V2


def test_spec_without_the_new_fields_is_unchanged():
    # to_dict (and so meta.json) keeps exactly the keys it had before the step existed
    old_keys = ["preset", "view", "velocity_mps", "n_frames", "pressure_bar",
                "temperature_C", "humidity_pct", "salinity_pct", "sliding_direction",
                "contact_is", "camera", "seed", "noise", "follow_camera", "dynamics",
                "settle_s", "friction", "loss_factor", "center_time_s",
                "lateral_offset_mm", "contrast", "contrast_max", "pressure_ref_MPa",
                "edge_band_mm", "block"]
    plain = FootageSpec(view="side", n_frames=3, dynamics="steady", settle_s=0.004)
    assert list(plain.to_dict()) == old_keys
    assert "velocity_step_to_mps" in _step_spec().to_dict()
    # ground truth of this spec against its converged value. The clip's model is integrated
    # with LSODA at rtol 1e-4 (synthetic.footage._SOLVER); its "steady" value is the mean over
    # the last 30 % of a 4 ms run that ends inside a stick-slip cycle, so it moves with the
    # solver's steps. Tolerance 10 x rtol (1e-3 relative, ~0.01 deg, the accuracy the
    # renderer needs); a 1 % change of the physics fails (at loss factor 0.4, before the one
    # rubber: 10.1934 deg on scipy 1.17 and 10.1961 deg on another environment's against
    # the converged 10.19216 deg, all within 4e-4). The front edge is a fixed 22 mm of
    # geometry plus the tip deflection, so it carries the tip's absolute error (1e-3 x 1.08 mm).
    # With scipy 1.10 the same integration starts the slip 0.1 ms later and gives 11.03 deg
    # (+8 %): a real loss of accuracy of the rtol-1e-4 model, which this test reports.
    truth = pd.concat([t for _, _, t in iter_frames(plain)], ignore_index=True)
    row = truth[(truth["frame"] == 1) & (truth["element"] == 0)].iloc[0]
    np.testing.assert_allclose(
        [row["deflection_angle_deg"], row["tip_deflection_mm"]], CONVERGED_G3_STEADY[:2],
        rtol=1e-3)
    assert row["front_edge_x_mm"] == pytest.approx(CONVERGED_G3_STEADY[2], abs=1.1e-3)


#: Element 0, frame 1 of FootageSpec(view="side", n_frames=3, dynamics="steady",
#: settle_s=0.004): deflection_angle_deg, tip_deflection_mm, front_edge_x_mm, from the same
#: model integrated to convergence (rtol 1e-8, atol 1e-12), with the one rubber's loss factor
#: 0.2 (friction_model.compound; at 0.4 it was 10.19216 deg, 1.083475 mm, 23.135013 mm). The
#: renderer's own rtol-1e-4 run gives 10.99973 deg (3e-6 relative) with scipy 1.17.1.
CONVERGED_G3_STEADY = [10.99970, 1.166964, 23.226769]


@pytest.mark.parametrize(
    ("kw", "match"),
    [
        ({"velocity_step_to_mps": 5.0}, "step_time_s must be given"),
        ({"step_time_s": 0.01}, "step_time_s needs velocity_step_to_mps"),
        ({"velocity_step_to_mps": 0.0, "step_time_s": 0.01}, "velocity_step_to_mps must lie"),
        ({"velocity_step_to_mps": 5.0, "step_time_s": 1.0}, "step_time_s must lie"),
        ({"velocity_step_to_mps": 5.0, "step_time_s": 0.01, "dynamics": "steady"},
         "dynamics must be 'simulated'"),
        ({"friction_relaxation_s": -0.01}, "friction_relaxation_s must lie"),
    ],
)
def test_bad_step_fields_raise_naming_the_field(kw, match):
    with pytest.raises(ValueError, match=match):
        FootageSpec(**kw)
