"""LoD quality: the bias of the render methods against a converged reference (hair-lod-aggregated-bcsdf.txt
Sec. 6, Fig. 5 and 12; docs/ARCHITECTURE.md, "Judging the LoD").

bench_quality() renders, for each view (near, mid, far), a path-traced full-geometry reference ('pt' at
`reference_spp`, default 1024, with a seed of its own) and every method at `spp` (default 256), 128 x 128
by default, so that noise is small against the differences measured. Each row holds the Embree segments
in the scene, the render time, rays per second and, against the reference: PSNR, blurred PSNR (of 4 x 4
box averages in linear radiance, render.blurred_psnr: noise averages out, bias stays), SSIM, LDR-FLIP,
the signed relative error of the mean linear radiance per channel (R, G, B) over the hair's pixels
(those the strands cover with alpha > HAIR_ALPHA), and the coverage error of the method's geometry
against the strands' (render.coverage: relative error of the total alpha, and mean |alpha difference|
over all pixels), and the radiance error of the hair alone (render.hair_radiance_error: each image
unmixed from the sky its uncovered share shows, so that a coverage error does not read as a shading
error). Every coverage render of a view uses the methods' seed and `spp`, so geometry equal
to the strands reads exactly 0. The 'pt' row is an independent path-traced render at `spp` (the
methods' seed): the noise floor the other rows are read against. A view whose hair covers fewer pixels
renders more samples per pixel (view_spp_scales): the mean hair radiance of a far view, averaged over
fewer pixels, is otherwise noisier than the near view's by the square root of the ratio.

The equal-time table renders every method again at `equal_time_spp` (default 16) against the same
reference: the error at a real-time sample budget, noise included. A sweep of the LoD width threshold
eps_w (pixels, Huang 2025 Eq. 16) at one view, at `spp`, gives segments and time against error.
write_view_images() draws per view reference | ds | lod | lod-single | lod - reference around the
hair; plot_quality() the paper's FLIP-against-segments figure. No assertions on times: a benchmark,
not a test.
"""

import os
import time

import numpy as np

from . import atomic_output, flip, lod, render

__all__ = ["EPS_W", "HAIR_ALPHA", "IMAGE_METHODS", "MAX_VIEW_SPP_SCALE", "PANEL_PIXELS", "bench_quality", "format_tables",
           "plot_quality", "view_spp_scales", "write_view_images"]

EPS_W = (0.5, 1.0, 2.0, 4.0, 8.0)
# A pixel is the hair's (for the mean radiance) when the strands cover more than half of it.
HAIR_ALPHA = 0.5
# The methods write_view_images() shows beside the reference, and the least width of a panel.
IMAGE_METHODS = ("ds", "lod", "lod-single")
PANEL_PIXELS = 256
_REFERENCE_SEED = 1_000_003
# The most a view's spp is raised over the given spp (view_spp_scales). At 128 px the default views'
# hair covers about 2600 / 850 / 85 pixels of the dense hairs: 1x / 4x / 16x keeps their mean hair
# radiance about equally noisy (at 256 spp and 1x everywhere, the far view's 256-spp pt row read 3-4 %
# from the 1024-spp reference on the dense hairs, the near view's 0.5 %), at about 2x the bench's time.
MAX_VIEW_SPP_SCALE = 16


def view_spp_scales(hair_pixels, most=MAX_VIEW_SPP_SCALE):
    """Per view of `hair_pixels` ({view: pixels the strands cover}), the power of two (1 to `most`) closest
    to the largest count over the view's, by which its spp is raised so that every view's mean hair
    radiance averages about as many samples; 1 for a view without hair pixels."""
    if int(most) < 1:
        raise ValueError(f"the largest view spp scale must be >= 1, got {most}")
    largest = max(hair_pixels.values(), default=0)
    scales = {}
    for view, pixels in hair_pixels.items():
        ratio = largest / pixels if pixels > 0 else 1.0
        scales[view] = int(min(int(most), 2 ** max(0, round(np.log2(ratio)))))
    return scales




def _finite(value):
    """`value` as a float, or None where it is infinite or NaN (strict JSON has neither): an infinite
    PSNR means identical 8-bit images."""
    return float(value) if np.isfinite(value) else None


