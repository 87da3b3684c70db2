"""The scene's world as SRBF lights for the LoD preview (hairlod.world_lighting fits them; this reads
the world from Blender and uploads the lobes and the response table of shaders/srbf_world.glsl).

Worlds read: no node tree (world.color), or a Background node feeding the active World Output whose
Color is unlinked (colour x strength) or linked straight to an Environment Texture node with an
equirectangular image and an unlinked Vector (image x strength). Anything else (Sky Texture, mapping
nodes, mixes) is reported by ``world_lights`` and the preview keeps the ambient term.
"""

import gpu
import numpy as np

from ... import world_lighting
from ..versions import uses_nodes

MAX_LOBES = world_lighting.DEFAULT_LOBE_COUNT
# std140 layout of the world uniform block; world_block() fills it in this order. No member may be
# named `constant`, `device`, `thread`, `threadgroup` or `static`: Blender 5's shader sources define
# them away (Metal's address spaces), and a struct member of that name no longer compiles.
WORLD_BLOCK = f"""
struct HairWorld {{
  vec4 uniform_part;
  vec4 counts;
  vec4 lobe_directions[{MAX_LOBES}];
  vec4 lobe_colours[{MAX_LOBES}];
}};
"""


def declare(info, slot=3):
    """Declares what srbf_world.glsl needs on a GPUShaderCreateInfo whose typedef_source includes
    WORLD_BLOCK: the response table and the HairWorld block (uniform buffer 1)."""
    info.sampler(slot, 'FLOAT_2D', "srbf_lut")
    info.uniform_buf(1, "HairWorld", "hair_world")


def lit_lobes(lights):
    """Per SRBF lobe of `lights`: whether it carries light (a coefficient not 0 in some channel)."""
    return np.any(np.asarray(lights.coefficients) != 0.0, axis=-1)


def world_block_data(lights):
    """The HairWorld block's floats for `lights` (hairlod.world_lighting.WorldLights), or for the
    ambient path (uniform_part.w = 0) when `lights` is None. Only the lobes that carry light go in: every
    fragment loops over those it is given, and a uniform world (the default one) fits lobes of
    coefficient 0, 16 of them, which took a third of a near view's redraw on llvmpipe for nothing. A lobe's
    colour's w is the mean of its G over the sphere (world_lighting.srbf_mean): its light spread over every
    direction, which the hair around a point scatters on to it (hair_shading.glsl)."""
    data = np.zeros(8 + 8 * MAX_LOBES, np.float32)
    if lights is not None:
        if len(lights.directions) > MAX_LOBES:
            raise ValueError(f"at most {MAX_LOBES} world lobes, got {len(lights.directions)}")
        lit = lit_lobes(lights)
        count = int(lit.sum())
        data[0:4] = (*lights.constant, 1.0)
        data[4] = count
        directions = data[8:8 + 4 * MAX_LOBES].reshape(MAX_LOBES, 4)
        colours = data[8 + 4 * MAX_LOBES:].reshape(MAX_LOBES, 4)
        directions[:count, :3] = np.asarray(lights.directions)[lit]
        colours[:count, :3] = np.asarray(lights.coefficients)[lit]
        colours[:count, 3] = world_lighting.srbf_mean(lights.lam)
    return data


def world_block(lights):
    """world_block_data(lights) as the GPUUniformBuf the shader reads."""
    data = world_block_data(lights)
    return gpu.types.GPUUniformBuf(gpu.types.Buffer('FLOAT', data.size, data))


def response_texture(tables):
    """The GPUTexture of a hairlod.preview_luts.SrbfTables (rows as in its docstring)."""
    from .bcsdf_textures import rgba_texture

    return rgba_texture(tables.response)


def empty_texture():
    """What srbf_lut reads on the ambient path, where the shader never samples it (a sampler must
    still be bound)."""
    return gpu.types.GPUTexture((2, 2), format='RGBA32F', data=gpu.types.Buffer('FLOAT', 16, [0.0] * 16))


def _background_node(world):
    tree = world.node_tree
    outputs = [node for node in tree.nodes if node.type == 'OUTPUT_WORLD']
    output = next((node for node in outputs if node.is_active_output), outputs[0] if outputs else None)
    if output is None or not output.inputs["Surface"].is_linked:
        return None, "the world has no World Output with a Surface"
    node = output.inputs["Surface"].links[0].from_node
    if node.type != 'BACKGROUND':
        return None, f"the world's Surface is a {node.bl_label} node, not a Background"
    return node, None


def world_key(world):
    """A cheap key that changes when what world_lights reads changes (checked every redraw)."""
    if world is None:
        return None
    if not uses_nodes(world):
        return (world.name, tuple(world.color))
    node, _ = _background_node(world)
    if node is None:
        return (world.name, "unsupported")
    colour, strength = node.inputs["Color"], node.inputs["Strength"]
    if not colour.is_linked:
        return (world.name, tuple(colour.default_value), strength.default_value)
    source = colour.links[0].from_node
    image = getattr(source, "image", None)
    return (world.name, source.name, strength.default_value, image.name if image else None,
            image.is_dirty if image else None, tuple(image.size) if image else None)


def world_lights(world, count=MAX_LOBES):
    """(WorldLights, None) for a world this module reads, else (None, the reason)."""
    if world is None:
        return None, "the scene has no world"
    if not uses_nodes(world):
        return world_lighting.uniform_world(world.color, count), None
    node, reason = _background_node(world)
    if node is None:
        return None, reason
    colour, strength = node.inputs["Color"], float(node.inputs["Strength"].default_value)
    if node.inputs["Strength"].is_linked:
        return None, "the Background's Strength is linked"
    if not colour.is_linked:
        return world_lighting.uniform_world(np.maximum(np.array(colour.default_value[:3]) * strength, 0.0), count), None
    source = colour.links[0].from_node
    if source.type != 'TEX_ENVIRONMENT':
        return None, f"the Background's Color comes from a {source.bl_label} node"
    if source.projection != 'EQUIRECTANGULAR' or source.inputs["Vector"].is_linked:
        return None, "the Environment Texture is not a plain equirectangular map"
    image = source.image
    if image is None or image.size[0] < 1 or image.size[1] < 1:
        return None, "the Environment Texture has no image"
    return world_lighting.blender_equirectangular_world(np.maximum(image_radiance(image) * strength, 0.0), count), None


def image_radiance(image):
    """The radiance of a bpy image, float64 [H, W, 3] in Blender's pixel layout (rows bottom-up), texels
    below 0 clamped to 0: real images hold some (compression; -0.003 in courtyard.exr), which neither the
    fit nor the path tracer takes."""
    width, height = image.size
    pixels = np.empty(width * height * 4, np.float32)
    image.pixels.foreach_get(pixels)
    rgb = pixels.reshape(height, width, 4)[..., :3].astype(np.float64)
    if not image.is_float and image.colorspace_settings.name == 'sRGB':
        # Byte images read back sRGB-encoded; the fit wants radiance.
        rgb = np.where(rgb <= 0.04045, rgb / 12.92, ((rgb + 0.055) / 1.055) ** 2.4)
    return np.maximum(rgb, 0.0)
