"""The LoD preview looks like the render (issue 14; Blender under Xvfb, see scripts/run_ui_tests.sh).

scripts/bench_preview_fidelity.py's measurement at the mid and far views, on the bundled real hair (Ratboy_mohawk,
2228 strands) and on 20,000 strands generated from the bundled hair mesh: the preview with the panel's
defaults (Strand Coverage on, the default hair, one sun and a grey world, Standard view transform)
against the full strands path-traced from the same camera (128 spp at half the viewport's size: the
ratios move by under 1 % from there to 256 spp at full size; at 64 spp the mohawk's blue reads 4 %
higher, its rare bright paths missed). Asserted:
- both hairs' mean radiance within 10 % per channel of the path-traced image, issue 14's target: at the
  mid view the mohawk 1.00 / 0.99 / 0.96, the generated hair 1.04 / 1.01 / 0.96 (Blender 3.4), at the
  far view 1.02 / 1.00 / 0.98 and 1.03 / 1.01 / 0.93, the preview at rest, its hair averaged over the
  8 samples of the viewport's anti-aliasing (Blender's default). The preview's radiance is read from its hair layer: unmixed
  from the screenshot, the 8-bit framebuffer's rounding of partly covered pixels read the mohawk at
  1.06 / 1.04 / 1.08 (scripts/bench_preview_fidelity.py). While the thick hairs were drawn solid and
  shaded at the hair's mean free path below their near side, the generated hair's far view read
  0.98 / 1.07 / 0.99; drawn by their coverage at that depth, 0.90 / 0.96 / 0.89 (the deeper hair they
  let through is shaded again below it); shaded at the strand the ray meets, as now. While a strand's
  back-scatter took Huang 2025 Eq. 10's A_1+ at n = 1 (the side scattering of a thick hair's own hairs
  behind the shaded one, of which a strand has none, on top of the hair behind's A_1 + A_3) they read
  1.05 / 1.05 / 1.02 and 1.04 / 1.10 / 1.04, the mohawk's sun term alone 1.40 / 1.37 / 1.34. The mohawk
  was 0.97 / 0.94 / 0.90 while the uniform world's response was Xu's closed form on the Marschner fibre
  (0.94-0.96 of the material's directional albedo at normal incidence, down to 0.4 at grazing views,
  most of all in blue), not the albedo itself. While the lights were shaded with the R / TT / D fibre of
  Huang 2025 Eq. 1 and the uniform world's transmittance was one average over all directions, the
  generated hair's sun term read 0.73 / 0.85 / 1.00 of the path-traced sun light and its world term
  1.36 / 1.29 / 1.00, offsetting each other in red; with the material's fibre and the world split by
  side, 0.99 / 0.97 / 0.96 and 1.09 / 1.06 / 0.98 (docs/preview.md, "The lights on the material's
  fibre");
- both hairs covering the pixels their path-traced strands cover: within 25 % at the mid view (the
  mohawk 0.94x, the generated hair 1.00x), and at the far view the sky let through between a thick
  hair's strands (COVERAGE);
- lit by an HDRI alone (Blender's own courtyard.exr, the bench's --hdri courtyard --sun 0), which the
  preview fits with SRBF lights: both hairs within 15 % per channel of the path-traced image, which
  draws the image by its luminance (HDRI_TOLERANCE; the mohawk 0.93 / 0.97 / 1.02, the generated hair
  1.01 / 0.98 / 0.92), and the mohawk
  brighter at its tips than at its roots as the path-traced image is (GRADIENT_SHARE). Each SRBF light reaches the hair through the hair on its own way
  (Xu 2011 Eq. 2's effective transmittance): with the uniform world's one transmittance for every
  lobe the generated hair read 1.54 / 1.46 / 0.88 (the lobes behind it let through as much as those
  in front);
- lit by sunrise.exr alone, whose sun holds 59 % of its light: the generated hair within 15 % (0.87 /
  0.88 / 0.88; 0.96 / 1.01 / 0.96 while the lights were shaded with the R / TT / D fibre: its low sun from
  the camera's right is short with the material's fibre, docs/preview.md, "The lights on the material's
  fibre"), its sun shaded as a sun lamp with an opacity map (1.25 / 1.28 / 1.11 while the SRBF lobes
  carried it). The mohawk's ratio is printed, not asserted: 0.98 / 1.11 / 1.19 (1.09 / 1.17 / 1.21 on the
  R / TT / D fibre, 1.08 / 1.08 / 1.38 with the Fibonacci fit), the fibre's response to a sun at its
  grazing views (docs/preview.md, "Lit by an HDRI").
Each reference is one render (spread_tolerance 0): the means are unbiased at 128 spp; the luminance spread, for
which the benchmark doubles the reference's samples until it settles, is not asserted here.
Screenshots and the path-traced images go to $HAIRLOD_UI_OUT (default out/ui) as fidelity_<hair>_<view>[_<hdri>]_*.png.
"""

