"""The world (environment) as SRBF lights for the viewport preview (no bpy).

Xu et al. 2011 (circular-gaussian-hair-env-lighting.txt, Sec. 3) light hair with a sum of spherical
radial basis functions, L(w) = sum_j L_j G(w; w_j, lambda), G = exp(2 (w . w_j - 1) / lambda^2).
``fit_world`` fits radiance samples of a world (a uniform colour, an environment map) with a uniform
term c_0 (one SRBF of infinite bandwidth, so a uniform world is represented exactly) plus ``count``
lobes of one shared bandwidth: the amplitudes solve a solid-angle-weighted non-negative least-squares
problem per colour channel (Lawson and Hanson 1974), since a negative light would darken the hair
where the world is dark and the shader cannot tell. A shared bandwidth lets the preview tabulate
the hair's response to one lobe once (hairlod.preview_luts.srbf_tables); the lobes' centres are free.

The lobes go where the light is. A spherical Fibonacci set spaced sqrt(4 pi / count) apart, the
bandwidth its spacing, spreads Blender's courtyard.exr (40 % of its light from 0-20 degrees above the
horizon, its zenith dark) over the whole sky: relative error 0.84, and a mohawk's tips, 40 % brighter
than its roots in a path-traced image, came out as bright as them. So the centres are also moved by
Lloyd's iterations of spherical k-means over the samples weighted by their light (luminance x solid
angle), starting from the Fibonacci set, and the bandwidth is chosen from the Fibonacci spacing down
to MIN_LOBE_BANDWIDTH: of the fits with either set of centres, the one of least residual is kept.
Its amplitudes are then scaled per channel so that the fit holds the world's light (the integral of
the radiance over the sphere). The least-squares fit holds it exactly only while its uniform term
is above 0 (its residual then sums to 0): studio.exr's held 1.55x, the Fibonacci fits 1.06-1.28x,
and the hair's mean response follows. On Blender's eight studio worlds (suns taken out) the
response of the Chiang fibre at 300 random (tangent, view) pairs to the fit is within 6-31 % RMS of
its response to the image, against 25-67 % for the Fibonacci fit (scripts/bench_world_fit.py;
docs/preview.md, "The world's lobes where its light is").

A sun in an environment map is a few texels thousands of times the sky's radiance (Blender's
sunrise.exr: 59 % of its light in 4e-4 sr). Lobes of bandwidth 0.89 (16 of them) would spread it over
a quarter of the sky, where the hair lets it through as soft light; ``extract_sun`` takes it out of the
image first, as a light of its own (its direction and irradiance), which the preview shades like a sun
lamp: with its own deep opacity map and the BCSDF's sharp response.
"""

from dataclasses import dataclass

import numpy as np


__all__ = ["DEFAULT_LOBE_COUNT", "LLOYD_ITERATIONS", "MIN_LOBE_BANDWIDTH", "SUN_CONTRAST", "SUN_MIN_SHARE", "SUN_RADIUS",
           "UNIFORM_BANDWIDTH", "WorldLights", "blender_equirectangular_directions", "blender_equirectangular_world",
           "equirectangular_samples", "extract_sun", "fit_world", "fibonacci_directions", "lobe_bandwidth", "srbf", "srbf_mean",
           "uniform_world", "world_radiance"]

DEFAULT_LOBE_COUNT = 16
# The bandwidth standing for "infinite" where an SRBF evaluation needs a number: G >= 1 - 4e-6.
UNIFORM_BANDWIDTH = 1e3
# A sun (extract_sun): the texels within SUN_RADIUS (radians) of the brightest one whose luminance is over
# SUN_CONTRAST times the world's mean, when they hold at least SUN_MIN_SHARE of its light. Blender's
# studio worlds: city, interior, night and sunrise hold 24-59 % of their light in such texels
# (2e-4 to 4e-3 sr); forest's sun behind leaves 8 % over 0.0025 sr and the softboxes of studio.exr
# 67 % over 0.03 sr, wider than SUN_RADIUS takes whole; courtyard has no texel over 69x its mean.
SUN_CONTRAST = 100.0
# The narrowest lobe a fit may choose (radians of G's 1/e half-width): the preview's response table
# samples theta_o, theta_j and phi at 20 nodes, about 0.17 rad apart (preview_luts.srbf_tables), and
# a lobe narrower than about that falls between its nodes.
MIN_LOBE_BANDWIDTH = 0.2
# Lloyd's iterations moving the lobes' centres to where the light is (fit_world). On Blender's studio
# worlds a centre still moves by up to 9 degrees from 30 to 60 iterations (forest; under 2 on six of
# the eight), and the hair's response to the fit changes by under 0.002 RMS (scripts/bench_world_fit.py's
# measure).
LLOYD_ITERATIONS = 30
SUN_RADIUS = 0.1
SUN_MIN_SHARE = 0.05
_LUMINANCE = np.array([0.2126, 0.7152, 0.0722])


