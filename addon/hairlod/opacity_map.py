"""The geometry of the preview's deep opacity maps (no bpy): the light's projection, the layers and the
optical depth a shading point reads.

A deep opacity map (Yuksel and Keyser 2008, "Deep Opacity Maps"; the paper's real-time renderer
makes one for its self-shadowing, hair-lod-aggregated-bcsdf.txt Sec. 6, step 1 "Shadow pass") holds,
per pixel of the light's view, the depth z0 of the first hair the light meets and the optical depth
tau accumulated by the hairs up to depths z0 + s, z0 + 4 s, z0 + 16 s and z0 + 64 s (LAYER_STEPS, s the
layer spacing). The light reaching a point at depth z unscattered is exp(-tau(z - z0)), tau piecewise
linear between the layers, 0 at z0 and the last layer's beyond it; each strand crossed passes a_f of the
light on forwards, so the shader keeps a_f^tau of it per channel (Zinke et al. 2008's forward
transmittance T_f, a product over the strands crossed: they are counted here, not drawn at random). Each hair adds its coverage of the
pixel: a strand of radius r, drawn as a line one pixel wide, 2 r over the pixel's width; a thick
hair of N strands, whose strands spread over its ellipse (the aggregated model's assumption,
hair-lod-aggregated-bcsdf.txt Sec. 4), 4 r N sqrt(1 - x^2) / (pi w) at the offset x w across its
silhouette of half-width w, which integrates to the 2 r N of its strands across it.
shaders/opacity_map.glsl evaluates the same; tests/ui/test_opacity_map.py checks the maps against
these formulas.
"""

import numpy as np

__all__ = ["LAYER_STEPS", "MAX_SHADOWED_LIGHTS", "TILE", "LightProjection", "light_projection", "layer_spacing",
           "optical_depth", "shadow_level", "strand_coverage", "thick_hair_coverage"]

# Layer boundaries below the first hair, in units of the spacing: dense near the lit side, where the
# light falls fastest, out to the hair's radius. Hair lies in a shell (a head of hair, a mohawk) far
# thinner than its bounding sphere, and most of the light falls within it: with boundaries at 1/8, 1/4,
# 1/2 and 1 radius a shell's tau was interpolated linearly over a first layer deeper than the shell, and
# the strands the camera sees in it were lit too brightly. Measured with strands drawn by coverage
# (scripts/bench_preview_fidelity.py, generated 20k at mid, preview / path-traced per channel):
# 1.06 / 1.14 / 1.15 with (1, 2, 4, 8) over one radius, 1.03 / 1.10 / 1.09 with them over a quarter
# radius (whose slab test, tests/ui/test_opacity_map.py, then lost its shadowed bottom beyond the last
# layer), 1.04 / 1.11 / 1.10 with these over one radius (and the edge texels of opacity_map.glsl);
# Ratboy 0.98 / 0.97 / 0.95 and 0.98 / 0.96 / 0.95 with the first two, 0.98 / 0.95 / 0.91 now.
LAYER_STEPS = (1.0, 4.0, 16.0, 64.0)
# Lights with a map of their own (the first ones of the scene's); the others fall back to the
# hair-volume ellipsoid of hairlod.self_shadow.
MAX_SHADOWED_LIGHTS = 4
TILE = 512  # pixels on a side of each light's map
# The maps are drawn from the finest level with at most this many segments (the coarser levels hold
# the same strands' optical depth spread over their ellipses). They are drawn again on every frame of
# an animation, about 1.7 us a segment on llvmpipe: with 1 << 17, 100k strands drew theirs from a
# thick level of 108k segments in 200 ms a frame, with 1 << 15 from one of 20k in 55-63 ms, and the
# preview's colour against the path tracer moved by at most 0.025 in a channel on both hairs of
# scripts/bench_preview_fidelity.py (docs/animated-hair.md).
SHADOW_SEGMENTS = 1 << 15
# Optical depth of one pixel is capped (a strand wider than the line drawn for it): exp(-4) = 2 %.
MAX_PIXEL_DEPTH = 4.0


class LightProjection:
    """The light's view of the hair's bounding sphere: `view_projection` (4 x 4, clip = M p, world
    space), `pixel_size` (world units per pixel; per unit of distance from a point light) and
    `perspective` (a point light)."""

    def __init__(self, view_projection, pixel_size, perspective):
        self.view_projection = view_projection
        self.pixel_size = pixel_size
        self.perspective = perspective

    def pixel_at(self, depth):
        """World units per pixel at `depth` from the light."""
        return self.pixel_size * depth if self.perspective else self.pixel_size


def _look_basis(forward):
    """Rows x, y, z of a right-handed view basis looking along `forward` (z = -forward)."""
    forward = forward / np.linalg.norm(forward)
    up = np.array([0.0, 0.0, 1.0]) if abs(forward[2]) < 0.9 else np.array([0.0, 1.0, 0.0])
    x = np.cross(forward, up)
    x /= np.linalg.norm(x)
    return np.stack([x, np.cross(x, forward), -forward])


