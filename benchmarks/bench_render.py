"""Rendering speed of the synthetic TIR footage (:mod:`synthetic.footage`), one core, no disk.

Prints, measured in this run on 640 x 256 px frames of the G3 block crossing the view
(default spec: 0.1 mm/px, 4000 frames/s, 1 m/s, exposure 20 us, 8 bit, per-frame states of
the simulated rigid model; the model integration itself is done once before timing):

* frames/s of the renderer with the default camera (motion blur, shot and read noise) and
  of a noise-free variant, each including the per-frame ground-truth table;
* frames/s of a straightforward baseline on the same frames: every element's contact drawn
  with ``skimage.draw.polygon`` on a 4x supersampled grid, the darkness filled column by
  column from the same pressure profile, blurred with ``scipy.ndimage.uniform_filter1d``,
  block-averaged back to pixels, then exact Poisson shot noise and Gaussian read noise;
* the speed ratio renderer / baseline.

The renderer precomputes everything static (illumination, ice imperfections, dust, the
lateral coverage of the block) and per frame integrates the 1-D darkness profile of the
block analytically over each pixel column and the exposure (exact area coverage and box
blur), so that a frame is one outer product plus the noise.

Run: ``python benchmarks/bench_render.py [n_frames]``.
"""

import os

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import sys
import time

import numpy as np
from scipy import ndimage
from skimage.draw import polygon

from synthetic import footage
from synthetic._render_tir import element_contacts

N_FRAMES = int(sys.argv[1]) if len(sys.argv) > 1 else 400
SS = 4  # supersampling of the baseline
N_BASELINE = min(N_FRAMES, 60)  # the baseline is slow; its frames are spread over the clip


def baseline_frame(clip: footage._Clip, k: int, rng: np.random.Generator | None) -> np.ndarray:
    """One frame the straightforward way (same physics, no precomputed profile)."""
    cam, path = clip.spec.camera, clip.path
    frame = footage._element_frame(clip.geom, clip.states, k)
    contacts = element_contacts(frame, clip.contact, node_spacing_mm=clip.node_spacing_mm)
    h, w = cam.height_px * SS, cam.width_px * SS
    px = cam.mm_per_px / SS
    dark = np.zeros((h, w))
    u_front = clip.u_front(k)
    yc = 0.5 * path.height_mm + path.lateral_mm
    y0, y1 = (yc - 0.5 * clip.geom.width_mm) / px, (yc + 0.5 * clip.geom.width_mm) / px
    xs = (np.arange(w) + 0.5) * px
    for i, c in enumerate(contacts):
        if c.length_mm <= 0:
            continue
        xa = u_front + frame.front_corner_mm[i] + c.zeta_start_mm
        xb = u_front + frame.front_corner_mm[i] + c.zeta_end_mm
        rr, cc = polygon([y0, y0, y1, y1], [xa / px, xb / px, xb / px, xa / px], shape=(h, w))
        zeta = xs[cc] - u_front - frame.front_corner_mm[i]
        dark[rr, cc] = clip.contact.darkness(np.interp(zeta, c.nodes_mm, c.pressure_Pa))
    blur = clip.blur_mm / px
    if blur >= 1.0:
        dark = ndimage.uniform_filter1d(dark, size=round(blur), axis=1)
    dark = dark.reshape(cam.height_px, SS, cam.width_px, SS).mean(axis=(1, 3))
    signal = clip.base * (1.0 - dark)
    top = (1 << cam.bit_depth) - 1
    dn_per_e = cam.gain * top / cam.full_well_e
    e = signal * cam.full_well_e
    if rng is not None:
        e = rng.poisson(e) + rng.normal(0.0, cam.read_noise / dn_per_e, e.shape)
    return np.clip(np.rint(e * dn_per_e), 0, top).astype(np.uint8)


def rate(fn, frames) -> float:
    frames = list(frames)
    t0 = time.perf_counter()
    for k in frames:
        fn(k)
    return len(frames) / (time.perf_counter() - t0)


def main() -> None:
    spec = footage.FootageSpec(preset="G3", n_frames=N_FRAMES)
    quiet = footage.FootageSpec(preset="G3", n_frames=N_FRAMES, noise=False)
    t0 = time.perf_counter()
    clip = footage._Clip(spec)
    t_model = time.perf_counter() - t0
    clip_quiet = footage._Clip(quiet)  # shares the cached model run
    clip.image(0), clip_quiet.image(0)  # warm-up
    fast = rate(clip.image, range(N_FRAMES))
    fast_quiet = rate(clip_quiet.image, range(N_FRAMES))
    sample = np.linspace(0, N_FRAMES - 1, N_BASELINE).round().astype(int)
    base = rate(lambda k: baseline_frame(clip, k, clip.noise_rng(k)), sample)
    base_quiet = rate(lambda k: baseline_frame(clip, k, None), sample)
    print(f"G3, {N_FRAMES} frames of 640 x 256 px, one core (model run {t_model:.1f} s, once)")
    print(f"renderer, default camera (blur + noise): {fast:7.1f} frames/s")
    print(f"renderer, noise-free:                    {fast_quiet:7.1f} frames/s")
    print(f"baseline (polygon + ndimage), noisy:     {base:7.1f} frames/s")
    print(f"baseline, noise-free:                    {base_quiet:7.1f} frames/s")
    print(f"speed-up: {fast / base:.1f}x (default), {fast_quiet / base_quiet:.1f}x (noise-free)")


if __name__ == "__main__":
    main()