@dataclass(frozen=True)
class WorldLights:
    constant: np.ndarray      # float64 [3]: c_0, the uniform part of the radiance (>= 0)
    directions: np.ndarray    # float64 [K, 3]: unit lobe centres w_j, world space
    lam: float                # the lobes' shared bandwidth lambda
    coefficients: np.ndarray  # float64 [K, 3]: L_j >= 0
    relative_error: float     # weighted RMS error of the fit over the weighted RMS of the samples
    # A sun taken out of the world before the fit (extract_sun), or None: the unit direction towards
    # it (world space) and its irradiance on a surface facing it (RGB).
    sun_direction: np.ndarray = None
    sun_irradiance: np.ndarray = None

    def srbf_lights(self):
        """The lobes in the form hairlod.bcsdf.srbf_single_scattering takes, the uniform term as one
        more lobe of bandwidth UNIFORM_BANDWIDTH."""
        return {"directions": np.vstack([self.directions, [[0.0, 0.0, 1.0]]]),
                "lambdas": np.append(np.full(len(self.directions), self.lam), UNIFORM_BANDWIDTH),
                "coefficients": np.vstack([self.coefficients, self.constant[None, :]])}


def fibonacci_directions(count):
    """count unit directions spread evenly over the sphere (golden-angle spiral), float64 [count, 3]."""
    count = int(count)
    if count < 1:
        raise ValueError(f"count must be >= 1, got {count}")
    k = np.arange(count) + 0.5
    z = 1.0 - 2.0 * k / count
    r = np.sqrt(np.maximum(0.0, 1.0 - z * z))
    phi = np.pi * (3.0 - np.sqrt(5.0)) * k
    return np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=1)


def srbf(w, centre, lam):
    """Xu et al. 2011, Sec. 3: G(w; w_j, lambda) = exp(2 (w . w_j - 1) / lambda^2) for unit vectors."""
    return np.exp(2.0 * (np.asarray(w) @ np.asarray(centre) - 1.0) / (lam * lam))


def srbf_mean(lam):
    """The mean over the sphere of G(w; w_j, lambda) (srbf): with kappa = 2 / lambda^2, G integrates to
    2 pi (1 - exp(-2 kappa)) / kappa, so the mean is (1 - exp(-2 kappa)) / (2 kappa) (1 as lambda grows)."""
    kappa = 2.0 / (float(lam) * float(lam))
    return float(-np.expm1(-2.0 * kappa) / (2.0 * kappa))


def lobe_bandwidth(count):
    """The mean spacing sqrt(4 pi / count) of `count` Fibonacci centres: neighbouring lobes overlap
    at about exp(-2) of their peak, smooth enough to fit a smooth world without ringing."""
    return float(np.sqrt(4.0 * np.pi / count))


def world_radiance(lights, w):
    """The fitted radiance c_0 + sum_j L_j G(w; w_j, lambda) for unit directions w [N, 3], [N, 3]."""
    basis = srbf(np.asarray(w, np.float64), lights.directions.T, lights.lam)
    return lights.constant[None, :] + basis @ lights.coefficients


def uniform_world(colour, count=DEFAULT_LOBE_COUNT):
    """A uniform world of radiance `colour` (RGB): exactly c_0, every lobe zero."""
    colour = np.asarray(colour, np.float64).reshape(-1)
    if colour.shape != (3,) or not np.all(np.isfinite(colour)) or np.any(colour < 0.0):
        raise ValueError(f"world colour must be 3 finite values >= 0, got {colour.tolist()}")
    count = _lobe_count(count)
    return WorldLights(constant=colour.copy(), directions=fibonacci_directions(count), lam=lobe_bandwidth(count),
                       coefficients=np.zeros((count, 3)), relative_error=0.0)


