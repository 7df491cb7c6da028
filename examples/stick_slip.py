"""Stick-slip limit cycle of the Timoshenko element (Fig. 5.16, end of thesis section 5.3.2).

The thesis matched the damping k_i and Young's modulus E "to values such that a stick slip
vibration could be observed" and reports a deflection of 0.625 mm at 1111 Hz (simulated;
the squealing rig showed 1500 Hz). Here the element, contact and friction law of
``timoshenko_validation.py`` (G3 element, 2.5 bar, Eq. 5.24 fitted to Table 4.6, v0 = 1 m/s,
Eq. 5.25/5.26 with the axial terms) get a 100 times smaller damping, k_i = 10 us (a rubber
loss factor of ~0.07 at 1 kHz), and a stiffer E, calibrated so that the limit cycle runs at
the thesis's 1111 Hz. The falling characteristic then feeds energy into the first bending
mode faster than the damping removes it; the amplitude is a prediction.

Run: ``python examples/stick_slip.py``; writes ``examples/out/timoshenko/stick_slip.png``.
"""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import math

import matplotlib.pyplot as plt
import numpy as np

from friction_model import ArctanExponentialLaw, fit_law, table_4_6_targets
from friction_model.dynamics import velocity_ramp
from friction_model.dynamics.timoshenko import (
    TimoshenkoParams,
    natural_frequencies_timoshenko,
    preload_for_normal_force,
    simulate_timoshenko,
)

F_THESIS_HZ = 1111.0
F_RIG_HZ = 1500.0
R_THESIS_MM = 0.625
PRESSURE_PA = 2.5e5
DENSITY = 1150.0
K_I = 1e-5
V0 = 1.0
WINDOW_S = 0.03  # analysis window at the end of the run

out = Path(__file__).parent / "out" / "timoshenko"
out.mkdir(parents=True, exist_ok=True)

rows = table_4_6_targets()
rows = rows[rows["curve"] == "cold-dry 2.5 bar"]
law = fit_law(ArctanExponentialLaw, rows["velocity_mps"], rows["mu_target"], fixed={"k4": 50.0}).law


def make_params(E: float) -> TimoshenkoParams:
    area, height = 4.55e-3 * 80e-3, 6e-3  # G3 element (the TimoshenkoParams defaults)
    return TimoshenkoParams(
        E_Pa=E, density_kg_m3=DENSITY, kelvin_voigt_s=K_I, contact_stiffness_N_m=E * area / height
    )


def limit_cycle(E: float, t_end: float = 0.08):
    p = make_params(E)
    res = simulate_timoshenko(
        p,
        velocity=velocity_ramp(0.0, V0, 0.0, 0.01),
        preload=preload_for_normal_force(p, PRESSURE_PA * p.area_m2),
        friction=law,
        t_end_s=t_end,
        n_output=int(t_end * 2e5) + 1,  # 5 us samples
    )
    d = res.data[res.data["time_s"] > t_end - WINDOW_S]
    t, x = d["time_s"].to_numpy(), d["tip_deflection_mm"].to_numpy()
    xc = x - x.mean()
    i = np.flatnonzero((xc[:-1] < 0) & (xc[1:] >= 0))
    tc = t[i] - xc[i] * (t[i + 1] - t[i]) / (xc[i + 1] - xc[i])
    freq = (tc.size - 1) / (tc[-1] - tc[0]) if tc.size > 2 else 0.0
    return p, res, d, freq


# calibrate E on the limit-cycle frequency (f ~ sqrt(E), two secant steps in log-log)
E_a = 6e6
f_a = limit_cycle(E_a)[3]
E_b = E_a * (F_THESIS_HZ / f_a) ** 2
f_b = limit_cycle(E_b)[3]
slope = math.log(f_b / f_a) / math.log(E_b / E_a)
E = E_b * (F_THESIS_HZ / f_b) ** (1.0 / slope)
p, res, d, freq = limit_cycle(E, t_end=0.1)

x = d["tip_deflection_mm"].to_numpy()
v_rel = d["v_rel_mps"].to_numpy()
f1 = natural_frequencies_timoshenko(p, 1)[0]
spec = np.abs(np.fft.rfft((x - x.mean()) * np.hanning(x.size), n=1 << 18))
f_fft = np.fft.rfftfreq(1 << 18, d["time_s"].diff().median())[np.argmax(spec)]
print(f"stick-slip set: E = {E / 1e6:.2f} MPa (G = E/3), k_i = {K_I * 1e6:.0f} us, v0 = {V0} m/s")
print(f"  first natural frequency (frequency equation): {f1:.0f} Hz")
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
fig.tight_layout()
fig.savefig(out / "stick_slip.png", dpi=130)
print(f"wrote {out / 'stick_slip.png'}")
