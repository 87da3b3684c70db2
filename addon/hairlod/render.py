"""Reference renderer over the C++ core (Embree, hair-lod-aggregated-bcsdf.txt Sec. 6): views framed on
the hair, default lights, LoD geometry from a selection, images out (EXR, PNG) and error metrics.

Methods: 'pt' path-traced full geometry with the Chiang BCSDF (the reference), 'ds' full geometry with
dual scattering, 'lod' LoD geometry with the aggregated BCSDF, 'lod-single' LoD geometry with the
single-fibre BCSDF, 'lod-no-s' the aggregated BCSDF without the thick hairs shadowing themselves
(ablations). A thick hair is shaded at the first of its strands the ray meets inside it, and shadowed
through its other strands.
"""

import os

import numpy as np

from . import _core, atomic_output, memory_budget, png
from .lod import DEFAULT_VERTEX_TOLERANCE_PX
from .hair_params import as_params
from .camera import look_at, perspective

__all__ = ["BLUR_BOX", "METHODS", "VIEWS", "blurred_psnr", "box_average", "coverage", "coverage_error",
           "default_lights", "frame_view", "lod_geometry", "mean_radiance_error", "psnr", "render", "ssim", "to_srgb8",
           "write_image"]

METHODS = ("pt", "ds", "lod", "lod-single", "lod-no-s")
# Fraction of the image the hair covers: (bounding-sphere diameter on screen / image height)^2.
VIEWS = {"near": 0.6, "mid": 0.2, "far": 0.02}
FOV_Y = np.radians(30.0)
# Pixels per side of the blocks blurred_psnr() averages: 4 x 4 averages 16 pixels' noise away (-12 dB).
BLUR_BOX = 4
# Scatterings after the camera ray's hit at most (Russian roulette ends most paths sooner); 0 is
# direct light only.
MAX_BOUNCES = _core.DEFAULT_MAX_BOUNCES
# What a path leaving a strand inside a thick hair does with the hair's other strands (lod-single;
# the first is the renderer's default): attenuate (skip them, keeping dual scattering's forward share)
# or scatter (meet them at their Poisson arrivals and scatter there). integrator.h, OwnHair.
OWN_HAIR = ("attenuate", "scatter")


def frame_view(points, view, width, height=None, fov_y=FOV_Y):
    """Camera dict (eye, target, up, fov_y, width, height) looking at the hair from the front (-y),
    slightly above, at the distance where its bounding sphere covers VIEWS[view] of the image."""
    if view not in VIEWS:
        raise ValueError(f"view must be one of {', '.join(VIEWS)}, got {view!r}")
    height = width if height is None else height
    points = np.asarray(points, dtype=np.float64)
    lower, upper = points.min(axis=0), points.max(axis=0)
    centre, radius = (lower + upper) / 2.0, max(np.linalg.norm(upper - lower) / 2.0, 1e-12)
    # The sphere's screen diameter over the image height is radius / (d tan(fov / 2)).
    distance = radius / (np.tan(fov_y / 2.0) * np.sqrt(VIEWS[view]))
    direction = np.array([0.0, -1.0, 0.35])
    eye = centre + distance * direction / np.linalg.norm(direction)
    return {"eye": eye.tolist(), "target": centre.tolist(), "up": [0.0, 0.0, 1.0], "fov_y": float(fov_y),
            "width": int(width), "height": int(height)}


def default_lights(camera):
    """A key light from above the camera's left and a dim uniform sky."""
    eye, target = np.asarray(camera["eye"]), np.asarray(camera["target"])
    forward = (target - eye) / np.linalg.norm(target - eye)
    key = forward + np.array([0.4, 0.0, -0.6])
    return {"directional": [(tuple(key / np.linalg.norm(key)), (3.0, 3.0, 3.0))], "points": [],
            "environment": np.array([0.15, 0.15, 0.15], np.float32)}


def _matrices(camera):
    view = look_at(camera["eye"], camera["target"], camera["up"])
    distance = np.linalg.norm(np.subtract(camera["eye"], camera["target"]))
    projection = perspective(camera["fov_y"], camera["width"] / camera["height"], 1e-3 * distance, 1e3 * distance)
    return view, projection