def light_projection(light_vector, centre, radius, tile=TILE):
    """The LightProjection of a light (light_vector: (unit direction towards a sun, 0) or (position
    of a point light, 1), world space) onto a sphere (centre, radius) holding the hair, or None when
    a point light lies inside the sphere (no single view holds the hair)."""
    light_vector = np.asarray(light_vector, np.float64)
    centre = np.asarray(centre, np.float64)
    radius = float(radius)
    if not radius > 0.0:
        raise ValueError(f"opacity map: the hair's bounding radius must be positive, got {radius}")
    view = np.eye(4)
    if light_vector[3] == 0.0:
        # A sun: orthographic, x and y over the sphere's diameter, depth from its near to far side.
        basis = _look_basis(-light_vector[:3])
        view[:3, :3] = basis
        view[:3, 3] = -basis @ centre
        projection = np.diag([1.0 / radius, 1.0 / radius, -1.0 / radius, 1.0])
        return LightProjection(projection @ view, 2.0 * radius / tile, False)
    position = light_vector[:3]
    distance = float(np.linalg.norm(centre - position))
    if distance <= radius * 1.0001:
        return None
    basis = _look_basis(centre - position)
    view[:3, :3] = basis
    view[:3, 3] = -basis @ position
    near, far = distance - radius, distance + radius
    tan_half = radius / np.sqrt(distance * distance - radius * radius)
    projection = np.zeros((4, 4))
    projection[0, 0] = projection[1, 1] = 1.0 / tan_half
    projection[2, 2] = -(far + near) / (far - near)
    projection[2, 3] = -2.0 * far * near / (far - near)
    projection[3, 2] = -1.0
    return LightProjection(projection @ view, 2.0 * tan_half / tile, True)


def layer_spacing(radius):
    """The spacing s of the layers for hair of bounding radius `radius`: the last layer at
    z0 + LAYER_STEPS[-1] s reaches the sphere's radius below the first hair."""
    return float(radius) / LAYER_STEPS[-1]


def optical_depth(layers, below, spacing):
    """tau at `below` (depth under the first hair, array) from the cumulative layers [..., 4]:
    piecewise linear through (0, 0) and (LAYER_STEPS s, layers), constant beyond the last."""
    layers = np.asarray(layers, np.float64)
    knots = np.concatenate([[0.0], np.asarray(LAYER_STEPS) * spacing])
    below = np.asarray(below, np.float64)
    shape = np.broadcast_shapes(layers.shape[:-1], below.shape)
    layers = np.broadcast_to(layers, shape + layers.shape[-1:])
    values = np.concatenate([np.zeros(shape + (1,)), layers], axis=-1)
    below = np.clip(np.broadcast_to(below, shape), 0.0, knots[-1])
    segment = np.clip(np.searchsorted(knots, below, side="right") - 1, 0, len(knots) - 2)
    t = (below - knots[segment]) / (knots[segment + 1] - knots[segment])
    lower = np.take_along_axis(values, segment[..., None], axis=-1)[..., 0]
    upper = np.take_along_axis(values, segment[..., None] + 1, axis=-1)[..., 0]
    return lower + t * (upper - lower)


def optical_depth_behind(layers, below, spacing):
    """tau of the hair deeper than `below` along the light: the last layer's less optical_depth at
    `below`, at least 0 (all of it above the first hair, none past the last layer)."""
    layers = np.asarray(layers, np.float64)
    return np.maximum(layers[..., -1] - optical_depth(layers, below, spacing), 0.0)


def strand_coverage(radius, pixel):
    """Optical depth a strand of `radius` adds to the pixel (world size `pixel`) its line crosses."""
    return np.minimum(2.0 * np.asarray(radius, np.float64) / pixel, MAX_PIXEL_DEPTH)


def thick_hair_coverage(radius, strands, half_width, across):
    """Optical depth a thick hair of `strands` strands of `radius` adds at offset `across` (in [-1,
    1], of its silhouette's half-width `half_width`) from its centre line."""
    across = np.clip(np.asarray(across, np.float64), -1.0, 1.0)
    return np.minimum(4.0 * radius * strands * np.sqrt(1.0 - across * across) / (np.pi * half_width), MAX_PIXEL_DEPTH)


def shadow_level(segments_per_level, budget=None):
    """The level the maps are drawn from: the finest (highest index; the strands are the last) with
    at most `budget` (default SHADOW_SEGMENTS) segments when all the hair is drawn at it, else the
    coarsest."""
    segments = np.asarray(segments_per_level, np.int64)
    budget = SHADOW_SEGMENTS if budget is None else budget
    within = np.flatnonzero(segments <= budget)
    return int(within[-1]) if within.size else 0