def fit_world(directions, solid_angles, radiance, count=DEFAULT_LOBE_COUNT, adaptive=True):
    """WorldLights fitting radiance samples: ``directions`` [P, 3] (unit, world space), their
    ``solid_angles`` [P] (> 0, the quadrature weights of the sphere) and ``radiance`` [P, 3] (>= 0).
    ``adaptive=False`` gives the fit of earlier releases, the baseline scripts/bench_world_fit.py
    measures against: the Fibonacci centres, the bandwidth their spacing, the least-squares amplitudes
    as they come."""
    directions = np.asarray(directions, np.float64)
    solid_angles = np.asarray(solid_angles, np.float64).reshape(-1)
    radiance = np.asarray(radiance, np.float64)
    if directions.ndim != 2 or directions.shape[1] != 3 or len(directions) == 0:
        raise ValueError(f"directions must have shape [P, 3] with P >= 1, got {directions.shape}")
    if radiance.shape != directions.shape:
        raise ValueError(f"radiance must have shape {directions.shape} like directions, got {radiance.shape}")
    if solid_angles.shape != (len(directions),):
        raise ValueError(f"solid_angles must have shape [{len(directions)}], got {solid_angles.shape}")
    for name, values in (("directions", directions), ("solid_angles", solid_angles), ("radiance", radiance)):
        if not np.all(np.isfinite(values)):
            raise ValueError(f"{name} must be finite (found NaN or infinity)")
    if np.any(solid_angles <= 0.0):
        raise ValueError("solid_angles must be > 0")
    if np.any(radiance < 0.0):
        raise ValueError("radiance must be >= 0")
    lengths = np.linalg.norm(directions, axis=1)
    if np.any(lengths < 1e-12):
        raise ValueError("directions must be non-zero")
    count = _lobe_count(count)
    directions = directions / lengths[:, None]
    root_weight = np.sqrt(solid_angles)[:, None]
    total = float(np.sum((radiance * root_weight) ** 2))
    spread = fibonacci_directions(count)
    if not adaptive:
        amplitudes, centres, lam = _nnls_fit(directions, root_weight, radiance, spread, lobe_bandwidth(count))[1:]
    else:
        fits = [_nnls_fit(directions, root_weight, radiance, centres, lam)
                for centres in (spread, _light_centres(directions, solid_angles, radiance, spread))
                for lam in _bandwidths(count)]
        amplitudes, centres, lam = min(fits, key=lambda fit: fit[0])[1:]
    basis = _basis(directions, centres, lam)
    if adaptive:
        # The fit holds the world's light, per channel: the least-squares amplitudes with the uniform term at
        # 0 do not (studio.exr's 1.55x).
        held = np.sum(basis * solid_angles[:, None], axis=0) @ amplitudes
        light = solid_angles @ radiance
        amplitudes = amplitudes * np.where(held > 0.0, light / np.maximum(held, 1e-300), 1.0)
    residual = (basis @ amplitudes - radiance) * root_weight
    relative = float(np.sqrt(np.sum(residual ** 2) / total)) if total > 0.0 else 0.0
    return WorldLights(constant=amplitudes[0], directions=centres, lam=lam, coefficients=amplitudes[1:],
                       relative_error=relative)


def _basis(directions, centres, lam):
    """The uniform term and the lobes at unit `directions` [P, 3]: [P, 1 + K]."""
    return np.concatenate([np.ones((len(directions), 1)), srbf(directions, centres.T, lam)], axis=1)


def _nnls_fit(directions, root_weight, radiance, centres, lam):
    """(weighted squared residual, amplitudes [1 + K, 3], centres, lam) of the non-negative fit."""
    weighted_basis = _basis(directions, centres, lam) * root_weight
    # |A x - b| = |R x - Q^T b| + a constant for A = Q R: the same problem on 1 + K rows, not P.
    q, r = np.linalg.qr(weighted_basis)
    projected = q.T @ (radiance * root_weight)
    amplitudes = np.stack([_nnls(r, projected[:, c]) for c in range(3)], axis=1)
    residual = weighted_basis @ amplitudes - radiance * root_weight
    return float(np.sum(residual ** 2)), amplitudes, centres, lam


def _bandwidths(count):
    """The bandwidths a fit of `count` lobes tries: the Fibonacci spacing, then halved in area at each step
    down to MIN_LOBE_BANDWIDTH (at least the spacing itself)."""
    widest = lobe_bandwidth(count)
    steps = int(np.floor(2.0 * np.log2(widest / MIN_LOBE_BANDWIDTH))) if widest > MIN_LOBE_BANDWIDTH else 0
    return [widest * 2.0 ** (-0.5 * k) for k in range(steps + 1)]


