"""Stick-slip limit cycle of the Timoshenko element (Fig. 5.16, end of thesis section 5.3.2).

The thesis matched the damping k_i and Young's modulus E "to values such that a stick slip
vibration could be observed" and reports a deflection of 0.625 mm at 1111 Hz (simulated;
the squealing rig showed 1500 Hz). Nothing is tuned here: the element, load and friction
law of ``timoshenko_validation.py`` (G3 element, constant 91 N = 2.5 bar, Haringx
beam-column, Eq. 5.24 fitted to Table 4.6, v0 = 1 m/s) with the one rubber of
:data:`friction_model.compound.REFERENCE_COMPOUND`: the modulus at the frequency of the
vibration, E(f) of the causal constant-loss model (fixed point f = f1(E(f)) of the loaded
first mode), and the damping of its loss factor, k_i = tan(delta) / (2 pi f). Frequency and
amplitude are predictions; k4 (not determined by Table 4.6) is varied over 20-200 s/m.

Run: ``python examples/stick_slip.py [--out DIR]``; writes
``examples/out/timoshenko/stick_slip.png``.
"""

import matplotlib

matplotlib.use("Agg")

from dataclasses import replace

import matplotlib.pyplot as plt
import numpy as np
from _common import example_arguments, save_figure

from friction_model import ArctanExponentialLaw, fit_law, table_4_6_targets
from friction_model.compound import REFERENCE_COMPOUND
from friction_model.dynamics.stick_slip import limit_cycle_run, loaded_mode_at_own_modulus_Hz
from friction_model.dynamics.timoshenko import TimoshenkoParams

F_THESIS_HZ = 1111.0
F_RIG_HZ = 1500.0
R_THESIS_MM = 0.625
PRESSURE_PA = 2.5e5
V0 = 1.0
K4_VALUES = (20.0, 50.0, 200.0)  # s/m: interval of the unidentified zero-crossing steepness
WINDOW_S = 0.03  # analysis window at the end of the run

out = example_arguments(None, __doc__, "timoshenko").out

rows = table_4_6_targets()
rows = rows[rows["curve"] == "cold-dry 2.5 bar"]
rubber = REFERENCE_COMPOUND
base = TimoshenkoParams(
    E_Pa=rubber.E0_Pa,
    density_kg_m3=rubber.density_kg_m3,
    kelvin_voigt_s=0.0,
    contact_stiffness_N_m=1.0,  # unused: applied normal force
)
N = PRESSURE_PA * base.area_m2


def law_for(k4: float) -> ArctanExponentialLaw:
    return fit_law(
        ArctanExponentialLaw, rows["velocity_mps"], rows["mu_target"], fixed={"k4": k4}
    ).law


f1 = loaded_mode_at_own_modulus_Hz(base, N, rubber.storage_modulus_Pa)
E = rubber.storage_modulus_Pa(f1)
K_I = rubber.kelvin_voigt_s(f1)


def limit_cycle(k4: float, t_end: float = 0.08):
    p = replace(base, E_Pa=E, kelvin_voigt_s=K_I)
    res, d = limit_cycle_run(p, law_for(k4), N, V0, t_end, WINDOW_S)
    t, x = d["time_s"].to_numpy(), d["tip_deflection_mm"].to_numpy()
    xc = x - x.mean()
    i = np.flatnonzero((xc[:-1] < 0) & (xc[1:] >= 0))
    tc = t[i] - xc[i] * (t[i + 1] - t[i]) / (xc[i + 1] - xc[i])
    freq = (tc.size - 1) / (tc[-1] - tc[0]) if tc.size > 2 else 0.0
    return p, res, d, freq


for k4 in K4_VALUES:
    if k4 != 50.0:
        _, _, dk, fk = limit_cycle(k4)
        xk = dk["tip_deflection_mm"].to_numpy()
        print(f"k4 = {k4:g} s/m: {fk:.0f} Hz, amplitude {np.ptp(xk) / 2:.3f} mm")
p, res, d, freq = limit_cycle(50.0, t_end=0.1)

x = d["tip_deflection_mm"].to_numpy()
v_rel = d["v_rel_mps"].to_numpy()
spec = np.abs(np.fft.rfft((x - x.mean()) * np.hanning(x.size), n=1 << 18))
f_fft = np.fft.rfftfreq(1 << 18, d["time_s"].diff().median())[np.argmax(spec)]
print(
    f"one rubber: E(f) = {E / 1e6:.2f} MPa at f = {f1:.0f} Hz (E0 = {rubber.E0_Pa / 1e6:.2f} MPa),"
    f" k_i = {K_I * 1e6:.1f} us (tan(delta) = {rubber.loss_factor}), N = {N:.0f} N, v0 = {V0} m/s"
)
print(f"  first mode of the loaded element (fixed point f = f1(E(f))): {f1:.0f} Hz")
print(
    f"  limit cycle: {freq:.0f} Hz by zero crossings, {f_fft:.0f} Hz by FFT "
    f"(thesis simulation {F_THESIS_HZ:.0f} Hz, rig {F_RIG_HZ:.0f} Hz)"
)
print(
    f"  tip deflection: mean {x.mean():.3f} mm, amplitude {(x.max() - x.min()) / 2:.3f} mm, "
    f"range {x.min():.3f} .. {x.max():.3f} mm (thesis r_s = {R_THESIS_MM} mm)"
)
print(
    f"  v_rel: {v_rel.min():.3f} .. {v_rel.max():.2f} m/s, "
    f"{np.mean(v_rel < 0.05) * 100:.0f} % of the time below 0.05 m/s (quasi-stick: Eq. 5.24 "
    "has mu(0) = 0, so there is no true sticking)"
)
print(
    f"  wall time of the 0.1 s run: {res.meta['wall_time_s']:.1f} s ({res.meta['n_steps']} steps)"
)

# -- figure: deflection over time, detail with v_rel, limit cycle (Fig. 5.16 a-c) ----------
fig, axes = plt.subplots(1, 3, figsize=(13, 4))
all_t = res.data["time_s"].to_numpy() * 1e3
axes[0].plot(all_t, res.data["tip_deflection_mm"], lw=0.5)
axes[0].set_xlabel("time / ms")
axes[0].set_ylabel("tip deflection r(d) / mm")
axes[0].set_title("a) deflection", fontsize=9)

detail = d[d["time_s"] > d["time_s"].max() - 0.004]
t_ms = detail["time_s"].to_numpy() * 1e3
axes[1].plot(t_ms, detail["tip_deflection_mm"], "C0")
axes[1].set_xlabel("time / ms")
axes[1].set_ylabel("tip deflection / mm", color="C0")
ax_v = axes[1].twinx()
ax_v.plot(t_ms, detail["v_rel_mps"], "C3", lw=0.8)
ax_v.set_ylabel("v_rel / (m/s)", color="C3")
axes[1].set_title(f"b) detail: {freq:.0f} Hz", fontsize=9)

tip_velocity = V0 - v_rel
axes[2].plot(x, tip_velocity, lw=0.6)
axes[2].set_xlabel("tip deflection r(d) / mm")
axes[2].set_ylabel("tip velocity dr/dt(d) / (m/s)")
axes[2].set_title("c) limit cycle", fontsize=9)
save_figure(fig, out / "stick_slip.png")
print(f"wrote {out / 'stick_slip.png'}")