def lod_geometry(asset, camera, width_px=_core.DEFAULT_WIDTH_PX, guides=None,
                 vertex_tolerance_px=DEFAULT_VERTEX_TOLERANCE_PX):
    """The LoD selection (Sec. 5.1 step 5) for `camera`, at the rest pose or skinned to `guides`
    [G, n_c, 3] (an animated frame), as renderable geometry: (Strands of the strand-level segments or
    None, thick-hair dict or None). Each drawn strand keeps the control points its shape needs within
    `vertex_tolerance_px` pixels (vertex LoD, lod/vertex_lod.h; 0 keeps them all)."""
    if not (np.isfinite(vertex_tolerance_px) and vertex_tolerance_px >= 0):
        raise ValueError(f"vertex_tolerance_px must be >= 0 and finite, got {vertex_tolerance_px}")
    view, projection = _matrices(camera)
    selection = asset.select(view, projection, (camera["width"], camera["height"]), width_px, guides=guides)
    skinned = asset.skin(guides)
    nc = asset.control_points
    strand_order = asset.arrays()["strand_order"]
    thick = {"centres": [], "major_axis": [], "radii": [], "density": [], "counts": [], "n_total": []}
    strand_points, strand_radius, strand_counts = [], [], []
    rest = skinned["strands"]
    rest_points, rest_radius = rest.points.reshape(-1, nc, 3), rest.radius.reshape(-1, nc)
    for level, _cluster, first, count, first_segment, segment_count in selection.draws:
        k = np.arange(first_segment, first_segment + segment_count + 1)
        if level < len(asset.levels):
            hairs = np.arange(first, first + count)
            geometry, stored = skinned["levels"][level], asset.levels[level]
            major = geometry["major"][hairs][:, k]
            minor = geometry["minor"][hairs][:, k]
            major_radius = np.linalg.norm(major, axis=-1)
            minor_radius = np.minimum(np.linalg.norm(minor, axis=-1), major_radius)
            thick["centres"].append(geometry["centres"][hairs][:, k].reshape(-1, 3))
            thick["major_axis"].append((major / np.maximum(major_radius, 1e-30)[..., None]).reshape(-1, 3))
            thick["radii"].append(np.stack([major_radius, np.maximum(minor_radius, 1e-6 * major_radius)], -1).reshape(-1, 2))
            # rho in (0, 1]; the renderer floors it at bcsdf's kMinClusterDensity (real hair is sparse).
            thick["density"].append(np.minimum(stored.density[hairs][:, k], 1.0).reshape(-1))
            thick["counts"].append(np.full(count, len(k)))
            thick["n_total"].append(stored.n_total[hairs].astype(np.float32))
        else:
            strands = strand_order[first:first + count]
            strand_points.append(rest_points[strands][:, k].reshape(-1, 3))
            strand_radius.append(rest_radius[strands][:, k].reshape(-1))
            strand_counts.append(np.full(count, len(k)))

    strands = None
    if strand_points:
        points, radius = np.concatenate(strand_points), np.concatenate(strand_radius).astype(np.float32)
        offsets = np.concatenate([[0], np.cumsum(np.concatenate(strand_counts))]).astype(np.int64)
        keep = _core.vertex_lod_keep(points, offsets, radius[:, None], view, projection,
                                     (camera["width"], camera["height"]), vertex_tolerance_px)
        strands = _core.Strands.from_counts(points[keep], np.add.reduceat(keep.astype(np.int64), offsets[:-1]),
                                            radius[keep])
    # Thick hairs keep every section: each carries the area and density the aggregated shading and the
    # self-shadowing read (Sec. 4), not only an outline. Left out by their outline alone, the
    # generated hair's far view lost 3 points of red and 1.7 dB (README, Reference renderer).
    hairs = None
    if thick["centres"]:
        counts = np.concatenate(thick["counts"]).astype(np.int64)
        hairs = {"centres": np.concatenate(thick["centres"]), "major_axis": np.concatenate(thick["major_axis"]),
                 "radii": np.concatenate(thick["radii"]), "density": np.concatenate(thick["density"]),
                 "offsets": np.concatenate([[0], np.cumsum(counts)]).astype(np.int64),
                 "n_total": np.concatenate(thick["n_total"])}
    return strands, hairs