def _light_centres(directions, solid_angles, radiance, start):
    """Spherical k-means (Lloyd's iterations) of the unit `directions`, each weighted by its light
    (luminance x solid angle), from the centres `start` [K, 3]; a centre that gathers no light stays."""
    weights = (radiance @ _LUMINANCE) * solid_angles
    centres = start.copy()
    for _ in range(LLOYD_ITERATIONS):
        nearest = np.argmax(directions @ centres.T, axis=1)
        sums = np.zeros_like(centres)
        np.add.at(sums, nearest, directions * weights[:, None])
        lengths = np.linalg.norm(sums, axis=1)
        moved = lengths > 1e-12 * max(float(weights.sum()), 1e-300)
        centres[moved] = sums[moved] / lengths[moved, None]
    return centres


def blender_equirectangular_directions(height, width, rows=slice(None)):
    """Pixel-centre directions [H, W, 3] and solid angles [H, W] of an equirectangular image as
    Blender's Environment Texture maps it (Cycles' direction_to_equirectangular): row 0 at the bottom
    (elevation -pi/2 to pi/2 upwards), u = 0.5 - atan2(y, x) / (2 pi), so the image's middle column
    looks along +x. `rows` (a slice) gives only those rows."""
    elevation = ((np.arange(height)[rows] + 0.5) / height - 0.5) * np.pi
    azimuth = np.pi - 2.0 * np.pi * (np.arange(width) + 0.5) / width
    cos_e = np.cos(elevation)[:, None]
    directions = np.stack(np.broadcast_arrays(cos_e * np.cos(azimuth)[None, :], cos_e * np.sin(azimuth)[None, :],
                                              np.sin(elevation)[:, None]), axis=-1)
    solid_angle = np.broadcast_to(cos_e * (np.pi / height) * (2.0 * np.pi / width), (len(elevation), width))
    return directions, solid_angle


def extract_sun(image, directions, solid_angles, world=None):
    """(image without its sun, unit direction towards the sun [3], its irradiance [3]) for radiance
    texels ``image`` [..., 3] >= 0 seen along unit ``directions`` [..., 3] over ``solid_angles`` [...],
    or (image, None, None) where the world has no sun. ``world``: (its light, sum of luminance x solid
    angle, and its solid angle) when the texels are only a part of it holding its brightest texel and
    every texel within 2 SUN_RADIUS of it; default, the texels' own. The sun is every texel within SUN_RADIUS of the
    brightest one whose luminance exceeds SUN_CONTRAST times the world's mean (by solid angle), if what
    they hold over the sky around them is SUN_MIN_SHARE of the world's light or more. Those texels
    take the sky's radiance instead: the mean (by solid angle) of the others within 2 SUN_RADIUS of
    the brightest, per channel, where a texel is brighter than that. The sun's irradiance is what they
    lose, the sum of radiance x solid angle (the light on a surface facing the sun; its spread below
    SUN_RADIUS ignored), and its direction theirs, weighted by the luminance each loses: the image and
    the sun together hold the world's light."""
    image = np.asarray(image, np.float64)
    directions = np.asarray(directions, np.float64)
    solid_angles = np.asarray(solid_angles, np.float64)
    luminance = image @ _LUMINANCE
    total, sphere = world if world is not None else (float(np.sum(luminance * solid_angles)), float(np.sum(solid_angles)))
    if not total > 0.0:
        return image, None, None
    threshold = SUN_CONTRAST * total / sphere
    closeness = directions @ directions[np.unravel_index(np.argmax(luminance), luminance.shape)]
    sun = (closeness >= np.cos(SUN_RADIUS)) & (luminance > threshold)
    around = (closeness >= np.cos(2.0 * SUN_RADIUS)) & ~sun
    sky = (np.sum(image[around] * solid_angles[around][:, None], axis=0) / float(np.sum(solid_angles[around]))
           if around.any() else np.zeros(3))
    without = image.copy()
    without[sun] = np.minimum(image[sun], sky)
    lost = (image - without) * solid_angles[..., None]
    if float(np.sum(lost @ _LUMINANCE)) < SUN_MIN_SHARE * total:
        return image, None, None
    towards = np.sum(directions[sun] * (lost[sun] @ _LUMINANCE)[:, None], axis=0)
    return without, towards / np.linalg.norm(towards), np.sum(lost, axis=(tuple(range(lost.ndim - 1))))


