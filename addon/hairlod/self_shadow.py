"""Cheap self-shadowing of the viewport preview, without a shadow map (no bpy).

realtime-pbr-hair-thesis.txt Sec. 4.5 (after Karis 2016) replaces the hard shadow-map test by an
exponential falloff of the light with the depth, in light space, of the shaded point below the
first lit hair: points behind more hair receive less light. We estimate that depth from the asset
alone: the hair volume is the axis-aligned ellipsoid whose semi-axes are the half extents of the
strands' bounding box, and the depth d is the length of the path from the point towards the light
that lies inside it (0 on the lit side, growing into the hair; 0 for points the ray to the light
never crosses the volume from). The light reaching the point is T = exp(-sigma d) with

    sigma = strength x 2 r L / V,

2 r L / V the projected fibre area per unit volume (all strands' length L times their mean
diameter 2 r, over the ellipsoid's volume V = 4/3 pi a b c): the extinction coefficient of a
volume of fibres crossed at right angles. `strength` (the panel's "Shadowing", default 1) scales
it; 0 disables the term. A fibre passes much of the light that hits it forward (the TT lobe): the
preview's shader keeps T^(1 - a_f) per channel, a_f the fibre's forward-scattered share (dual
scattering), which this module leaves to it.

shaders/self_shadow.glsl evaluates the same formula; tests/ui/test_bcsdf_shader.py compares them.
"""

from dataclasses import dataclass

import numpy as np

__all__ = ["HairVolume", "WORLD_DIRECTIONS", "hair_volume", "scattered_share", "strand_arrays", "strands_volume",
           "transmittance", "world_depths", "world_transmittance", "world_transmittance_by_side"]

# Semi-axes are at least this share of the largest one, so flat hair (all in a plane) keeps a
# finite volume and the ellipsoid test stays well conditioned.
MIN_AXIS_SHARE = 1e-3


@dataclass(frozen=True)
class HairVolume:
    centre: np.ndarray     # float64 [3], object space
    semi_axes: np.ndarray  # float64 [3], > 0
    extinction: float      # 2 r L / V, per object-space unit; 0 when the hair has no extent


def hair_volume(points, offsets, radius):
    """The HairVolume of strands given as points [N, 3], offsets [C + 1] and radius [N] (the layout
    of hairlod.Strands)."""
    points, offsets, radius = strand_arrays(points, offsets, radius, "hair volume")
    # Segments within a strand only: drop the step from one strand's tip to the next one's root.
    steps = np.linalg.norm(np.diff(points, axis=0), axis=1)
    within = np.ones(len(steps), bool)
    within[offsets[1:-1] - 1] = False
    return _volume(points.min(axis=0), points.max(axis=0), float(steps[within].sum()), float(radius.mean()))


def strand_arrays(points, offsets, radius, what):
    """points [N >= 2, 3], offsets [C + 1] from 0 to N and radius [N], finite, as float64 / int64 arrays;
    ValueError naming `what` and the array at fault otherwise."""
    points = np.asarray(points, dtype=np.float64)
    offsets = np.asarray(offsets, dtype=np.int64)
    radius = np.asarray(radius, dtype=np.float64)
    if points.ndim != 2 or points.shape[1] != 3 or len(points) < 2:
        raise ValueError(f"{what}: points must have shape [N >= 2, 3], got {list(points.shape)}")
    if radius.shape != (len(points),):
        raise ValueError(f"{what}: radius must have shape [{len(points)}], got {list(radius.shape)}")
    if offsets.ndim != 1 or len(offsets) < 2 or offsets[0] != 0 or offsets[-1] != len(points):
        raise ValueError(f"{what}: offsets must run from 0 to {len(points)}")
    if not (np.isfinite(points).all() and np.isfinite(radius).all()):
        raise ValueError(f"{what}: points and radius must be finite")
    return points, offsets, radius


def strands_volume(strands):
    """The HairVolume of a hairlod.Strands (validated, finite), from the core's bounding box and curve
    lengths: the same as hair_volume of its arrays, without numpy passes over every point (0.4 s on
    100k strands of 17 points, where the preview's first frame waits for it)."""
    lower, upper = strands.bounding_box()
    return _volume(np.asarray(lower, np.float64), np.asarray(upper, np.float64), float(np.sum(strands.curve_lengths())),
                   float(np.mean(strands.radius, dtype=np.float64)))


