"""LoD quality: speed against error of the render methods (hair-lod-aggregated-bcsdf.txt Sec. 6, Fig. 5 and 12).

bench_quality() renders, for each view (near, mid, far), a path-traced full-geometry reference at
`reference_spp` and every method at `spp`; each row holds the Embree segments in the scene, the render
time, rays per second and PSNR / SSIM / LDR-FLIP against the reference. A sweep of the LoD width
threshold eps_w (pixels, Eq. 16) at one view gives segments and time against error. The 'pt' row is an
independent path-traced render at `spp` (another seed): the noise floor the other methods are read
against. No assertions on times: a benchmark, not a test.
"""

import time

import numpy as np

from . import flip, lod, render

__all__ = ["EPS_W", "bench_quality", "default_guides", "format_tables", "plot_quality"]

EPS_W = (0.5, 1.0, 2.0, 4.0, 8.0)
_REFERENCE_SEED = 1_000_003


def default_guides(strand_count, guides=256):
    """256 guides, or a quarter of the strands (at least 1) for small inputs."""
    return int(max(1, min(guides, strand_count // 4)))


def _errors(image, reference):
    test_srgb, reference_srgb = render.to_srgb8(image) / 255.0, render.to_srgb8(reference) / 255.0
    psnr = render.psnr(image, reference)  # identical 8-bit images: infinite, reported as null (strict JSON)
    return {"psnr": psnr if np.isfinite(psnr) else None, "ssim": render.ssim(image, reference),
            "flip": flip.flip(test_srgb, reference_srgb)}


def _row(result):
    return {"segments": result["segments"], "strand_segments": int(result["strand_segments"]),
            "thick_segments": int(result["thick_segments"]), "seconds": float(result["seconds"]),
            "setup_seconds": float(result["setup_seconds"]), "rays": int(result["rays"]),
            "rays_per_second": float(result["rays_per_second"])}


def _difference(a, b):
    return None if a is None or b is None else a - b


def _db(value):
    return "inf" if value is None else f"{value:.2f}"


def bench_quality(strands, asset=None, views=tuple(render.VIEWS), methods=render.METHODS, spp=16, width=160,
                  reference_spp=128, eps_w=EPS_W, sweep_view="mid", width_px=2.0, guides=None, params=None, seed=0,
                  progress=None):
    """Dict with settings, the LoD build (when `asset` is None it is built here), one entry per view
    {camera, reference, rows: {method: row}} and the eps_w sweep rows. `progress(message)` is called
    before each render when given."""
    if int(spp) < 1 or int(width) < 1 or int(reference_spp) < 1:
        raise ValueError(f"spp, width and reference spp must be >= 1, got {spp}, {width}, {reference_spp}")
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
        guides = default_guides(len(strands)) if guides is None else int(guides)
        say(f"building the LoD ({guides} guides)")
        start = time.perf_counter()
        asset = lod.build_lod(strands, guides=guides)
        build = {"guides": asset.guide_count, "clusters": asset.cluster_count, "seconds": time.perf_counter() - start,
                 "levels": lod.level_report(asset)}
    references, result_views = {}, {}
    for view in dict.fromkeys(list(views) + [sweep_view]):
        say(f"{view}: pt reference at {reference_spp} spp")
        reference = render.render(strands, "pt", view, width, reference_spp, params=params, seed=_REFERENCE_SEED)
        references[view] = reference
        if view not in views:
            continue
        rows = {}
        for method in methods:
            say(f"{view}: {method}")
            out = render.render(strands, method, view, width, spp, asset=asset, params=params, seed=seed,
                                width_px=width_px)
            rows[method] = dict(_row(out), **_errors(out["image"], reference["image"]))
        result_views[view] = {"coverage": render.VIEWS[view], "camera": reference["camera"],
                              "reference": _row(reference), "rows": rows}
    sweep = []
    for eps in eps_w:
        say(f"{sweep_view}: lod at eps_w {eps:g} px")
        out = render.render(strands, "lod", sweep_view, width, spp, asset=asset, params=params, seed=seed,
                            width_px=float(eps))
        sweep.append(dict(_row(out), eps_w=float(eps), **_errors(out["image"], references[sweep_view]["image"])))
    full_sweep = render.render(strands, "ds", sweep_view, width, spp, params=params, seed=seed)
    summary = {}
    for view, entry in result_views.items():
        rows = entry["rows"]
        if "lod" in rows and ("ds" in rows or "pt" in rows):
            full = rows.get("ds", rows.get("pt"))["segments"]
            summary[view] = {"segment_reduction": full / max(rows["lod"]["segments"], 1),
                             "lod_minus_ds_psnr": _difference(rows["lod"]["psnr"], rows.get("ds", {}).get("psnr")),
                             "lod_minus_ds_flip": rows["lod"]["flip"] - rows["ds"]["flip"] if "ds" in rows else None}
    return {"strands": len(strands), "points": int(strands.point_count), "width": int(width), "spp": int(spp),
            "reference_spp": int(reference_spp), "width_px": float(width_px), "lod_build": build,
            "guides": asset.guide_count, "views": result_views, "summary": summary,
            "sweep": {"view": sweep_view, "full_segments": int(full_sweep["segments"]), "rows": sweep}}


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
    """The result as two Markdown tables (methods per view; the eps_w sweep), as a string."""
    lines = ["| view | method | segments | seconds | M rays/s | PSNR dB | SSIM | FLIP |",
             "| --- | --- | --- | --- | --- | --- | --- | --- |"]
    for view, entry in result["views"].items():
        ref = entry["reference"]
        lines.append(f"| {view} | pt reference ({result['reference_spp']} spp) | {ref['segments']} | "
                     f"{ref['seconds']:.3f} | {ref['rays_per_second'] / 1e6:.2f} | | | |")
        for method, r in entry["rows"].items():
            lines.append(f"| {view} | {method} | {r['segments']} | {r['seconds']:.3f} | "
                         f"{r['rays_per_second'] / 1e6:.2f} | {_db(r['psnr'])} | {r['ssim']:.4f} | {r['flip']:.4f} |")
    sweep = result["sweep"]
    lines += ["", f"eps_w sweep ({sweep['view']} view, lod; full geometry {sweep['full_segments']} segments):", "",
              "| eps_w px | segments | seconds | PSNR dB | SSIM | FLIP |", "| --- | --- | --- | --- | --- | --- |"]
    for r in sweep["rows"]:
        lines.append(f"| {r['eps_w']:g} | {r['segments']} | {r['seconds']:.3f} | {_db(r['psnr'])} | {r['ssim']:.4f} | "
                     f"{r['flip']:.4f} |")
    return "\n".join(lines)