import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import harness  # noqa: E402  (tests/ui/harness.py)
from harness import check  # noqa: E402

sys.path.insert(0, os.path.join(harness.REPO_ROOT, "scripts"))
import bench_preview_fidelity  # noqa: E402  (scripts/bench_preview_fidelity.py)

TOLERANCE = {"generated wavy 20k mid": 0.10, "Ratboy_mohawk mid": 0.10, "generated wavy 20k far": 0.10,
             "Ratboy_mohawk far": 0.10}
# The preview's hair pixels over the path-traced coverage, per view. At the far view most of the hair is
# thick hairs, drawn by the share of their strip their strands cover (thick_hair.vert.glsl): the mohawk
# 0.78x and the generated hair 1.01x (1.75x and 1.11x while every thick hair was drawn solid).
COVERAGE = {"mid": (0.8, 1.25), "far": (0.6, 1.25)}
# Both hairs within 15 % per channel under an HDRI. The dense generated hair's world light needs what the
# hair around each strand scatters on to it (self_shadow.scattered_share): without it the hair read 0.92 /
# 0.90 / 0.85 of the path tracer's under courtyard.exr (0.84 in blue in Blender 4.3) and 0.89 / 0.96 / 0.93
# under sunrise.exr (docs/preview.md, "The world's light the hair around scatters on").
HDRI_TOLERANCE = {"generated wavy 20k mid": 0.15, "Ratboy_mohawk mid": 0.15}
# The mohawk under courtyard.exr is brighter at its tips than at its roots: its top band of rows over its
# bottom band reads 1.36 in a path-traced image at 1024 spp (same_pixels_rows). The preview holds at least
# this share of that rise (1.35: all of it; 1.03 while the world's 16 lobes were a fixed Fibonacci set).
GRADIENT_SHARE = 0.5


def check_mean_ratios(results, tolerance, lit_by):
    """The preview's mean hair radiance over the path-traced image's, per hair, within its tolerance."""
    check(sorted(results) == sorted(tolerance), f"measured {sorted(results)}, lit by {lit_by}")
    for name, entry in results.items():
        ratio = np.asarray(entry["mean_ratio"])
        check(bool(np.all(np.abs(ratio - 1.0) <= tolerance[name])),
              f"{name}, lit by {lit_by}: mean hair radiance {np.round(ratio, 3)} of the path-traced image, within "
              f"{tolerance[name]:.0%} per channel")


def steps():
    results = {}
    yield from bench_preview_fidelity.measure(results, views=("mid", "far"), spp=128, scale=0.5,
                                              spread_tolerance=0.0)
    check_mean_ratios(results, TOLERANCE, "a sun and a grey world")
    for name, entry in results.items():
        lowest, highest = COVERAGE[name.split()[-1]]
        check(lowest <= entry["coverage_ratio"] <= highest,
              f"{name}: the preview's hair pixels {entry['coverage_ratio']:.3f}x the path-traced coverage, within "
              f"[{lowest}, {highest}]")
    lit_by_hdri = {}
    yield from bench_preview_fidelity.measure(lit_by_hdri, views=("mid",), spp=128, scale=0.5, spread_tolerance=0.0,
                                              sun_irradiance=0.0, hdri="courtyard")
    check_mean_ratios(lit_by_hdri, HDRI_TOLERANCE, "courtyard.exr")
    rows = lit_by_hdri["Ratboy_mohawk mid"]["rows_same_pixels"]
    rise = {image: rows[image][-1] / rows[image][0] for image in ("preview", "path_traced")}
    check(rise["preview"] - 1.0 >= GRADIENT_SHARE * (rise["path_traced"] - 1.0),
          f"Ratboy_mohawk mid, lit by courtyard.exr: tips over roots {rise['preview']:.3f} in the preview, "
          f"{rise['path_traced']:.3f} path-traced; the preview holds at least {GRADIENT_SHARE:.0%} of the rise")
    lit_by_sun = {}
    yield from bench_preview_fidelity.measure(lit_by_sun, views=("mid",), spp=128, scale=0.5, spread_tolerance=0.0,
                                              sun_irradiance=0.0, hdri="sunrise")
    print("Ratboy_mohawk mid, lit by sunrise.exr (not asserted: the fibre, docs/preview.md):",
          np.round(lit_by_sun["Ratboy_mohawk mid"]["mean_ratio"], 3))
    check_mean_ratios({"generated wavy 20k mid": lit_by_sun["generated wavy 20k mid"]},
                      {"generated wavy 20k mid": HDRI_TOLERANCE["generated wavy 20k mid"]}, "sunrise.exr")


harness.run(steps)