def moved_volume(rest_volume, rest_box, box):
    """The HairVolume of hair that moved or deformed, from its rest volume and a box bounding it at
    rest and now ((lower, upper) pairs, e.g. of the skinned clusters' spheres): the ellipsoid moves
    with the box's centre and scales with its extents, and the extinction scales inversely with the
    volume (the same strands, spread wider). Exact for a translation; a rotation is seen through the
    axis-aligned box."""
    rest_lower, rest_upper = (np.asarray(v, np.float64) for v in rest_box)
    lower, upper = (np.asarray(v, np.float64) for v in box)
    rest_extent, extent = rest_upper - rest_lower, upper - lower
    scale = np.where(rest_extent > 0.0, extent / np.where(rest_extent > 0.0, rest_extent, 1.0), 1.0)
    scale = np.maximum(scale, MIN_AXIS_SHARE)  # a box collapsed to a plane keeps a finite extinction
    centre = np.asarray(rest_volume.centre, np.float64) + 0.5 * ((lower + upper) - (rest_lower + rest_upper))
    return HairVolume(centre=centre, semi_axes=np.asarray(rest_volume.semi_axes, np.float64) * scale,
                      extinction=rest_volume.extinction / float(np.prod(scale)))


def _volume(lower, upper, length, mean_radius):
    """The ellipsoid of the box [lower, upper] and the extinction 2 r L / V of strands of total length
    L and mean radius r in it."""
    half_extent = 0.5 * (upper - lower)
    largest = float(half_extent.max())
    if largest <= 0.0:
        return HairVolume(centre=0.5 * (lower + upper), semi_axes=np.ones(3), extinction=0.0)
    semi_axes = np.maximum(half_extent, MIN_AXIS_SHARE * largest)
    volume = 4.0 / 3.0 * np.pi * float(np.prod(semi_axes))
    return HairVolume(centre=0.5 * (lower + upper), semi_axes=semi_axes, extinction=2.0 * mean_radius * length / volume)


# Directions the world's light is averaged over (the 6 axes and the 8 cube diagonals, unit length):
# self_shadow.glsl's HAIR_WORLD_DIRECTIONS are the same.
WORLD_DIRECTIONS = np.concatenate([np.vstack([np.eye(3), -np.eye(3)]),
                                   np.array([(x, y, z) for x in (1, -1) for y in (1, -1) for z in (1, -1)]) / np.sqrt(3.0)])


def world_depths(points, volume, strength):
    """The optical depths from points [N, 3] out to the world along WORLD_DIRECTIONS through the hair
    volume, each direction taken as a sun (transmittance): float64 [N, 14] (self_shadow.glsl's
    hair_world_depths)."""
    points = np.atleast_2d(np.asarray(points, dtype=np.float64))
    return np.stack([-np.log(transmittance(points, np.append(direction, 0.0), volume, strength))
                     for direction in WORLD_DIRECTIONS], axis=1)


def _world_keep(keep):
    keep = np.asarray(keep, dtype=np.float64)
    if keep.shape not in ((3,), (len(WORLD_DIRECTIONS), 3)):
        raise ValueError(f"world transmittance: keep must have shape [3] or [{len(WORLD_DIRECTIONS)}, 3], "
                         f"got {list(keep.shape)}")
    return np.broadcast_to(keep, (len(WORLD_DIRECTIONS), 3))


def world_transmittance(points, volume, strength, keep=None):
    """The share of a uniform world's light that reaches points [N, 3] through the hair volume:
    transmittance() over WORLD_DIRECTIONS taken as suns, averaged; float64 [N]. The world lights the
    hair's inside through the hair as the suns do; without it the preview's interior was lit by the
    whole sky (2.2x the path-traced hair radiance on generated hair). With `keep` (1 - a_f, the share
    the strands on the way do not pass on forwards: per channel [3], or per direction of
    WORLD_DIRECTIONS and channel [14, 3], as the preview takes a_f at each direction's inclination to
    the strand) each direction's T is raised to it before the average, [N, 3], as self_shadow.glsl's
    hair_world_transmittance does."""
    tau = world_depths(points, volume, strength)
    if keep is None:
        return np.exp(-tau).mean(axis=1)
    return np.exp(-tau[:, :, None] * _world_keep(keep)[None, :, :]).mean(axis=1)


def world_transmittance_by_side(tau, keep, facing):
    """self_shadow.glsl's hair_world_transmittance: from optical depths tau [N, 14] along WORLD_DIRECTIONS
    (world_depths, or world_occlusion.optical_depths times the strength), keep [3] or [14, 3] (1 - a_f) and
    facing [N, 14] (the cosine between each direction and the direction towards the camera), each
    direction's exp(-keep tau) averaged over all 14 directions, over those on the camera's side (facing >
    1e-4) and over those on the far side (facing < -1e-4), a direction across the view counting half to
    each; (all, near, far), float64 [N, 3] each. A side without directions takes the mean over all. The
    preview's uniform world lights a strand's R share from the camera's side, its TT share from the far
    side (hair_shading.glsl's world_by_side)."""
    tau = np.atleast_2d(np.asarray(tau, dtype=np.float64))
    facing = np.broadcast_to(np.asarray(facing, dtype=np.float64), tau.shape)
    through = np.exp(-tau[:, :, None] * _world_keep(keep)[None, :, :])
    near_weight = np.where(facing > 1e-4, 1.0, np.where(facing < -1e-4, 0.0, 0.5))[:, :, None]
    near_count, far_count = near_weight.sum(axis=1), (1.0 - near_weight).sum(axis=1)
    all_directions = through.mean(axis=1)
    near = np.where(near_count > 0.0, (near_weight * through).sum(axis=1) / np.maximum(near_count, 1e-30), all_directions)
    far = np.where(far_count > 0.0, ((1.0 - near_weight) * through).sum(axis=1) / np.maximum(far_count, 1e-30),
                   all_directions)
    return all_directions, near, far