def render(strands, method="pt", view="mid", width=256, spp=16, asset=None, params=None, seed=0,
           max_bounces=MAX_BOUNCES, width_px=_core.DEFAULT_WIDTH_PX, lights=None, camera=None, progress=None, coverage_only=False,
           guides=None, own_hair=None, vertex_tolerance_px=DEFAULT_VERTEX_TOLERANCE_PX):
    """Renders `strands` (full geometry; also frames the view) or, for the lod methods, the selection of
    `asset` for the framed camera, skinned to `guides` [G, n_c, 3] when given (a frame of an animation:
    lod.load_animation, lod.frame_guides). Returns a dict: image [H, W, 3] float32 linear, camera, seconds,
    setup_seconds, rays, rays_per_second, segments (Embree curve segments in the scene).
    coverage_only: black hair under a white environment (it takes no `lights`), so every channel of
    the image is 1 - alpha, the thick hairs' gaps included. own_hair: one of OWN_HAIR for lod-single
    (None: the first). vertex_tolerance_px: the lod methods' vertex LoD (lod_geometry)."""
    if method not in METHODS:
        raise ValueError(f"method must be one of {', '.join(METHODS)}, got {method!r}")
    if own_hair is not None and own_hair not in OWN_HAIR:
        raise ValueError(f"own_hair must be one of {', '.join(OWN_HAIR)}, got {own_hair!r}")
    if own_hair not in (None, OWN_HAIR[0]) and method != "lod-single":
        raise ValueError(f"own_hair {own_hair!r} applies to the lod-single method only, not {method!r}")
    if int(spp) < 1 or int(width) < 1:
        raise ValueError(f"spp and width must be >= 1, got spp={spp}, width={width}")
    # The image in float32 and the renderer's float64 accumulation, with its film copies.
    memory_budget.check(int(width) ** 2 * 3 * (4 + 8 + 8), f"a {width} x {width} image (width)")
    strands.require_float_range("render")  # before framing the view on it
    camera = camera or frame_view(strands.points, view, width)
    if coverage_only:
        if lights is not None:
            raise ValueError("coverage_only renders under its own white environment: pass no lights")
        lights = {"directional": [], "points": [], "environment": np.ones(3, np.float32)}
    lights = lights or default_lights(camera)
    params = as_params(params)
    if method.startswith("lod"):
        if asset is None:
            raise ValueError(f"method {method!r} needs an LoD asset (--lod DIR)")
        scene_strands, thick = lod_geometry(asset, camera, width_px, guides, vertex_tolerance_px)
    else:
        scene_strands, thick = strands, None
    result = _core.render(scene_strands, thick, camera, lights, params, method=method, spp=int(spp),
                          max_bounces=int(max_bounces), seed=int(seed), coverage_only=bool(coverage_only),
                          progress=progress, own_hair=own_hair)
    result["camera"] = camera
    result["segments"] = int(result["strand_segments"] + result["thick_segments"])
    return result


def coverage(strands, method="pt", view="mid", width=256, spp=16, asset=None, camera=None, width_px=_core.DEFAULT_WIDTH_PX, seed=0,
             vertex_tolerance_px=DEFAULT_VERTEX_TOLERANCE_PX):
    """Alpha [H, W] float32 in [0, 1] of the geometry `method` renders (the strands, or the selection of
    `asset`), framed as render() frames it: the fraction of each pixel's camera rays that meet hair,
    through the thick hairs' gaps included (1 - render(coverage_only=True)'s image)."""
    result = render(strands, method, view, width, spp, asset=asset, seed=seed, width_px=width_px, camera=camera,
                    coverage_only=True, vertex_tolerance_px=vertex_tolerance_px)
    return 1.0 - result["image"][..., 0]


def to_srgb8(image, exposure=1.0):
    """Linear RGB -> 8-bit sRGB (clamped; the sRGB transfer curve, IEC 61966-2-1)."""
    x = np.clip(np.asarray(image, np.float64) * exposure, 0.0, 1.0)
    srgb = np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1.0 / 2.4) - 0.055)
    return np.round(srgb * 255.0).astype(np.uint8)


def write_image(path, image):
    """Writes linear RGB as .exr (float32) or .png (sRGB 8-bit) atomically (temporary name, rename)."""
    image = np.ascontiguousarray(image, dtype=np.float32)
    extension = os.path.splitext(path)[1].lower()
    if extension not in (".exr", ".png"):
        raise ValueError(f"{path}: output must end in .exr or .png")
    with atomic_output.replacing_file(path) as temporary:
        if extension == ".exr":
            _core.write_exr(temporary, image, ["R", "G", "B"])
        else:
            with open(temporary, "wb") as file:
                file.write(png.encode_png(to_srgb8(image[..., :3])))


def psnr(image, reference):
    """PSNR in dB of tone-mapped (sRGB, clamped) images: 10 log10(1 / MSE) on [0, 1]."""
    a, b = to_srgb8(image) / 255.0, to_srgb8(reference) / 255.0
    mse = float(np.mean((a - b) ** 2))
    return float("inf") if mse == 0.0 else 10.0 * np.log10(1.0 / mse)


def ssim(image, reference):
    """SSIM (scikit-image) of the tone-mapped images."""
    from skimage.metrics import structural_similarity

    return float(structural_similarity(to_srgb8(image), to_srgb8(reference), channel_axis=-1, data_range=255))


