"""Cross-check: the dry/wet model's real contact fraction against rough-contact mechanics.

The friction model carries the real contact as ``phi(p) = phi_ref (p / p_ref)^gamma``
(:func:`friction_model.real_contact_fraction`, phi_ref and gamma fitted to Table 4.6 of
the thesis). Contact mechanics predicts it from the rubber and the roughness alone: the
one rubber's E* = E0 / (1 - nu^2) = 4.81 MPa pressed on a flat by the nominal pressure p,
with a self-affine rough face (:mod:`synthetic.roughness`, solved by tamaas). Neither
number is fitted to the other: this is a prediction against a fit.

The contact of a given surface shape depends on ``x = p / (E* h')`` only (scaling the
heights by s scales the load for the same contact by s), so one master curve
``A_r / A_0 = f(x)`` per surface shape answers "which rms slope h' would make the two
agree": ``h' = p / (E* f^-1(phi(p)))``.

Run: ``python examples/real_contact_crosscheck.py [--out crosscheck-out]`` (needs the
contact extra; about a minute). Writes ``real_contact_crosscheck.csv`` and ``.md``.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import pandas as pd

from friction_model import DryWetParameters, real_contact_fraction
from synthetic._physical import scene_contact_tile
from synthetic.roughness import ROUGHNESS_PRESETS, Roughness, e_star_Pa

PRESSURES_BAR = (0.5, 1.0, 2.5, 5.0)
TILE = 256
SEED = 1


def master_curve(hurst: float) -> tuple[np.ndarray, np.ndarray]:
    """``x = p / (E* h')`` and the solved ``A_r / A_0`` for one surface shape."""
    shape = Roughness(hurst, 1.0, 0.5, 0.04, f"master H={hurst}")
    xs = np.geomspace(0.005, 2.0, 14)
    e = e_star_Pa()
    fr = [scene_contact_tile(shape, TILE, SEED, float(x * e)).contact_fraction for x in xs]
    return xs, np.maximum.accumulate(np.asarray(fr))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=Path("crosscheck-out"))
    args = ap.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    e = e_star_Pa()
    params = DryWetParameters()
    xs, fx = master_curve(0.8)
    rows = []
    for p_bar in PRESSURES_BAR:
        p = p_bar * 1e5
        phi = float(real_contact_fraction(p, params))
        row = {"pressure_bar": p_bar, "phi_drywet": phi}
        for name in ("moulded_rubber", "rough_ice", "abraded_rubber"):
            rough = ROUGHNESS_PRESETS[name]
            solved = scene_contact_tile(rough, TILE, SEED, p)
            row[f"Ar_A0_{name}"] = solved.contact_fraction
        x_needed = float(np.exp(np.interp(phi, fx, np.log(xs)))) if phi < fx[-1] else np.nan
        row["slope_for_agreement"] = p / (e * x_needed)
        rows.append(row)
    table = pd.DataFrame(rows)
    table.to_csv(args.out / "real_contact_crosscheck.csv", index=False)
    head = (
        "| p, bar | phi dry/wet (fit) | A_r/A_0 moulded rubber (h' 0.4) | rough ice (h' 0.6) "
        "| abraded rubber (h' 1.2) | h' that gives phi (H 0.8) |"
    )
    lines = [head, "|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(
            f"| {r['pressure_bar']:g} | {r['phi_drywet']:.3f} | "
            f"{r['Ar_A0_moulded_rubber']:.3f} | {r['Ar_A0_rough_ice']:.3f} | "
            f"{r['Ar_A0_abraded_rubber']:.3f} | {r['slope_for_agreement']:.3f} |"
        )
    (args.out / "real_contact_crosscheck.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))
    print("master curve (H 0.8): x = p/(E* h') -> A_r/A_0:")
    print(", ".join(f"{x:.3g}: {f:.3f}" for x, f in zip(xs, fx, strict=True)))


if __name__ == "__main__":
    main()