def blender_equirectangular_world(image, count=DEFAULT_LOBE_COUNT, max_height=32, sun=True):
    """WorldLights fitting an equirectangular radiance image ``image`` [H, W, 3] laid out as
    Blender's pixels (blender_equirectangular_directions): fit_world over equirectangular_samples."""
    samples = equirectangular_samples(image, max_height, sun)
    lights = fit_world(*samples[:3], count)
    if samples[3] is None:
        return lights
    return WorldLights(constant=lights.constant, directions=lights.directions, lam=lights.lam,
                       coefficients=lights.coefficients, relative_error=lights.relative_error,
                       sun_direction=samples[3], sun_irradiance=samples[4])


def equirectangular_samples(image, max_height=32, sun=True):
    """The samples of an equirectangular radiance image ``image`` [H, W, 3] (Blender's pixel layout)
    that the lobes are fitted to: (directions [P, 3], solid angles [P], radiance [P, 3], the sun's
    direction [3] or None, its irradiance [3] or None). With ``sun``, a sun is taken out first at the
    image's own resolution (extract_sun). Images taller than ``max_height`` are then box-filtered down:
    the lobes are far wider than a texel."""
    image = np.asarray(image, np.float64)
    if image.ndim != 3 or image.shape[2] != 3 or image.shape[0] < 1 or image.shape[1] < 1:
        raise ValueError(f"image must have shape [H, W, 3], got {image.shape}")
    if not np.all(np.isfinite(image)) or np.any(image < 0.0):
        raise ValueError("image must be finite and >= 0")
    sun_direction = sun_irradiance = None
    if sun:
        image, sun_direction, sun_irradiance = _extract_equirectangular_sun(image)
    factor = max(1, int(np.ceil(image.shape[0] / max_height)))
    height, width = image.shape[0] // factor, image.shape[1] // factor
    if width < 1:
        raise ValueError(f"image {image.shape[1]}x{image.shape[0]} is too narrow for its height")
    image = image[:height * factor, :width * factor].reshape(height, factor, width, factor, 3).mean(axis=(1, 3))
    directions, solid_angles = blender_equirectangular_directions(height, width)
    return (directions.reshape(-1, 3), solid_angles.reshape(-1), image.reshape(-1, 3), sun_direction,
            sun_irradiance)


def _extract_equirectangular_sun(image):
    """extract_sun on a Blender-layout equirectangular image, the directions made only for the rows
    within 2 SUN_RADIUS of the brightest texel's (an 8k image's would take 0.8 GB)."""
    height, width = image.shape[:2]
    luminance = image @ _LUMINANCE
    row_solid_angle = np.cos(((np.arange(height) + 0.5) / height - 0.5) * np.pi) * (np.pi / height) * (2.0 * np.pi / width)
    total = float(np.sum(luminance.sum(axis=1) * row_solid_angle))
    brightest_row = int(np.unravel_index(np.argmax(luminance), luminance.shape)[0])
    reach = int(np.ceil(2.0 * SUN_RADIUS / (np.pi / height))) + 1
    rows = slice(max(0, brightest_row - reach), min(height, brightest_row + reach + 1))
    band, sun_direction, sun_irradiance = extract_sun(image[rows], *blender_equirectangular_directions(height, width, rows),
                                                      world=(total, float(row_solid_angle.sum()) * width))
    if sun_direction is None:
        return image, None, None
    image = image.copy()
    image[rows] = band
    return image, sun_direction, sun_irradiance


def _lobe_count(count):
    if isinstance(count, bool) or not isinstance(count, (int, np.integer)) or count < 1:
        raise ValueError(f"lobe count must be an integer >= 1, got {count!r}")
    return int(count)


def _nnls(a, b):
    """min |a x - b| subject to x >= 0: Lawson and Hanson's active-set method (Solving Least Squares
    Problems, 1974, Ch. 23), small dense problems only."""
    columns = a.shape[1]
    x = np.zeros(columns)
    passive = np.zeros(columns, bool)
    tolerance = 1e-12 * max(1.0, float(np.abs(a).max()) * float(np.abs(b).max()))
    for _ in range(3 * columns):
        gradient = a.T @ (b - a @ x)
        candidates = np.where(passive, -np.inf, gradient)
        if passive.all() or candidates.max() <= tolerance:
            break
        passive[int(np.argmax(candidates))] = True
        while True:
            z = np.zeros(columns)
            z[passive] = np.linalg.lstsq(a[:, passive], b, rcond=None)[0]
            if np.all(z[passive] > 0.0):
                x = z
                break
            # Step from x towards z until the first passive variable reaches zero, then drop it.
            blocking = passive & (z <= 0.0)
            step = np.min(x[blocking] / (x[blocking] - z[blocking]))
            x = x + step * (z - x)
            passive &= x > tolerance
            x[~passive] = 0.0
    return x