def box_average(image, box=BLUR_BOX):
    """Mean of `image` [H, W, ...] over box x box pixel blocks, [H // box, W // box, ...] float64 (the
    rows and columns past the last whole block are dropped)."""
    image, box = np.asarray(image, np.float64), int(box)
    if box < 1 or image.shape[0] < box or image.shape[1] < box:
        raise ValueError(f"a {image.shape[1]} x {image.shape[0]} image holds no {box} x {box} block")
    rows, columns = image.shape[0] // box, image.shape[1] // box
    blocks = image[:rows * box, :columns * box].reshape(rows, box, columns, box, *image.shape[2:])
    return blocks.mean(axis=(1, 3))


def blurred_psnr(image, reference, box=BLUR_BOX):
    """psnr() of the images box-averaged over box x box pixels in linear radiance, before the sRGB tone
    map: the image a box times coarser sensor would see. Pixel noise averages out (4 x 4: 16 pixels,
    +12 dB against pure noise) while a bias over the block stays, so it reads bias where psnr() reads
    noise. Infinite when the averaged 8-bit images are identical."""
    return psnr(box_average(image, box), box_average(reference, box))


def luminance(image):
    """Rec. 709 luminance of linear RGB [..., 3]: float64 [...]."""
    return np.asarray(image, np.float64)[..., :3] @ np.array([0.2126, 0.7152, 0.0722])


def weighted_percentiles(values, weights, percents):
    """Percentiles (0-100) of `values` [N] where each counts with its weight [N] (>= 0, their sum > 0):
    the weighted cumulative distribution, linear between the sorted values, so that a value of small
    weight moves them by little and one of weight 0 not at all."""
    values, weights = np.asarray(values, np.float64).ravel(), np.asarray(weights, np.float64).ravel()
    if values.shape != weights.shape or not len(values):
        raise ValueError(f"weighted_percentiles: {len(values)} values and {len(weights)} weights")
    if np.any(weights < 0.0) or not weights.sum() > 0.0:
        raise ValueError("weighted_percentiles: weights must be >= 0 with a positive sum")
    order = np.argsort(values, kind="stable")
    cumulative = np.cumsum(weights[order])
    return np.interp(np.asarray(percents, np.float64) / 100.0, cumulative / cumulative[-1], values[order])


# Fewer pixels than this make a spread of noise, not of the hair's look.
SPREAD_LEAST_PIXELS = 20


def same_pixels_spread(image, hair, reference, coverage, step, least=0.25, percents=(5, 95)):
    """The luminance spread (the `percents` percentiles) of `image` and of `reference` on the same
    pixels, the reference's. `image` [step H, step W, 3] with its hair pixels `hair` [step H, step W]
    (a screenshot of the preview) is averaged over the hair pixels of each step x step block;
    `reference` [H, W, 3] is the hair's own radiance (a render's, unmixed from the sky) where its hair
    covers `coverage` [H, W]. Only the pixels both cover by more than `least` count, each weighted by
    its reference coverage: where a render's pixel is mostly sky, its unmixed radiance is its noise
    divided by the coverage, and whole-image percentiles of different pixels compare nothing. Returns
    {"pixels", "image": [low, high], "reference": [low, high], "ratio": image's high - low over the
    reference's}, or None where fewer than SPREAD_LEAST_PIXELS pixels count."""
    paired = _same_pixels(image, hair, reference, coverage, step, least)
    if paired is None:
        return None
    averaged, reference, weights, _ = paired
    low_high = [weighted_percentiles(luminance(picture), weights, percents) for picture in (averaged, reference)]
    width = low_high[1][-1] - low_high[1][0]
    return {"pixels": int(len(weights)), "image": low_high[0].tolist(), "reference": low_high[1].tolist(),
            "ratio": float((low_high[0][-1] - low_high[0][0]) / width) if width > 0.0 else float("inf")}