def _errors(image, reference, hair):
    test_srgb, reference_srgb = render.to_srgb8(image) / 255.0, render.to_srgb8(reference) / 255.0
    return {"psnr": _finite(render.psnr(image, reference)),
            "blurred_psnr": _finite(render.blurred_psnr(image, reference)),
            "ssim": render.ssim(image, reference), "flip": flip.flip(test_srgb, reference_srgb),
            "radiance_error": [_finite(v) for v in render.mean_radiance_error(image, reference, hair)]}


def _coverage_errors(alpha, reference_alpha):
    relative, mean_abs = render.coverage_error(alpha, reference_alpha)
    return {"coverage_error": _finite(relative), "coverage_abs_error": mean_abs}


def _row(result):
    return {"segments": result["segments"], "strand_segments": int(result["strand_segments"]),
            "thick_segments": int(result["thick_segments"]), "seconds": float(result["seconds"]),
            "setup_seconds": float(result["setup_seconds"]), "rays": int(result["rays"]),
            "rays_per_second": float(result["rays_per_second"])}


def _difference(a, b):
    return None if a is None or b is None else a - b


def _db(value):
    return "inf" if value is None else f"{value:.2f}"


def bench_quality(strands, asset=None, views=tuple(render.VIEWS), methods=render.METHODS, spp=256, width=128,
                  reference_spp=1024, equal_time_spp=16, eps_w=EPS_W, sweep_view="mid", width_px=lod.DEFAULT_WIDTH_PX, guides=None,
                  params=None, seed=0, keep_images=False, progress=None, max_bounces=render.MAX_BOUNCES, own_hair=None,
                  vertex_tolerance_px=lod.DEFAULT_VERTEX_TOLERANCE_PX, max_view_spp_scale=MAX_VIEW_SPP_SCALE):
    """Dict with settings, the LoD build (when `asset` is None it is built here), one entry per view
    {camera, reference, rows: {method: row}}, the equal-time rows per view and the eps_w sweep rows.
    With `keep_images` it also holds "images": {view: {"reference": image, method: image}} (linear
    [H, W, 3] arrays, not JSON: for write_view_images). `progress(message)` is called before each
    render when given. `max_bounces` limits every render's paths, the reference's too, to that many
    scatterings after the camera ray's hit (0: direct light only, the light scattered once on its way
    to the camera): what separates single from multiple scattering. `own_hair` (render.OWN_HAIR) is how
    the lod-single renders treat paths inside their own thick hair; `vertex_tolerance_px` the lod
    methods' vertex LoD (render.lod_geometry; 0 draws every control point). Each view renders its reference
    and methods at `reference_spp` and `spp` times its view_spp_scales() factor (at most
    `max_view_spp_scale`; 1 renders every view at the spp given); coverage and the equal-time table stay
    at `spp` and `equal_time_spp`."""
    if int(max_bounces) < 0:
        raise ValueError(f"max bounces must be >= 0, got {max_bounces}")
    if own_hair is not None and own_hair not in render.OWN_HAIR:
        raise ValueError(f"own_hair must be one of {', '.join(render.OWN_HAIR)}, got {own_hair!r}")
    own_hair = own_hair or render.OWN_HAIR[0]
    if int(max_view_spp_scale) < 1:
        raise ValueError(f"max view spp scale must be >= 1, got {max_view_spp_scale}")
    if min(int(spp), int(reference_spp), int(equal_time_spp)) < 1:
        raise ValueError(f"spp, reference spp and equal-time spp must be >= 1, got {spp}, {reference_spp}, "
                         f"{equal_time_spp}")
    if int(width) < render.BLUR_BOX:
        raise ValueError(f"width must be >= {render.BLUR_BOX} (the blurred PSNR's box), got {width}")
    for view in list(views) + [sweep_view]:
        if view not in render.VIEWS:
            raise ValueError(f"view must be one of {', '.join(render.VIEWS)}, got {view!r}")
    for method in methods:
        if method not in render.METHODS:
            raise ValueError(f"method must be one of {', '.join(render.METHODS)}, got {method!r}")
    if any(not e > 0 for e in eps_w):
        raise ValueError(f"eps_w values must be > 0, got {list(eps_w)}")
    say = progress or (lambda message: None)
    build = None
    if asset is None:
        say("building the LoD" + (f" ({guides} guides)" if guides else ""))
        start = time.perf_counter()
        asset = lod.build_lod(strands, guides=guides)
        build = {"guides": asset.guide_count, "clusters": asset.cluster_count, "seconds": time.perf_counter() - start,
                 "levels": lod.level_report(asset)}

    def render_method(method, view, samples, eps=width_px):
        return render.render(strands, method, view, width, samples, asset=asset, params=params, seed=seed, width_px=eps,
                             max_bounces=max_bounces, own_hair=own_hair if method == "lod-single" else None,
                             vertex_tolerance_px=vertex_tolerance_px)

    references, reference_alphas, hair_pixels, result_views, equal_time, images = {}, {}, {}, {}, {}, {}
    rendered_views = list(dict.fromkeys(list(views) + [sweep_view]))
    for view in rendered_views:
        say(f"{view}: the strands' coverage")
        reference_alphas[view] = render.coverage(strands, "pt", view, width, spp, seed=seed)
        hair_pixels[view] = reference_alphas[view] > HAIR_ALPHA
    scales = view_spp_scales({view: int(hair.sum()) for view, hair in hair_pixels.items()}, max_view_spp_scale)
    for view in rendered_views:
        view_spp, view_reference_spp = spp * scales[view], reference_spp * scales[view]
        say(f"{view}: pt reference at {view_reference_spp} spp")
        reference = render.render(strands, "pt", view, width, view_reference_spp, params=params, seed=_REFERENCE_SEED,
                                  max_bounces=max_bounces)
        reference_alpha, hair = reference_alphas[view], hair_pixels[view]
        references[view] = reference
        if view not in views:
            continue
        rows, equal_rows, view_images = {}, {}, {"reference": reference["image"]}
        # What the camera rays that miss the hair show: the default lights' uniform sky.
        background = render.default_lights(reference["camera"])["environment"]
        for method in methods:
            say(f"{view}: {method} at {view_spp} spp, its coverage, and at {equal_time_spp} spp")
            out = render_method(method, view, view_spp)
            alpha = render.coverage(strands, method, view, width, spp, asset=asset, width_px=width_px, seed=seed,
                                    vertex_tolerance_px=vertex_tolerance_px)
            rows[method] = dict(_row(out), **_errors(out["image"], reference["image"], hair),
                                **_coverage_errors(alpha, reference_alpha),
                                hair_radiance_error=[_finite(v) for v in render.hair_radiance_error(
                                    out["image"], alpha, reference["image"], reference_alpha, hair, background)])
            view_images[method] = out["image"]
            quick = render_method(method, view, equal_time_spp)
            equal_rows[method] = dict(_row(quick), **_errors(quick["image"], reference["image"], hair))
        radiance = reference["image"][hair].mean(axis=0).tolist() if hair.any() else None
        result_views[view] = {"coverage": render.VIEWS[view], "camera": reference["camera"], "spp": int(view_spp),
                              "reference_spp": int(view_reference_spp),
                              "reference": dict(_row(reference), alpha_mean=float(reference_alpha.mean()),
                                                hair_pixels=int(hair.sum()), hair_radiance=radiance),
                              "rows": rows}
        equal_time[view] = {"rows": equal_rows}
        images[view] = view_images
    sweep = []
    for eps in eps_w:
        say(f"{sweep_view}: lod at eps_w {eps:g} px")
        out = render_method("lod", sweep_view, spp * scales[sweep_view], float(eps))
        sweep.append(dict(_row(out), eps_w=float(eps),
                          **_errors(out["image"], references[sweep_view]["image"], hair_pixels[sweep_view])))
    summary = {}
    for view, entry in result_views.items():
        rows, facts = entry["rows"], {}
        if "pt" in rows:
            facts["noise_floor_blurred_psnr"] = rows["pt"]["blurred_psnr"]
        if "lod" in rows:
            facts["segment_reduction"] = entry["reference"]["segments"] / max(rows["lod"]["segments"], 1)
            if "ds" in rows:
                for metric in ("psnr", "blurred_psnr", "flip"):
                    facts[f"lod_minus_ds_{metric}"] = _difference(rows["lod"][metric], rows["ds"][metric])
        summary[view] = facts
    result = {"strands": len(strands), "points": int(strands.point_count), "width": int(width), "spp": int(spp),
              "reference_spp": int(reference_spp), "max_view_spp_scale": int(max_view_spp_scale),
              "max_bounces": int(max_bounces), "own_hair": own_hair,
              "vertex_tolerance_px": float(vertex_tolerance_px), "blur_box": render.BLUR_BOX, "hair_alpha": HAIR_ALPHA,
              "width_px": float(width_px), "lod_build": build, "guides": asset.guide_count, "views": result_views,
              "equal_time": {"spp": int(equal_time_spp), "views": equal_time}, "summary": summary,
              "sweep": {"view": sweep_view, "spp": int(spp * scales[sweep_view]), "full_segments": int(references[sweep_view]["segments"]),
                        "rows": sweep}}
    if keep_images:
        result["images"] = images
    return result


