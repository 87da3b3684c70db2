"""GPU textures of the aggregated BCSDF's tables (hairlod.preview_luts) and the uniforms that go with
them, for shaders that include shaders/aggregated_bcsdf.glsl."""

import gpu
import numpy as np

from ...preview_luts import scattering_albedo

MATERIAL_SLOT = 13  # sampler slot of "material_lut" (the shading takes 0-9, the hair layer 10-11, the world's grid 12)


def rgba_texture(rows):
    """An RGBA32F GPUTexture of float rows [height, width, 4]."""
    height, width = rows.shape[:2]
    data = gpu.types.Buffer('FLOAT', width * height * 4, np.ascontiguousarray(rows, dtype=np.float32).ravel())
    return gpu.types.GPUTexture((width, height), format='RGBA32F', data=data)


def deon_log_normalisation(variance):
    """deon_log_normalisation of aggregated_bcsdf.glsl: the log of 2 v sinh(1 / v), in float64."""
    v = float(variance)
    return float(np.log(v) + 1.0 / v + np.log(max(-np.expm1(-2.0 / v), 1e-30)))


class BcsdfTextures:
    """Uploads ShaderTables once; bind() sets the samplers and constants on a bound shader."""

    def __init__(self, tables):
        self.tables = tables
        self.fiber = rgba_texture(tables.fiber)
        self.dual = rgba_texture(tables.dual)
        self.aggregated = rgba_texture(tables.aggregated)
        self.material = rgba_texture(tables.material)
        # sin 2s and cos 2s of the R and TT lobes' shifts s, which every fragment would take again.
        r_shift, tt_shift = tables.lobe_shapes[0], tables.lobe_shapes[2]
        self.lobe_tilts = (float(np.sin(2.0 * r_shift)), float(np.cos(2.0 * r_shift)),
                           float(np.sin(2.0 * tt_shift)), float(np.cos(2.0 * tt_shift)))
        # The table's constants, then the R and TT lobes' log normalisations at their own variances:
        # a strand's (n = 1), which its fragments would otherwise take again (aggregated_bcsdf.glsl).
        self.lut_constants = (*(float(c) for c in tables.lut_constants),
                              deon_log_normalisation(tables.lobe_shapes[1]), deon_log_normalisation(tables.lobe_shapes[3]))
        # The material's TRT lobe as lobe_tilts and lut_constants hold R and TT: sin 2s, cos 2s, its
        # variance and that variance's log normalisation (TRRT+ takes it unshifted).
        trt_shift, trt_variance = tables.material_lobes
        self.trt_lobe = (float(np.sin(2.0 * trt_shift)), float(np.cos(2.0 * trt_shift)), float(trt_variance),
                         deon_log_normalisation(trt_variance))
        # What the hair around a point scatters of the world's light (the HairFrame's scattering).
        self.scattering_albedo = tuple(float(c) for c in scattering_albedo(tables))

    def bind(self, shader):
        shader.uniform_sampler("fiber_lut", self.fiber)
        shader.uniform_sampler("dual_lut", self.dual)
        shader.uniform_sampler("aggregated_lut", self.aggregated)
        shader.uniform_sampler("material_lut", self.material)
        shader.uniform_float("trt_lobe", self.trt_lobe)
        shader.uniform_float("lobe_shapes", self.tables.lobe_shapes)
        shader.uniform_float("lobe_tilts", self.lobe_tilts)
        shader.uniform_float("lut_constants", self.lut_constants)


def declare(info, first_slot=0):
    """Declares the samplers and constants aggregated_bcsdf.glsl needs on a GPUShaderCreateInfo."""
    for slot, name in enumerate(("fiber_lut", "dual_lut", "aggregated_lut"), start=first_slot):
        info.sampler(slot, 'FLOAT_2D', name)
    info.sampler(MATERIAL_SLOT, 'FLOAT_2D', "material_lut")
    info.push_constant('VEC4', "trt_lobe")
    info.push_constant('VEC4', "lobe_shapes")
    info.push_constant('VEC4', "lobe_tilts")
    info.push_constant('VEC4', "lut_constants")
