"""The viewport's GLSL aggregated BCSDF agrees with the C++ evaluation, and its self-shadowing term
with the Python reference (Blender under Xvfb, see scripts/run_ui_tests.sh).

Draws one full-screen pass into a float offscreen buffer where every pixel evaluates
shaders/aggregated_bcsdf.glsl for its own (wi, wo, n, rho), read from data textures; reads the pixels
back and compares them with hairlod.bcsdf.evaluate("aggregated", ..., aggregated_fibre="material") for the
same inputs (the aggregated BCSDF on the material's own fibre, as the preview shades).
Configurations: random directions over the sphere plus grazing ones (|theta| up to 1.55), 8 hair
counts n from 1 to n_max (on and between table nodes) times 4 densities from 0.05 to 1, for a light
and a dark hair. Tolerance: the tables'
interpolation error, which `python3 -m hairlod bench bcsdf` reports (about 2% at the default
resolution), so |S_glsl - S_cpp| <= 0.05 S_cpp + 0.01 max(S_cpp) per channel. The strands' build of
the same file (HAIRLOD_SINGLE_HAIR) reads the general build's values at n = 1, rho = 1 towards the back
(1e-5); towards the front it leaves out A_1+ (a strand has no hairs of its own behind it), so that a
strand with no hair behind it is the material's Chiang fibre in the far field (C++ "chiang", the
tolerance above).

The deep opacity maps' optical depth between layers (shaders/opacity_map.glsl, layered_optical_depth)
against hairlod.opacity_map.optical_depth, on and between the layer boundaries (1e-5).

The world's occlusion by the hair on a grid: shaders/world_occlusion.glsl's depths (a 3D texture read
with linear filtering) against hairlod.world_occlusion's float64 lookup, at points in, around and outside
a hollow shell of strands, moved and stretched from rest (1 % of the largest depth; about 1e-5 on llvmpipe).

The world's light the hair around a point scatters on to it: self_shadow.glsl's hair_scattered_share
against hairlod.self_shadow.scattered_share (1e-5 relative).

Self-shadowing: shaders/self_shadow.glsl against hairlod.self_shadow.transmittance (the same formula
in float64) for points in and around a flattened ellipsoid lit by suns and point lights, inside and
outside it; the world's light through it, over all 14 directions and split by the camera's side
(hair_world_transmittance against self_shadow.world_transmittance_by_side, 1e-4). The GLSL runs in float32, whose rounding in the ray-ellipsoid chord grows as the ray
grazes the surface: |T_glsl - T_ref| <= 1e-4 (we measure about 4e-6 on llvmpipe).
"""

import dataclasses
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import harness  # noqa: E402  (tests/ui/harness.py)
from harness import check  # noqa: E402

SIZE = 64  # pixels per side: 4096 configurations per hair
# 1 - a_f per direction of self_shadow.WORLD_DIRECTIONS and channel for the world's transmittance (brown
# hair scatters red forwards most; a_f changes with each direction's inclination to the strand).
WORLD_KEEP = tuple((0.35 + 0.02 * k, 0.6 - 0.01 * k, 0.9 - 0.03 * k) for k in range(14))