def scattered_share(transmittance, albedo):
    """The world's light the hair around a point scatters to it, as a share of the light that reaches the
    point straight from the world: (1 - T) rho / (1 - rho (1 - T)), per channel (self_shadow.glsl's
    hair_scattered_share).

    T is the share of a uniform world's light that reaches the point through the hair (world_transmittance
    with keep = 1 - a_f), rho the share of the rest that the strands scatter rather than absorb
    (preview_luts.scattering_albedo). The directions the hair blocks (1 - T of them) are not dark: the hair
    there sends on rho of the light it receives, and the hair around a point receives about what the point
    does (the neighbours' light taken as the point's own, as the multiple-bounce ambient occlusion of
    Jimenez et al. 2016 does for surfaces). So the light arriving, E = T L + (1 - T) rho E, is T L / (1 -
    rho (1 - T)): the direct light times 1 + this share. A fibre that absorbs nothing (rho = 1) then keeps
    a uniform world's light everywhere inside the hair, the white furnace; rho = 0 or T = 1 adds nothing.
    Dense hair passes light on by scattering it many times: under interior.exr the path tracer's bounces
    nearly doubled the dense generated hair's red (docs/preview.md)."""
    transmittance = np.clip(np.asarray(transmittance, np.float64), 0.0, 1.0)
    albedo = np.clip(np.asarray(albedo, np.float64), 0.0, 1.0)
    blocked = 1.0 - transmittance
    return blocked * albedo / np.maximum(1.0 - albedo * blocked, 1e-4)


def transmittance(points, light_vectors, volume, strength):
    """T = exp(-strength x extinction x d) per point: the share of each light that reaches points
    [N, 3] through the hair. `light_vectors` [N, 4] or [4], in the volume's (object) space:
    (direction towards a sun, 0) or (position of a point light, 1); the path to a point light ends
    at the light. Returns float64 [N] in (0, 1], 1 where the path misses the volume."""
    points = np.atleast_2d(np.asarray(points, dtype=np.float64))
    light_vectors = np.asarray(light_vectors, dtype=np.float64)
    if points.ndim != 2 or points.shape[1] != 3:
        raise ValueError(f"transmittance: points must have shape [N, 3], got {list(points.shape)}")
    if light_vectors.shape not in ((4,), (len(points), 4)):
        raise ValueError(f"transmittance: light_vectors must have shape [4] or [{len(points)}, 4], "
                         f"got {list(light_vectors.shape)}")
    light_vectors = np.broadcast_to(light_vectors, (len(points), 4))
    if not np.isfinite(strength) or strength < 0.0:
        raise ValueError(f"transmittance: strength must be finite and >= 0, got {strength}")
    is_point = light_vectors[:, 3] > 0.0
    # Along p + t to_light: t in [0, 1] reaches a point light; a sun is at t -> infinity.
    to_light = np.where(is_point[:, None], light_vectors[:, :3] - points, light_vectors[:, :3])
    t_max = np.where(is_point, 1.0, np.inf)
    # The ray in the ellipsoid's unit-sphere coordinates: |q + t v|^2 = 1.
    q = (points - volume.centre) / volume.semi_axes
    v = to_light / volume.semi_axes
    a = np.einsum("ij,ij->i", v, v)
    b = np.einsum("ij,ij->i", q, v)
    c = np.einsum("ij,ij->i", q, q) - 1.0
    discriminant = b * b - a * c
    crosses = (a > 1e-30) & (discriminant > 0.0)
    root = np.sqrt(np.where(crosses, discriminant, 0.0))
    safe_a = np.where(crosses, a, 1.0)
    t_enter = np.maximum((-b - root) / safe_a, 0.0)
    t_exit = np.minimum((-b + root) / safe_a, t_max)
    depth = np.where(crosses, np.maximum(t_exit - t_enter, 0.0), 0.0) * np.linalg.norm(to_light, axis=1)
    return np.exp(-strength * volume.extinction * depth)
