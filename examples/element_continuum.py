"""The G3 tread-block element as a plane-strain continuum against the Timoshenko beam.

One element of the thesis's three-siped block (d = 6 mm, l = 4.55 mm, w = 80 mm), the one
rubber (Shore A 60 -> E0 = 3.61 MPa, nu = 0.5), 2.5 bar on its face (91 N) and the friction
of Eq. 5.24 fitted to Table 4.6 at 1 m/s (mu = 0.294). Models: the Haringx Timoshenko
beam-column with the lever arm of Fig. 5.12 a (the README's chapter-5 predictions), the
linear and the neo-Hookean finite-element element with its face on the ice (frictional
contact, mixed P2-P1), and the beam run with Eq. 5.21 refitted to the neo-Hookean lever
arm over the tip rotation. Nothing is fitted to a chapter-5 number.

Run: ``python examples/element_continuum.py --out DIR`` (needs ``pip install
'tir-contact[fem]'``); writes ``continuum_vs_beam.csv``, ``continuum_vs_beam.md``,
``lever_arm_sweep.csv``, ``face_pressure.csv``, ``section_profile.csv`` (deflection,
section rotation, slope and shear along the depth: the bending / shear split) and
``element_continuum.png`` (deformed mesh
with the face pressure, the pressure along the face, the lever arm over the tilt).
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from _common import OUT_ROOT, save_figure

from friction_model.continuum import (
    ElementSpec,
    continuum_vs_beam,
    element_outputs,
    section_profile,
    solve_element,
)
from friction_model.dynamics.timoshenko import TimoshenkoParams, lever_arm
from tir_common.atomic import atomic_write, write_json

COLUMNS = ["model", "tip_deflection_mm", "tip_slope_deg", "bending_deg", "lever_arm_mm",
           "contact_length_mm", "liftoff_mm", "front_pressure_ratio", "max_rotation_deg",
           "first_mode_sliding_Hz", "first_mode_stuck_Hz", "stick_slip_Hz", "status"]


def markdown(table) -> str:
    """The comparison as a Markdown table (blank where a model has no such number)."""
    def cell(v):
        if isinstance(v, str):
            return v
        return "" if not np.isfinite(v) else f"{v:.3g}" if abs(v) < 100 else f"{v:.0f}"

    cols = [c for c in COLUMNS if c in table.columns and c != "status"]
    lines = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    lines += ["| " + " | ".join(cell(row[c]) for c in cols) + " |" for _, row in table.iterrows()]
    return "\n".join(lines) + "\n"


def figure(cmp, path: Path) -> None:
    """Deformed neo-Hookean mesh coloured by the pressure, face pressure, lever arm."""
    st = cmp.neo_hookean.state
    em = st.mesh
    fig, axes = plt.subplots(1, 3, figsize=(13, 4.2))
    ax = axes[0]
    p = em.mesh.p
    nodes = em.basis_u.nodal_dofs
    xd = (p[0] + st.displacement[nodes[0]]) * 1e3
    yd = (p[1] + st.displacement[nodes[1]]) * 1e3
    tri = em.mesh.t.T
    tpc = ax.tripcolor(xd, yd, tri, -st.pressure[: p.shape[1]] / 1e6, shading="gouraud",
                       cmap="viridis")
    ax.triplot(xd, yd, tri, color="w", lw=0.2)
    fx = (em.face_x_m + st.face_ux_m) * 1e3
    ice_mm = (em.spec.height_m - st.indentation_m) * 1e3
    ax.bar(fx, st.face_pressure_Pa / 2e6, width=0.05, bottom=ice_mm, color="r", alpha=0.6)
    ax.axhline(ice_mm, color="c", lw=1)
    ax.set_aspect("equal")
    ax.set_xlabel("x / mm (ice moves to +x)")
    ax.set_ylabel("y / mm (root 0, ice at the top)")
    ax.set_title("neo-Hookean, deformed; red: face pressure (1 mm = 20 bar)", fontsize=9)
    fig.colorbar(tpc, ax=ax, label="compressive mean stress / MPa")
    ax = axes[1]
    for a, name in ((cmp.linear, "FE linear"), (cmp.neo_hookean, "FE neo-Hookean")):
        s = a.state
        ax.plot((s.mesh.face_x_m + s.face_ux_m) * 1e3, s.face_pressure_Pa / 1e5, ".-", label=name)
    ax.axhline(2.5, color="k", ls=":", label="nominal 2.5 bar")
    ax.set_xlabel("face x / mm (leading edge left)")
    ax.set_ylabel("contact pressure / bar")
    ax.legend(fontsize=7)
    ax = axes[2]
    sw = cmp.sweep
    ax.plot(np.degrees(sw["bending_rad"]), sw["lever_arm_m"] * 1e3, "o", label="FE neo-Hookean")
    phi = np.radians(np.linspace(0.0, 40.0, 400))
    ax.plot(np.degrees(phi), lever_arm(TimoshenkoParams(contact_stiffness_N_m=1.0), phi) * 1e3,
            "k--", label="Fig. 5.12 a (thesis)")
    law = {k: v for k, v in cmp.lever_law.items() if k != "rms_m"}
    ax.plot(np.degrees(phi), lever_arm(TimoshenkoParams(contact_stiffness_N_m=1.0, **law), phi)
            * 1e3, "r-", label="Eq. 5.21 refitted")
    ax.set_xscale("symlog", linthresh=0.1)
    ax.set_xlabel("tip rotation phi(d) / deg")
    ax.set_ylabel("lever arm e / mm")
    ax.legend(fontsize=7)
    save_figure(fig, path)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=OUT_ROOT / "element_continuum")
    parser.add_argument("--n-length", type=int, default=16,
                        help="elements across the element length (default 16)")
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    cmp = continuum_vs_beam(n_length=args.n_length)
    # sensitivity, not a fit: the linear element on a 14 mm base layer (the block under the
    # sipes, as friction_model.compound describes it), 5 mm of base beyond each side
    base = ElementSpec.from_preset("G3", n_length=args.n_length, base_thickness_m=14e-3,
                                   base_margin_m=5e-3)
    on_base = element_outputs(solve_element(base, normal_force_N=cmp.linear.outputs.normal_force_N,
                                            mu=cmp.mu)).as_row()
    on_base.update(model="FE linear on a 14 mm base layer (sensitivity)", status="sensitivity")
    table = pd.concat([cmp.table, pd.DataFrame([on_base])],
                                        ignore_index=True)
    table = table[[c for c in COLUMNS if c in table.columns]]
    atomic_write(args.out / "continuum_vs_beam.csv", lambda p: table.to_csv(p, index=False))
    atomic_write(args.out / "continuum_vs_beam.md", lambda p: p.write_text(markdown(table)))
    atomic_write(args.out / "lever_arm_sweep.csv", lambda p: cmp.sweep.to_csv(p, index=False))
    profiles = pd.concat(
        [section_profile(a.state).assign(model=name) for a, name in
         ((cmp.linear, "FE linear"), (cmp.neo_hookean, "FE neo-Hookean"))], ignore_index=True)
    atomic_write(args.out / "section_profile.csv", lambda p: profiles.to_csv(p, index=False))
    st = cmp.neo_hookean.state
    face = {"x_mm": (st.mesh.face_x_m + st.face_ux_m) * 1e3,
            "pressure_bar": st.face_pressure_Pa / 1e5, "in_contact": st.active}
    atomic_write(args.out / "face_pressure.csv",
                 lambda p: pd.DataFrame(face).to_csv(p, index=False))
    write_json(args.out / "lever_law.json", {**cmp.lever_law, "mu": cmp.mu,
               "frequencies_sliding_Hz_E0": {k: list(a.frequencies_sliding_Hz) for k, a in
                                            (("linear", cmp.linear), ("neo-hookean",
                                                                      cmp.neo_hookean))},
               "frequencies_stuck_Hz_E0": {k: list(a.frequencies_stuck_Hz) for k, a in
                                          (("linear", cmp.linear), ("neo-hookean",
                                                                    cmp.neo_hookean))}})
    figure(cmp, args.out / "element_continuum.png")
    print(f"mu(1 m/s) = {cmp.mu:.4f}; Eq. 5.21 refitted: " + json.dumps(
        {k: round(v, 6) for k, v in cmp.lever_law.items()}))
    print(markdown(table))
    print(f"first modes at E0: sliding {cmp.neo_hookean.frequencies_sliding_Hz.round(0)} Hz, "
          f"stuck {cmp.neo_hookean.frequencies_stuck_Hz.round(0)} Hz (neo-Hookean); "
          f"tip slope at the face {math.degrees(cmp.neo_hookean.outputs.tip_slope_rad):.2f} deg")
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