def directions(rng, count, max_theta=1.55):
    theta = rng.uniform(-max_theta, max_theta, count)
    theta[: count // 8] = rng.choice([-1.55, -1.45, 1.45, 1.55], count // 8)  # grazing
    phi = rng.uniform(-np.pi, np.pi, count)
    return np.stack([np.sin(theta), np.cos(theta) * np.cos(phi), np.cos(theta) * np.sin(phi)], axis=1)


def data_texture(xyz, w):
    """A SIZE x SIZE RGBA32F texture holding (xyz, w) per pixel."""
    import gpu

    rows = np.concatenate([xyz, w[:, None]], axis=1).astype(np.float32).reshape(SIZE, SIZE, 4)
    return gpu.types.GPUTexture((SIZE, SIZE), format='RGBA32F',
                                data=gpu.types.Buffer('FLOAT', SIZE * SIZE * 4, rows.ravel()))


def draw_full_screen(shader, bind):
    """Draws one full-screen triangle into a SIZE x SIZE float offscreen after bind(shader); returns
    the pixels' RGB [SIZE * SIZE, 3]."""
    import gpu
    from gpu_extras.batch import batch_for_shader

    quad = batch_for_shader(shader, 'TRIS', {"position": [(-1, -1), (3, -1), (-1, 3)]})
    offscreen = gpu.types.GPUOffScreen(SIZE, SIZE, format='RGBA32F')
    with offscreen.bind():
        framebuffer = gpu.state.active_framebuffer_get()
        framebuffer.clear(color=(0.0, 0.0, 0.0, 0.0))
        shader.bind()
        bind(shader)
        quad.draw(shader)
        pixels = np.asarray(framebuffer.read_color(0, 0, SIZE, SIZE, 4, 0, 'FLOAT').to_list(), np.float32)
    offscreen.free()
    return pixels.reshape(SIZE * SIZE, 4)[:, :3]


def full_screen_shader_info():
    import gpu

    info = gpu.types.GPUShaderCreateInfo()
    info.vertex_in(0, 'VEC2', "position")
    info.fragment_out(0, 'VEC4', "fragColor")
    info.vertex_source("void main() { gl_Position = vec4(position, 0.0, 1.0); }")
    return info


def evaluate_on_gpu(tables, wi, wo, hair_count, density, single_hair=False, behind=None, call=None):
    """aggregated_bcsdf per pixel; with `single_hair`, as the strands' shader builds it
    (HAIRLOD_SINGLE_HAIR: n = 1 and rho = 1 whatever hair_count and density say); with `behind`,
    aggregated_bcsdf_behind with that share of hair behind; `call` another vec3 expression of
    aggregated_bcsdf.glsl in i (wi, hair count) and o (wo, density)."""
    import gpu

    from hairlod.blender.preview import bcsdf_textures
    from hairlod.blender.preview.shaders import glsl_source

    info = full_screen_shader_info()
    info.sampler(3, 'FLOAT_2D', "incoming")
    info.sampler(4, 'FLOAT_2D', "outgoing")
    bcsdf_textures.declare(info)
    if call is None:
        call = ("aggregated_bcsdf(normalize(i.xyz), normalize(o.xyz), vec3(1.0, 0.0, 0.0), i.w, o.w)" if behind is None else
                f"aggregated_bcsdf_behind(normalize(i.xyz), normalize(o.xyz), vec3(1.0, 0.0, 0.0), i.w, o.w, {float(behind)!r})")
    info.fragment_source(("#define HAIRLOD_SINGLE_HAIR\n" if single_hair else "") + glsl_source("aggregated_bcsdf.glsl") + """
void main()
{
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec4 i = texelFetch(incoming, pixel, 0);
  vec4 o = texelFetch(outgoing, pixel, 0);
  fragColor = vec4(%s, 1.0);
}
""" % call)
    shader = gpu.shader.create_from_info(info)
    textures = bcsdf_textures.BcsdfTextures(tables)
    # Kept referenced until drawn: a freed GPUTexture reads as zeros.
    incoming, outgoing = data_texture(wi, hair_count), data_texture(wo, density)

    def bind(program):
        textures.bind(program)
        program.uniform_sampler("incoming", incoming)
        program.uniform_sampler("outgoing", outgoing)

    return draw_full_screen(shader, bind)


def transmittance_on_gpu(points, light_vectors, volume, strength, sides=0):
    """self_shadow.glsl's hair_transmittance per pixel, the light vector turned into the path to the
    light as hair.frag.glsl does, and its hair_world_transmittance with the camera towards the light
    vector: (T, the world's red, its blue; with `sides` 1 the near side's green, 2 the far side's blue)."""
    import gpu

    from hairlod.blender.preview.shaders import glsl_source

    info = full_screen_shader_info()
    info.sampler(0, 'FLOAT_2D', "point_data")
    info.sampler(1, 'FLOAT_2D', "light_data")
    info.push_constant('VEC4', "centre_sigma")
    info.push_constant('VEC3', "semi_axes")
    info.push_constant('INT', "sides")
    keeps = ", ".join(f"vec3{keep}" for keep in WORLD_KEEP)
    info.fragment_source(glsl_source("self_shadow.glsl") + f"const vec3 WORLD_KEEP[14] = vec3[]({keeps});\n" + """
void main()
{
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec3 p = texelFetch(point_data, pixel, 0).xyz;
  vec4 light = texelFetch(light_data, pixel, 0);
  vec3 to_light = light.xyz - p * light.w;
  float t = hair_transmittance(p, to_light, light.w > 0.0 ? 1.0 : 1e30, centre_sigma.xyz, semi_axes, centre_sigma.w);
  float tau[14], facing[14];
  hair_world_depths(p, centre_sigma.xyz, semi_axes, centre_sigma.w, tau);
  for (int k = 0; k < 14; ++k) {
    facing[k] = dot(HAIR_WORLD_DIRECTIONS[k], normalize(light.xyz));
  }
  vec3 near, far;
  vec3 world = hair_world_transmittance(tau, WORLD_KEEP, facing, near, far);
  fragColor = vec4(t, world.x, sides == 0 ? world.z : (sides == 1 ? near.y : far.z), 1.0);
}
""")
    shader = gpu.shader.create_from_info(info)
    point_texture = data_texture(points, np.zeros(len(points)))
    light_texture = data_texture(light_vectors[:, :3], light_vectors[:, 3])

    def bind(program):
        program.uniform_sampler("point_data", point_texture)
        program.uniform_sampler("light_data", light_texture)
        program.uniform_float("centre_sigma", (*volume.centre, strength * volume.extinction))
        program.uniform_float("semi_axes", tuple(volume.semi_axes))
        program.uniform_int("sides", sides)

    values = draw_full_screen(shader, bind)
    return values[:, 0], values[:, [1, 2]]


def check_self_shadowing():
    from hairlod import self_shadow

    rng = np.random.default_rng(12)
    count = SIZE * SIZE
    volume = self_shadow.HairVolume(centre=np.array([0.3, -0.2, 1.0]), semi_axes=np.array([1.5, 1.0, 0.4]),
                                    extinction=2.5)
    # Points inside and up to half an axis outside; half the lights suns, half point lights within
    # 3 semi-axes of the centre (inside the hair too).
    points = volume.centre + rng.uniform(-1.5, 1.5, (count, 3)) * volume.semi_axes
    suns = rng.normal(size=(count, 3))
    suns /= np.linalg.norm(suns, axis=1, keepdims=True)
    lamps = volume.centre + rng.uniform(-3.0, 3.0, (count, 3)) * volume.semi_axes
    is_point = rng.uniform(size=count) < 0.5
    light_vectors = np.concatenate([np.where(is_point[:, None], lamps, suns), is_point[:, None]], axis=1)
    strength = 0.7
    shader_values, shader_world = transmittance_on_gpu(points, light_vectors, volume, strength)
    reference = self_shadow.transmittance(points, light_vectors, volume, strength)
    # The world's light per channel, each direction's T raised to keep = 1 - a_f before the average
    # (red and blue of WORLD_KEEP read back).
    world_reference = self_shadow.world_transmittance(points, volume, strength, keep=WORLD_KEEP)[:, [0, 2]]
    world_error = np.abs(shader_world - world_reference)
    print(f"self-shadowing of the world: max |T_glsl - T_ref| = {world_error.max():.2e}, T from "
          f"{world_reference.min():.3f} to {world_reference.max():.3f}")
    check((world_error <= 1e-4).all() and world_reference.min() < 0.5 < world_reference.max(),
          "self-shadowing of the world: GLSL agrees with the reference within 1e-4 (inside and outside the hair)")
    # Split by the camera's side (the camera towards each pixel's light vector): near side's green, far side's blue.
    facing = light_vectors[:, :3] @ self_shadow.WORLD_DIRECTIONS.T / np.linalg.norm(light_vectors[:, :3], axis=1, keepdims=True)
    _, near, far = self_shadow.world_transmittance_by_side(self_shadow.world_depths(points, volume, strength), WORLD_KEEP, facing)
    side_error = max(np.abs(transmittance_on_gpu(points, light_vectors, volume, strength, sides=1)[1][:, 1] - near[:, 1]).max(),
                     np.abs(transmittance_on_gpu(points, light_vectors, volume, strength, sides=2)[1][:, 1] - far[:, 2]).max())
    print(f"self-shadowing of the world by side: max |T_glsl - T_ref| = {side_error:.2e}, near minus far from "
          f"{(near - far).min():.3f} to {(near - far).max():.3f}")
    check(side_error <= 1e-4 and (near - far).min() < -0.05 and (near - far).max() > 0.05,
          "self-shadowing of the world by side: GLSL agrees with the reference within 1e-4, either side the darker")
    error = np.abs(shader_values - reference)
    shadowed = reference < 0.99
    print(f"self-shadowing: max |T_glsl - T_ref| = {error.max():.2e}, mean {error.mean():.2e} over {count} "
          f"configurations ({shadowed.mean():.0%} shadowed, min T {reference.min():.3f})")
    check(np.isfinite(shader_values).all(), "self-shadowing: the shader's values are finite")
    check(0.2 < shadowed.mean() < 0.9 and reference.min() < 0.05,
          "self-shadowing: the configurations cover lit, partly and deeply shadowed points")
    check((error <= 1e-4).all(), "self-shadowing: GLSL agrees with the reference within 1e-4")


def check_scattered_share():
    """self_shadow.glsl's hair_scattered_share against hairlod.self_shadow.scattered_share, over
    transmittances and albedos from 0 to 1 (the ends included) per channel (1e-5)."""
    import gpu

    from hairlod import self_shadow
    from hairlod.blender.preview.shaders import glsl_source

    rng = np.random.default_rng(15)
    count = SIZE * SIZE
    transmittance = rng.uniform(0.0, 1.0, (count, 3))
    albedo = rng.uniform(0.0, 1.0, (count, 3))
    transmittance[:64], albedo[64:128] = rng.choice([0.0, 1.0], (64, 3)), rng.choice([0.0, 1.0], (64, 3))
    info = full_screen_shader_info()
    info.sampler(0, 'FLOAT_2D', "transmittance_data")
    info.sampler(1, 'FLOAT_2D', "albedo_data")
    info.fragment_source(glsl_source("self_shadow.glsl") + """
void main()
{
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  fragColor = vec4(hair_scattered_share(texelFetch(transmittance_data, pixel, 0).rgb,
                                        texelFetch(albedo_data, pixel, 0).rgb), 1.0);
}
""")
    shader = gpu.shader.create_from_info(info)
    transmittance_texture = data_texture(transmittance, np.zeros(count))
    albedo_texture = data_texture(albedo, np.zeros(count))

    def bind(program):
        program.uniform_sampler("transmittance_data", transmittance_texture)
        program.uniform_sampler("albedo_data", albedo_texture)

    on_gpu = draw_full_screen(shader, bind)
    reference = self_shadow.scattered_share(transmittance, albedo)
    finite = reference < 1e3  # T = 0 with rho = 1: the cap (1e4), which float32 rounds differently
    error = (np.abs(on_gpu - reference) / np.maximum(reference, 1.0))[finite].max()
    print(f"scattered world light: max |share_glsl - share_ref| / max(share_ref, 1) = {error:.2e}, share up to "
          f"{reference[finite].max():.2f}")
    check(np.isfinite(on_gpu).all() and error <= 1e-5,
          "scattered world light: GLSL's share of the light the hair around scatters on agrees with the reference")


def world_grid_on_gpu(occlusion, strength, points):
    """world_occlusion.glsl's world_grid_depths per pixel, three directions a pass, and its
    self_shadow.glsl's hair_world_transmittance of those depths with WORLD_KEEP: [N, 17]."""
    import gpu

    from hairlod.blender.preview import world_occlusion_texture
    from hairlod.blender.preview.shaders import glsl_source

    info = full_screen_shader_info()
    info.sampler(0, 'FLOAT_2D', "point_data")
    info.sampler(2, 'FLOAT_3D', "world_depths")
    info.push_constant('VEC4', "lower_scale")
    info.push_constant('VEC3', "extent")
    info.push_constant('INT', "first")
    keeps = ", ".join(f"vec3{keep}" for keep in WORLD_KEEP)
    info.fragment_source(glsl_source("self_shadow.glsl", "world_occlusion.glsl") +
                         f"const vec3 WORLD_KEEP[14] = vec3[]({keeps});\n" + """
void main()
{
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  float tau[14];
  world_grid_depths(texelFetch(point_data, pixel, 0).xyz, lower_scale, extent, tau);
  float facing[14];
  for (int k = 0; k < 14; ++k) {
    facing[k] = 1.0;
  }
  vec3 near, far;
  vec3 values = hair_world_transmittance(tau, WORLD_KEEP, facing, near, far);
  for (int c = 0; c < 3 && first + c < 14; ++c) {
    values[c] = tau[first + c];
  }
  fragColor = vec4(values, 1.0);
}
""")
    shader = gpu.shader.create_from_info(info)
    point_texture = data_texture(points, np.zeros(len(points)))
    depths_texture = world_occlusion_texture.texture(occlusion)
    passes = []
    for first in (0, 3, 6, 9, 12, 14):
        def bind(program, first=first):
            program.uniform_sampler("point_data", point_texture)
            program.uniform_sampler("world_depths", depths_texture)
            program.uniform_float("lower_scale", (*occlusion.lower, strength * occlusion.depth_factor))
            program.uniform_float("extent", tuple(occlusion.extent))
            program.uniform_int("first", first)
        passes.append(draw_full_screen(shader, bind))
    return np.concatenate(passes[:-2] + [passes[-2][:, :2], passes[-1]], axis=1)


def check_world_occlusion():
    """The grid's depths in GLSL (a 3D texture, linear filtering) against world_occlusion's float64 lookup,
    at points in, around and outside a hollow shell of strands, moved and stretched from rest."""
    from hairlod import world_occlusion

    rng = np.random.default_rng(14)
    count = SIZE * SIZE
    # Radial strands of a shell from radius 0.5 to 1 about (0.2, -0.1, 1), flattened in z.
    directions_ = rng.normal(size=(3000, 3))
    directions_ /= np.linalg.norm(directions_, axis=1, keepdims=True)
    points = (directions_[:, None, :] * np.linspace(0.5, 1.0, 9)[None, :, None] * (1.0, 1.0, 0.6)).reshape(-1, 3)
    rest = world_occlusion.world_occlusion(points + (0.2, -0.1, 1.0), np.arange(0, len(points) + 1, 9),
                                           np.full(len(points), 0.002))
    box = (rest.lower, rest.lower + rest.extent)
    occlusion = world_occlusion.moved_occlusion(rest, box, (box[0] + (0.1, 0.0, -0.2), box[1] * (1.0, 1.2, 1.0) + (0.1, 0.0, -0.2)))
    probe = occlusion.lower + rng.uniform(-0.1, 1.1, (count, 3)) * occlusion.extent
    strength = 0.8
    on_gpu = world_grid_on_gpu(occlusion, strength, probe)
    reference = strength * world_occlusion.optical_depths(occlusion, probe)
    reference_light = world_occlusion.world_transmittance(probe, occlusion, strength, keep=WORLD_KEEP)
    # Linear filtering's weights are fixed-point on some GPUs (8 bits a texel): 1 % of the largest depth.
    tolerance = 1e-2 * reference.max()
    error = np.abs(on_gpu[:, :14] - reference).max()
    error_light = np.abs(on_gpu[:, 14:] - reference_light).max()
    print(f"world occlusion grid: max |tau_glsl - tau_ref| = {error:.2e}, tau up to {reference.max():.3f}; the world's "
          f"light through it max |T_glsl - T_ref| = {error_light:.2e}")
    check(np.isfinite(on_gpu).all() and reference.max() > 0.1 and reference.min() < 1e-3,
          "world occlusion grid: the probes reach empty and dense parts of the grid")
    check(error <= tolerance and error_light <= 1e-3,
          "world occlusion grid: GLSL's depths (within 1 % of the largest) and the world's light through them "
          "(within 1e-3) agree with the reference")


def check_layered_optical_depth():
    """opacity_map.glsl's layered_optical_depth (summed segment by segment, without branches) against
    hairlod.opacity_map.optical_depth (the same piecewise-linear tau, found by search, float64)."""
    import gpu

    from hairlod import opacity_map
    from hairlod.blender.preview import lod_preview, opacity_maps
    from hairlod.blender.preview.shaders import glsl_source

    rng = np.random.default_rng(13)
    count = SIZE * SIZE
    spacing = 0.37
    layers = np.cumsum(rng.exponential(2.0, (count, 4)), axis=1)  # cumulative: non-decreasing
    layers[: count // 16] = 0.0  # a texel no hair lies below
    knots = np.asarray(opacity_map.LAYER_STEPS) * spacing
    below = rng.uniform(-0.2 * knots[-1], 1.3 * knots[-1], count)
    below[: count // 4] = rng.choice(np.concatenate([[0.0], knots]), count // 4)  # on the knots
    info = full_screen_shader_info()
    info.typedef_source(lod_preview.FRAME_BLOCK)
    info.uniform_buf(0, "HairFrame", "frame")  # opacity_map.glsl's other functions read it; main does not
    opacity_maps.declare(info)
    info.sampler(0, 'FLOAT_2D', "layer_data")
    info.sampler(1, 'FLOAT_2D', "below_data")
    info.push_constant('FLOAT', "spacing")
    info.fragment_source(opacity_maps.glsl_constants() + glsl_source("opacity_map.glsl") + """
void main()
{
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec4 layers = texelFetch(layer_data, pixel, 0);
  float below = texelFetch(below_data, pixel, 0).w;
  fragColor = vec4(layered_optical_depth(layers, below, spacing), optical_depth_behind(layers, below, spacing), 0.0, 1.0);
}
""")
    shader = gpu.shader.create_from_info(info)
    layer_texture = data_texture(layers[:, :3], layers[:, 3])
    below_texture = data_texture(np.zeros((count, 3)), below)

    def bind(program):
        program.uniform_sampler("layer_data", layer_texture)
        program.uniform_sampler("below_data", below_texture)
        program.uniform_float("spacing", spacing)

    drawn = draw_full_screen(shader, bind)
    values = drawn[:, 0]
    reference = opacity_map.optical_depth(layers, below, spacing)
    error = np.abs(values - reference) / np.maximum(reference, 1.0)
    print(f"layered optical depth: max |tau_glsl - tau_ref| / max(tau_ref, 1) = {error.max():.2e} over {count} depths")
    check((error <= 1e-5).all(), "layered optical depth: GLSL agrees with hairlod.opacity_map.optical_depth within 1e-5")
    behind = opacity_map.optical_depth_behind(layers, below, spacing)
    error = np.abs(drawn[:, 1] - behind) / np.maximum(layers[:, 3], 1.0)
    print(f"optical depth behind: max |tau_glsl - tau_ref| / max(tau_total, 1) = {error.max():.2e}")
    check((error <= 1e-5).all(), "optical depth behind: GLSL agrees with hairlod.opacity_map.optical_depth_behind within 1e-5")


def srbf_world_on_gpu(tables, lights, tangents, wo):
    """srbf_world.glsl's srbf_world(wo, t) per pixel."""
    import gpu

    from hairlod.blender.preview import bcsdf_textures, world_srbf
    from hairlod.blender.preview.shaders import glsl_source

    info = full_screen_shader_info()
    info.typedef_source(world_srbf.WORLD_BLOCK)
    info.sampler(0, 'FLOAT_2D', "tangent_data")
    info.sampler(1, 'FLOAT_2D', "view_data")
    world_srbf.declare(info, slot=2)
    # srbf_world.glsl uses lut_row of aggregated_bcsdf.glsl, whose tables this pass never reads.
    bcsdf_textures.declare(info, first_slot=3)
    info.fragment_source(glsl_source("aggregated_bcsdf.glsl", "srbf_world.glsl") + """
void main()
{
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec3 t = normalize(texelFetch(tangent_data, pixel, 0).xyz);
  vec3 wo = normalize(texelFetch(view_data, pixel, 0).xyz);
  fragColor = vec4(srbf_world(wo, t), 1.0);
}
""")
    shader = gpu.shader.create_from_info(info)
    texture = world_srbf.response_texture(tables)
    block = world_srbf.world_block(lights)
    tangent_texture = data_texture(tangents, np.zeros(len(tangents)))
    view_texture = data_texture(wo, np.zeros(len(wo)))

    def bind(program):
        program.uniform_sampler("srbf_lut", texture)
        program.uniform_block("hair_world", block)
        program.uniform_sampler("tangent_data", tangent_texture)
        program.uniform_sampler("view_data", view_texture)

    return draw_full_screen(shader, bind)


def check_srbf_world():
    """The world as SRBF lights: srbf_world.glsl against hairlod.preview_luts.srbf_lookup (the same table
    read the same way in float64: the world's uniform part times the uniform row, each lobe's response
    at its angles in each pixel's fibre frame). A synthetic world (a uniform sky, a warm bright patch, a
    darker ground; 11% fit error, plus a uniform part) fitted by hairlod.world_lighting; 64 random
    tangents x 64 random views, a light and a dark hair. What the table holds, and how far its
    interpolation strays from the integral it tabulates, tests/python/test_world_lighting.py checks.
    Tolerance: float32 arithmetic (an angle on a node's edge can fall on either side of it),
    |L_glsl - L_ref| <= 5e-3 max(L_ref) everywhere and 2e-4 max(L_ref) on average (we measure 0.05-0.12%
    and under 0.01% on llvmpipe)."""
    from hairlod import preview_luts, world_lighting

    rng = np.random.default_rng(13)
    directions, solid_angles = world_lighting.blender_equirectangular_directions(32, 64)
    sky = 0.3 + 2.0 * np.exp(-2.0 * (1.0 - directions @ np.array([0.6, -0.3, 0.74])))[..., None] * [1.0, 0.8, 0.5]
    sky *= 0.2 + 0.8 / (1.0 + np.exp(-6.0 * directions[..., 2:3]))  # a darker ground, smoothly
    fit = world_lighting.fit_world(directions.reshape(-1, 3), solid_angles.reshape(-1), sky.reshape(-1, 3))
    # A uniform part too, so that the table's uniform-world row is read.
    lights = dataclasses.replace(fit, constant=np.array([0.2, 0.25, 0.3]))
    print(f"srbf world: fit of the synthetic world with {len(lights.directions)} lobes + a constant: "
          f"relative error {lights.relative_error:.3f}")
    check(lights.relative_error < 0.15 and lights.coefficients.max() > 0.1,
          "srbf world: the synthetic world fits within 15%")
    count = SIZE * SIZE
    tangents = rng.normal(size=(SIZE, 3))
    tangents /= np.linalg.norm(tangents, axis=1, keepdims=True)
    wo = directions_on_sphere = rng.normal(size=(count, 3))
    wo /= np.linalg.norm(directions_on_sphere, axis=1, keepdims=True)
    per_pixel_tangent = np.repeat(tangents, SIZE, axis=0)
    for name, sigma_a in (("light", (0.06, 0.1, 0.2)), ("dark", (1.2, 1.8, 3.0))):
        params = {"sigma_a": sigma_a, "beta_m": 0.3, "beta_n": 0.3}
        tables = preview_luts.srbf_tables(params, lights.lam)
        shader_values = srbf_world_on_gpu(tables, lights, per_pixel_tangent, wo)
        sin_o = np.einsum("ij,ij->i", wo, per_pixel_tangent)
        reference = lights.constant * preview_luts.srbf_lookup(tables, sin_o)
        view_across = wo - sin_o[:, None] * per_pixel_tangent
        for centre, colour in zip(lights.directions, lights.coefficients):
            sin_j = per_pixel_tangent @ centre
            lobe_across = centre[None, :] - sin_j[:, None] * per_pixel_tangent
            lengths = np.linalg.norm(view_across, axis=1) * np.linalg.norm(lobe_across, axis=1)
            cos_phi = np.where(lengths > 1e-12, np.einsum("ij,ij->i", view_across, lobe_across) / np.maximum(lengths, 1e-30), 1.0)
            reference += colour * preview_luts.srbf_lookup(tables, sin_o, sin_j, np.arccos(np.clip(cos_phi, -1.0, 1.0)))
        error = np.abs(shader_values - reference)
        peak = reference.max()
        print(f"srbf world, {name} hair: max |L_glsl - L_ref| = {error.max():.2e} = {error.max() / peak:.3%} of the "
              f"peak {peak:.3f}, mean {error.mean() / peak:.4%} of it, over {count} configurations")
        check(np.isfinite(shader_values).all() and (shader_values >= 0).all(),
              f"srbf world, {name} hair: the shader's values are finite and non-negative")
        check(bool((error <= 5e-3 * peak).all() and error.mean() <= 2e-4 * peak),
              f"srbf world, {name} hair: GLSL reads the table as preview_luts.srbf_lookup does, within 0.5% of the peak "
              f"(mean 0.02%)")


def run():
    from hairlod import bcsdf, preview_luts

    rng = np.random.default_rng(11)
    count = SIZE * SIZE
    for name, sigma_a in (("light", (0.06, 0.1, 0.2)), ("dark", (1.2, 1.8, 3.0))):
        params = {"sigma_a": sigma_a, "beta_m": 0.3, "beta_n": 0.3}
        max_hair_count = 40.0
        tables = preview_luts.shader_tables(params, max_hair_count=max_hair_count)
        wi, wo = directions(rng, count), directions(rng, count)
        # The C++ model takes one (n, rho) per call (and tabulates the fibre each time): 32 groups of
        # 128 direction pairs, n between table nodes included.
        counts, densities = (1.0, 1.7, 3.3, 6.1, 11.4, 19.9, 31.2, max_hair_count), (0.05, 0.37, 0.71, 1.0)
        groups = [(n, rho) for n in counts for rho in densities]
        hair_count = np.repeat([n for n, _ in groups], count // len(groups))
        density = np.repeat([rho for _, rho in groups], count // len(groups))
        shader_values = evaluate_on_gpu(tables, wi, wo, hair_count, density)
        reference = np.empty_like(shader_values)
        size = count // len(groups)
        for g, (n, rho) in enumerate(groups):
            rows = slice(g * size, (g + 1) * size)
            reference[rows] = bcsdf.evaluate("aggregated", params, wi[rows], wo[rows], hair_count=n, density=rho,
                                             aggregated_fibre="material")
        bad = ~np.isfinite(shader_values).all(axis=1) | (shader_values < 0).any(axis=1)
        for k in np.flatnonzero(bad)[:5]:
            print("bad:", wi[k], wo[k], hair_count[k], density[k], shader_values[k], reference[k])
        check(np.isfinite(shader_values).all() and (shader_values >= 0).all(),
              f"{name}: the shader's values are finite and non-negative")
        scale = reference.max()
        error = np.abs(shader_values - reference)
        relative = error / np.maximum(reference, 0.01 * scale)
        print(f"{name}: max |S_glsl - S_cpp| / max(S_cpp, 1% of peak) = {relative.max():.4f}, "
              f"mean {relative.mean():.5f} over {count} configurations")
        check((error <= 0.05 * reference + 0.01 * scale).all(), f"{name}: GLSL agrees with C++ within 5% + 1% of peak")

        # The strands' build (HAIRLOD_SINGLE_HAIR, the normalisations as uniforms) against the general one at
        # n = 1, rho = 1: the same function towards the back (float32 rounding apart, 1e-5 relative, well
        # under the tables' interpolation error). Towards the front it leaves out A_1+, the back-scatter of a
        # thick hair's own hairs behind the shaded one (Huang 2025 Eq. 10), of which a strand has none: with
        # no hair behind it, a strand is the material's Chiang fibre in the far field (C++ "chiang", 5 % + 1 %
        # of peak as above), and with hair behind it that fibre plus the hair behind's A_1 + A_3.
        ones = np.ones(count)
        cos_phi = np.einsum("ij,ij->i", wi[:, 1:], wo[:, 1:]) / (np.linalg.norm(wi[:, 1:], axis=1) *
                                                                 np.linalg.norm(wo[:, 1:], axis=1))
        # Away from cos(phi) = 0, where float32 rounding may put a configuration on either side.
        front, back = cos_phi > 1e-3, cos_phi < -1e-3
        single = evaluate_on_gpu(tables, wi, wo, ones, ones, single_hair=True)
        general = evaluate_on_gpu(tables, wi, wo, ones, ones)
        alone = evaluate_on_gpu(tables, wi, wo, ones, ones, single_hair=True, behind=0.0)
        fibre = bcsdf.evaluate("chiang", params, wi, wo)
        single_scale = fibre.max()
        gap = np.abs(single - general)[back] / np.maximum(np.abs(general[back]), 1e-3 * single_scale)
        print(f"{name}, single hair: max |S_single - S_general| / S_general towards the back = {gap.max():.2e}")
        check(np.isfinite(single).all() and (gap <= 1e-5).all(),
              f"{name}: the strands' single-hair shader reads the general shader's values at n = 1, rho = 1 towards the back")
        own = (general - single).sum(axis=1)[front]
        share = own / np.maximum(general.sum(axis=1)[front], 1e-30)
        print(f"{name}, single hair: A_1+ left out towards the front, up to {share.max():.1%} of the general value")
        check(bool(own.min() >= -1e-5 * single_scale and share.max() > 0.01),
              f"{name}: the strands' shader leaves out the general shader's A_1+ towards the front, and only that")
        check(np.isfinite(alone).all() and
              (np.abs(alone - fibre) <= 0.05 * fibre + 0.01 * single_scale).all(),
              f"{name}: a strand with no hair behind it is the material's fibre (C++ chiang, far field) within 5% + 1% of peak")
        check(bool(np.all(single >= alone - 1e-6 * single_scale)), f"{name}: the hair behind a strand adds light, never takes it")

        # The hair behind: all of it is aggregated_bcsdf; less of it takes only B^'s A_1 + A_3 away,
        # towards the front (phi < pi / 2) alone, never adding light, concave (B^ is capped by its budget).
        shares = {b: evaluate_on_gpu(tables, wi, wo, hair_count, density, behind=b) for b in (0.0, 0.5, 1.0)}
        tolerance = 1e-6 * scale
        check(bool(np.all(np.abs(shares[1.0] - shader_values) <= tolerance)), f"{name}: all hair behind is aggregated_bcsdf")
        check(bool(np.all(shares[0.0] <= shares[0.5] + tolerance) and np.all(shares[0.5] <= shares[1.0] + tolerance)),
              f"{name}: less hair behind never adds light")
        check(bool(np.all(shares[0.5] >= 0.5 * (shares[0.0] + shares[1.0]) - tolerance)), f"{name}: B^ concave in the hair behind")
        check(bool(np.all(np.abs(shares[0.0] - shares[1.0])[back] <= tolerance)),
              f"{name}: the hair behind changes nothing towards the back")
        taken = (shares[1.0] - shares[0.0]).sum(axis=1)[front]
        print(f"{name}: the hair behind's back-scatter, up to {taken.max() / scale:.2%} of the peak, in "
              f"{np.mean(taken > tolerance):.0%} of the front configurations")
        check(bool(taken.max() > 100.0 * tolerance), f"{name}: the hair behind's back-scatter is there towards the front")

        # Light that crossed m strands on its way (hair_shading.glsl, Zinke et al. 2008 Sec. 4.2's forward-scattered
        # light): a strand shades it with its lobes widened by m forward scatterings, as a thick hair of n = 1 + m
        # widens its own (Huang 2025 Eq. 9), without that hair's a_F^m, which the light's transmittance holds.
        # Towards the back, where neither adds B^, the strands' aggregated_bcsdf_crossed at m times a_F^m reads
        # the general aggregated_bcsdf at n = 1 + m, rho = 1 (float32 rounding apart).
        crossed = hair_count - 1.0
        widened = evaluate_on_gpu(tables, wi, wo, crossed, ones, single_hair=True,
                                  call="aggregated_bcsdf_crossed(normalize(i.xyz), normalize(o.xyz), vec3(1.0, 0.0, 0.0), "
                                       "1.0, 1.0, 1.0, i.w)")
        straight = evaluate_on_gpu(tables, wi, wo, crossed, ones, single_hair=True,
                                   call="aggregated_bcsdf_crossed(normalize(i.xyz), normalize(o.xyz), vec3(1.0, 0.0, 0.0), "
                                        "1.0, 1.0, 1.0, 0.0)")
        # theta_d as aggregated_bcsdf takes it (atan, not Mesa's coarser asin).
        inclination = "atan(clamp(normalize({0}).x, -1.0, 1.0), sqrt(max(1.0 - normalize({0}).x * normalize({0}).x, 0.0)))"
        theta_d = f"0.5 * ({inclination.format('o.xyz')} - {inclination.format('i.xyz')})"
        thick = evaluate_on_gpu(tables, wi, wo, hair_count, ones)
        kept = evaluate_on_gpu(tables, wi, wo, hair_count, ones,
                               call=f"forward_attenuation({theta_d}, i.w) + step(2.0, o.w) * aggregated_bcsdf("
                                    "normalize(i.xyz), normalize(o.xyz), vec3(1.0, 0.0, 0.0), i.w, o.w)")
        gap = np.abs(widened * kept - thick)[back] / np.maximum(np.abs(thick[back]), 1e-3 * scale)
        print(f"{name}, light that crossed strands: max |S_crossed a_F^m - S(n = 1 + m)| / S towards the back = {gap.max():.2e}")
        check(np.isfinite(widened).all() and (gap <= 1e-4).all(),
              f"{name}: a strand shades light that crossed m strands as a thick hair of n = 1 + m does, without its a_F^m")
        check(bool(np.all(np.abs(straight - single) <= 1e-6 * single_scale)),
              f"{name}: light that crossed no strand is shaded as aggregated_bcsdf_behind shades it")
        # The widening flattens the fibre's peaks across the directions that crossed most (m >= 10).
        many = crossed >= 10.0
        check(bool(widened[many].max() < 0.5 * straight[many].max()),
              f"{name}: light that crossed many strands arrives with its lobes widened (peak "
              f"{widened[many].max():.3g} against {straight[many].max():.3g})")


def check_forward_share():
    """aggregated_bcsdf.glsl's forward_share (a_f at a light's inclination to the strand: the suns' and each
    world direction's forward transmittance) against preview_luts.forward_share, grazing angles included."""
    from hairlod import preview_luts

    rng = np.random.default_rng(13)
    count = SIZE * SIZE
    tables = preview_luts.shader_tables({"sigma_a": (1.2, 1.8, 3.0), "beta_m": 0.3, "beta_n": 0.3})
    w = directions(rng, count)
    shader_values = evaluate_on_gpu(tables, w, w, np.ones(count), np.ones(count),
                                    # The BCSDF's term times step(2, density) = 0, which the compiler cannot drop,
                                    # keeps the uniforms BcsdfTextures binds in the program.
                                    call="forward_share(normalize(i.xyz), vec3(1.0, 0.0, 0.0)) + step(2.0, o.w) * aggregated_bcsdf("
                                         "normalize(i.xyz), normalize(o.xyz), vec3(1.0, 0.0, 0.0), i.w, o.w)")
    reference = preview_luts.forward_share(tables, w[:, 0])
    error = np.abs(shader_values - reference).max()
    print(f"forward share: max |a_f glsl - a_f ref| = {error:.2e}, a_f from {reference.min():.3f} to {reference.max():.3f}")
    # Mesa's asin is an approximation that errs by up to a few 1e-4 rad, most near |sin| = 1, where a_f also
    # changes fastest (2.6e-4 in a_f at 81 degrees); a node off by one would err by 1e-2.
    check(error <= 5e-4 and np.ptp(reference) > 0.05, "forward share: GLSL reads a_f at the light's inclination as "
          "the reference does, within 5e-4, and a_f changes with the inclination")


def steps():
    run()
    check_forward_share()
    check_self_shadowing()
    check_scattered_share()
    check_layered_optical_depth()
    check_world_occlusion()
    check_srbf_world()
    yield from ()


harness.run(steps, first_delay=0.5)