def _view_spp(result, view):
    """(methods' spp, reference spp) a view of `result` was rendered at (results before views were
    scaled hold only the run's)."""
    entry = result["views"][view]
    return entry.get("spp", result["spp"]), entry.get("reference_spp", result["reference_spp"])


def _percent(value, signed=True):
    return "n/a" if value is None else f"{100.0 * value:{'+' if signed else ''}.2f}"


def _rgb(errors):
    return " / ".join(_percent(v) for v in errors)


def _hair_window(reference, others, least=8):
    """(top, left, side) of the square of `reference` [H, W, 3] that holds every pixel where one of
    `others` differs from it (the hair, drawn by any method: where no ray meets hair every render reads
    the same environment), with a margin; the whole image when none differs."""
    height, width = reference.shape[:2]
    differs = np.zeros((height, width), bool)
    for image in others:
        differs |= np.any(image != reference, axis=-1)
    if not differs.any():
        return 0, 0, min(height, width)
    rows, columns = np.flatnonzero(differs.any(axis=1)), np.flatnonzero(differs.any(axis=0))
    extent = max(rows[-1] - rows[0], columns[-1] - columns[0]) + 1
    side = int(min(max(least, int(np.ceil(1.2 * extent)) + 2), height, width))
    top = int(np.clip((rows[0] + rows[-1] + 1 - side) // 2, 0, height - side))
    left = int(np.clip((columns[0] + columns[-1] + 1 - side) // 2, 0, width - side))
    return top, left, side


def write_view_images(result, images, folder):
    """Writes, per view of `images` (bench_quality(keep_images=True)["images"]), `folder`/<view>.png:
    the reference | ds | lod | lod-single (those rendered) | lod - reference as linear luminance on a
    diverging map (scale in its title: the 99th percentile of |difference| over the pixels where it is
    not 0). Each panel shows the same square around the hair (_hair_window), upscaled by an integer
    factor (nearest neighbour) to at least PANEL_PIXELS; titles give the window, the method, PSNR /
    blurred PSNR and the mean radiance error (of the whole image). `folder` is made when missing; each
    file replaces its target atomically (atomic_output.replacing_file) and nothing else in the folder
    is touched. Returns the paths written."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    os.makedirs(folder, exist_ok=True)
    margin, title_space, dpi = 8, 56, 100
    paths = []
    for view, view_images in images.items():
        rows, reference = result["views"][view]["rows"], view_images["reference"]
        shown = [m for m in IMAGE_METHODS if m in view_images]
        top, left, side = _hair_window(reference, [view_images[m] for m in shown])
        factor = -(-PANEL_PIXELS // side)
        spp, reference_spp = _view_spp(result, view)
        panels = [(f"{view}: pt reference, {reference_spp} spp\nx {left}-{left + side - 1}, "
                   f"y {top}-{top + side - 1} of {result['width']} px, shown x{factor}", render.to_srgb8(reference), {})]
        for method in shown:
            r = rows[method]
            panels.append((f"{method}, {spp} spp\nPSNR {_db(r['psnr'])}, blurred {_db(r['blurred_psnr'])} dB\n"
                           f"radiance RGB {_rgb(r['radiance_error'])} %", render.to_srgb8(view_images[method]), {}))
        if "lod" in view_images:
            difference = render.luminance(view_images["lod"]) - render.luminance(reference)
            changed = np.abs(difference[difference != 0.0])
            scale = float(np.percentile(changed, 99)) if changed.size else 1e-6
            panels.append((f"lod - reference, linear luminance\nscale +-{scale:.2g} (red: lod brighter)", difference,
                           {"cmap": "RdBu_r", "vmin": -scale, "vmax": scale}))
        panel = factor * side
        width_px = len(panels) * (panel + margin) + margin
        height_px = panel + title_space + margin
        figure = plt.figure(figsize=(width_px / dpi, height_px / dpi), dpi=dpi)
        for i, (title, pixels, style) in enumerate(panels):
            ax = figure.add_axes(((margin + i * (panel + margin)) / width_px, margin / height_px, panel / width_px,
                                  panel / height_px))
            window = pixels[top:top + side, left:left + side]
            ax.imshow(np.repeat(np.repeat(window, factor, axis=0), factor, axis=1), interpolation="nearest", **style)
            ax.set_title(title, fontsize=7.5)
            ax.set_axis_off()
        path = os.path.join(folder, f"{view}.png")
        with atomic_output.replacing_file(path) as staging:
            figure.savefig(staging, dpi=dpi, format="png")
        plt.close(figure)
        paths.append(path)
    return paths


_COLOURS = {"pt": "black", "ds": "tab:blue", "lod": "tab:red", "lod-single": "tab:orange", "lod-no-s": "tab:green"}


def plot_quality(results, path, titles=None):
    """The paper's Fig. 5 / 12 comparison as a PNG: per hairstyle (one row each), FLIP against segments
    drawn per method at each view (each point labelled with its render time), and the eps_w sweep
    (FLIP and segments against eps_w)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    results = results if isinstance(results, (list, tuple)) else [results]
    titles = titles or [f"{r['strands']} strands" for r in results]
    columns = max(len(r["views"]) for r in results) + 1
    figure, axes = plt.subplots(len(results), columns, figsize=(3.3 * columns, 3.0 * len(results)), squeeze=False)
    for row_axes, result, title in zip(axes, results, titles):
        for ax, (view, entry) in zip(row_axes, result["views"].items()):
            for method, r in entry["rows"].items():
                ax.scatter(r["segments"], r["flip"], s=40, color=_COLOURS.get(method), label=method, alpha=0.85,
                           edgecolors="none")
                ax.annotate(f"{r['seconds']:.2g} s", (r["segments"], r["flip"]), fontsize=6, xytext=(3, 3),
                            textcoords="offset points")
            ax.set_xlabel("segments drawn")
            ax.set_ylabel("FLIP vs pt reference")
            ax.ticklabel_format(axis="x", style="sci", scilimits=(-3, 4))
            ax.set_title(f"{title}: {view}", fontsize=9)
            ax.grid(alpha=0.3)
        row_axes[0].legend(fontsize=7)
        ax = row_axes[-1]
        sweep = result["sweep"]["rows"]
        eps = [r["eps_w"] for r in sweep]
        ax.plot(eps, [r["flip"] for r in sweep], "o-", color="tab:red", label="FLIP")
        ax.set_xscale("log", base=2)
        ax.set_xlabel("eps_w (px)")
        ax.set_ylabel("FLIP", color="tab:red")
        twin = ax.twinx()
        twin.plot(eps, [r["segments"] for r in sweep], "s--", color="tab:gray", label="segments")
        twin.axhline(result["sweep"]["full_segments"], color="tab:blue", lw=0.8, ls=":")
        twin.set_ylabel("segments (dotted: full)", color="tab:gray")
        ax.set_title(f"{title}: eps_w sweep, {result['sweep']['view']}", fontsize=9)
        ax.grid(alpha=0.3)
    figure.tight_layout()
    figure.savefig(path, dpi=110, format="png")
    plt.close(figure)


def format_tables(result):
    """The result as Markdown tables (converged methods per view; the equal-time methods; the eps_w
    sweep), each after a line saying what it measures, as a string."""
    box = result["blur_box"]
    error_columns = "PSNR dB | blurred PSNR dB | FLIP | radiance R / G / B %"

    def errors(r):
        return f"{_db(r['psnr'])} | {_db(r['blurred_psnr'])} | {r['flip']:.4f} | {_rgb(r['radiance_error'])}"

    def label(method, samples):
        return f"pt (noise floor, {samples} spp)" if method == "pt" else method

    bounces = result.get("max_bounces", render.MAX_BOUNCES)
    limit = ("" if bounces == render.MAX_BOUNCES else ", direct light only (paths of 0 bounces)" if bounces == 0 else
             f", paths of at most {bounces} bounce{'s' if bounces > 1 else ''} after the camera ray's hit")
    if result.get("own_hair", render.OWN_HAIR[0]) != render.OWN_HAIR[0]:
        limit += f", lod-single with own-hair {result['own_hair']}"
    tolerance = result.get("vertex_tolerance_px", lod.DEFAULT_VERTEX_TOLERANCE_PX)
    if tolerance != lod.DEFAULT_VERTEX_TOLERANCE_PX:
        limit += ", every control point drawn" if tolerance == 0 else f", vertex LoD within {tolerance:g} px"
    scaled = {view: _view_spp(result, view) for view in result["views"]}
    samples = ", ".join(f"{view} {reference_spp} / {spp}" for view, (spp, reference_spp) in scaled.items())
    lines = [f"Converged: spp of the pt reference / each method per view {samples} (more where the hair covers fewer "
             f"pixels), {result['width']} x {result['width']} px{limit}. Blurred PSNR: of {box} x {box} box averages (linear). Radiance: signed error of "
             f"the mean linear radiance over the hair's pixels (strands' alpha > {result['hair_alpha']:g}). Coverage: "
             "the method's geometry against the strands (total alpha; mean |alpha difference| per pixel). Hair alone: "
             "the radiance error of the hair itself, each image unmixed from the sky its uncovered share shows (its own "
             "alpha). The pt row, an independent path-traced render, is the noise floor.", "",
             f"| view | method | segments | seconds | {error_columns} | coverage % | mean abs alpha % | hair alone R / G / B % |",
             "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    for view, entry in result["views"].items():
        ref = entry["reference"]
        spp, reference_spp = scaled[view]
        lines.append(f"| {view} | pt reference ({reference_spp} spp) | {ref['segments']} | {ref['seconds']:.3f} "
                     "| | | | | | | |")
        for method, r in entry["rows"].items():
            hair_alone = _rgb(r["hair_radiance_error"]) if "hair_radiance_error" in r else ""
            lines.append(f"| {view} | {label(method, spp)} | {r['segments']} | {r['seconds']:.3f} | {errors(r)} | "
                         f"{_percent(r['coverage_error'])} | {_percent(r['coverage_abs_error'], signed=False)} | "
                         f"{hair_alone} |")
    equal_time = result["equal_time"]
    lines += ["", f"Equal time: each method at {equal_time['spp']} spp against the same reference (noise included).",
              "", f"| view | method | segments | seconds | {error_columns} |", "| --- | --- | --- | --- | --- | --- | --- | --- |"]
    for view, entry in equal_time["views"].items():
        for method, r in entry["rows"].items():
            lines.append(f"| {view} | {label(method, equal_time['spp'])} | {r['segments']} | {r['seconds']:.3f} | "
                         f"{errors(r)} |")
    sweep = result["sweep"]
    lines += ["", f"eps_w sweep ({sweep['view']} view, lod at {sweep['spp']} spp; full geometry {sweep['full_segments']} "
              "segments):", "", f"| eps_w px | segments | seconds | {error_columns} |",
              "| --- | --- | --- | --- | --- | --- | --- |"]
    for r in sweep["rows"]:
        lines.append(f"| {r['eps_w']:g} | {r['segments']} | {r['seconds']:.3f} | {errors(r)} |")
    return "\n".join(lines)