def same_pixels_rows(image, hair, reference, coverage, step, bands=6, least=0.25):
    """The hair's large-scale shading across the image: the mean luminance of `image` and of `reference`
    on the same pixels (as same_pixels_spread pairs them, each weighted by its reference coverage) in
    `bands` bands of equal height between the first and last row that hold such pixels, in the arrays'
    row order. A mohawk under courtyard.exr is 40 % brighter at its tips than at its roots in a
    path-traced image; a spread alone does not say where. Returns {"pixels", "image": [bands],
    "reference": [bands]} (a band without pixels reads nan), or None as same_pixels_spread does."""
    bands = int(bands)
    if bands < 1:
        raise ValueError(f"bands must be >= 1, got {bands}")
    paired = _same_pixels(image, hair, reference, coverage, step, least)
    if paired is None:
        return None
    averaged, reference, weights, rows = paired
    edges = np.linspace(rows.min(), rows.max() + 1, bands + 1)
    band = np.clip(np.searchsorted(edges, rows, side="right") - 1, 0, bands - 1)
    means = {}
    for name, picture in (("image", averaged), ("reference", reference)):
        weighted = np.bincount(band, weights * luminance(picture), minlength=bands)
        total = np.bincount(band, weights, minlength=bands)
        means[name] = np.where(total > 0.0, weighted / np.maximum(total, 1e-300), np.nan).tolist()
    return {"pixels": int(len(weights)), **means}


def _same_pixels(image, hair, reference, coverage, step, least):
    """The pixels of the reference's grid that `image` (averaged over its hair pixels per step x step
    block) and `reference` both cover by more than `least`: (image's RGB [N, 3], reference's [N, 3],
    reference coverage [N], their rows [N]), or None where fewer than SPREAD_LEAST_PIXELS."""
    step = int(step)
    hair = np.asarray(hair, np.float64)
    covered = box_average(hair, step)
    averaged = box_average(np.asarray(image, np.float64)[..., :3] * hair[..., None], step) / \
        np.maximum(covered, 1e-12)[..., None]
    coverage = np.asarray(coverage, np.float64)
    height, width = min(covered.shape[0], coverage.shape[0]), min(covered.shape[1], coverage.shape[1])
    both = (covered[:height, :width] > least) & (coverage[:height, :width] > least)
    if both.sum() < SPREAD_LEAST_PIXELS:
        return None
    return (averaged[:height, :width][both], np.asarray(reference, np.float64)[:height, :width, :3][both],
            coverage[:height, :width][both], np.nonzero(both)[0])


def mean_radiance_error(image, reference, hair):
    """Signed relative error per channel (R, G, B) of the mean linear radiance of `image` over the
    pixels where `hair` [H, W] is true against that of `reference`: (mean(image) - mean(reference)) /
    mean(reference). NaN in a channel where the reference's mean is 0 or no pixel is hair."""
    hair = np.asarray(hair, bool)
    if not hair.any():
        return np.full(3, np.nan)
    test = np.asarray(image, np.float64)[hair].mean(axis=0)
    truth = np.asarray(reference, np.float64)[hair].mean(axis=0)
    error = np.full(3, np.nan)
    np.divide(test - truth, truth, out=error, where=truth > 0.0)
    return error


def hair_radiance_error(image, alpha, reference, reference_alpha, hair, background):
    """Signed relative error per channel (R, G, B) of the hair's own mean radiance: each image unmixed
    from the `background` radiance [3] that its camera rays show where its geometry leaves a pixel
    uncovered (its own `alpha` [H, W]), L_hair = (sum L - sum (1 - alpha) background) / sum alpha over
    the pixels where `hair` [H, W] is true. mean_radiance_error mixes the hair with that background in
    proportion to each image's coverage, so a coverage error shows there as a radiance error (most
    where the background is much brighter than the hair); this one leaves it out, so the two together
    tell the geometry's part from the shading's. NaN in a channel where the reference's hair radiance
    is 0, or where either image covers none of those pixels."""
    hair = np.asarray(hair, bool)
    background = np.asarray(background, np.float64).reshape(3)

    def unmixed(img, a):
        a = np.asarray(a, np.float64)[hair]
        covered = a.sum()
        if not covered > 0.0:
            return np.full(3, np.nan)
        return (np.asarray(img, np.float64)[hair].sum(axis=0) - (len(a) - covered) * background) / covered

    if not hair.any():
        return np.full(3, np.nan)
    test, truth = unmixed(image, alpha), unmixed(reference, reference_alpha)
    error = np.full(3, np.nan)
    np.divide(test - truth, truth, out=error, where=np.isfinite(test) & (truth > 0.0))
    return error


def coverage_error(alpha, reference_alpha):
    """(signed relative error of the total alpha, NaN when the reference covers nothing; mean absolute
    alpha difference over all pixels) of `alpha` against `reference_alpha` (both [H, W])."""
    alpha, reference_alpha = np.asarray(alpha, np.float64), np.asarray(reference_alpha, np.float64)
    total, reference_total = alpha.sum(), reference_alpha.sum()
    relative = (total - reference_total) / reference_total if reference_total > 0.0 else float("nan")
    return float(relative), float(np.mean(np.abs(alpha - reference_alpha)))
