"""Real-time LoD preview of hair in the 3D viewport (hair-lod-aggregated-bcsdf.txt Sec. 5.2).

For every object with an LoD asset attached (``attach``), a POST_VIEW draw handler selects levels for
each viewport's camera with the C++ selection (the initial selection, then Huang 2025 Eq. 16 from the previous
levels run until stable, kept per view: a smooth camera move changes a level by one between frames, a
jump gets its levels on its first frame) and draws camera-facing strips for the selected thick hairs and lines for the
selected strands. Vertex and index buffers are built once per asset: each level is cut into blocks
of whole L0 clusters whose index buffers hold all their segments (preview_buffers). A redraw uploads
the selection (level per L0 cluster and segment) as a small texture; the fragment shader drops
segments selected at another level, and a block is drawn only when one of its clusters has a segment
at that level. A level with few selected segments (EXACT_SEGMENTS) is drawn from those segments
alone instead (the strands' from an index list, a thick level's fetched by the shader from textures,
pulled_strips, with no index list to make when they change); so is a thick level
whose drawn blocks would mostly be dropped (preview_buffers.blocks_wasteful): a thick hair not
selected is wider than the strands selected in its place, and the GPU rasterises it before the test
drops it.

The vertex buffers hold the rest pose. When the hair moves (playback, scrubbing, an edit of what
deforms it), the frame-change and depsgraph handlers read the evaluated guide curves; the next draw
skins to them with FrameSkinning (one quadratic map per L0 cluster and control point, Sec. 5.1 step 4),
uploads the maps as a texture that the vertex shaders apply (shaders/skinning.glsl) and gives every
view's selection the moved geometry: per frame O(clusters x n_c) work, no vertex buffer rebuilt.
Hair attached to a mesh (Curves.surface, moved by Deform Curves on Surface) is followed more closely:
each strand turns rigidly with its root triangle's frame, as Blender moves it (blender/surface.py,
hairlod.surface_attachment), one transform per strand uploaded as a texture, wherever the guides read
from the evaluated hair confirm it (a sheared scalp turns neighbouring triangles differently, which
no smooth skinning from guides reproduces). The thick hairs follow by the maps.
"""

import itertools
import time

import bpy
import gpu
from bpy.app.handlers import persistent
import numpy as np
from mathutils import Vector

from ... import depth_range, lod, opacity_map, preview_buffers, self_shadow, world_occlusion
from .shaders import glsl_source
from ..principled_hair import material_params, object_hair_params
from . import hair_layer, opacity_maps, pulled_strips, view_transform, world_occlusion_texture, world_srbf
from .strand_batch import attribute_buffer

# Level colours of the "Levels" overlay: coarsest first; the strands (finest level) are the last.
LEVEL_COLOURS = ((0.90, 0.25, 0.20), (0.95, 0.60, 0.15), (0.90, 0.85, 0.20), (0.35, 0.80, 0.30),
                 (0.20, 0.70, 0.85), (0.35, 0.40, 0.95), (0.75, 0.40, 0.90), (0.85, 0.85, 0.85))

_previews = {}     # object name -> LodPreview
_handle = None     # the draw handler
_shaders = {}      # ("thick" / "strand", "shade" / "depth" / "opacity", test_level, pulled) or ("strand shading",) -> GPUShader, built on first draw
_view_transforms = view_transform.ViewTransforms()  # the scenes' colour management tables
# Custom property of an object whose drawing the preview replaces: its own display type, to restore.
SOURCE_DISPLAY_PROPERTY = "hairlod_display_type"

# A level with at most this many selected segments is drawn from them alone instead (sparse_draw),
# made again when they change: for the strands an index list of at most 2 x 4096 indices, for a thick
# level a texture of them; a sparse level spread over many blocks (a far view's few finer clusters)
# draws no more than it selected.
EXACT_SEGMENTS = 1 << 12
SELECTION_SLOT = 6  # sampler slot of the selection texture (the BCSDF tables take 0-2)
SKIN_SLOT = 8       # sampler slot of the skinning maps (skinning.glsl; view_transform takes 7)
SURFACE_SLOT = 9    # of the strands' surface transforms (strand.vert.glsl)
SURFACE_ROW = 1024  # strands per row of that texture (3 texels each)
# The guides moved by their surface transforms agree with the guides Blender deformed to this fraction
# of the hair's size (float rounding is about 1e-6) before the strands follow the surface.
SURFACE_AGREEMENT = 1e-4


def level_colour(level, level_count):
    """The overlay colour of `level`; the strands take the last colour whatever their index."""
    if level == level_count - 1:
        return LEVEL_COLOURS[-1]
    return LEVEL_COLOURS[min(level, len(LEVEL_COLOURS) - 2)]


MAX_LIGHTS = 8
# std140 layout of the per-frame uniform block; frame_block() fills it in this order.
FRAME_BLOCK = f"""
struct HairFrame {{
  mat4 model;
  mat4 view_projection;
  mat4 model_inverse;
  vec4 camera;
  vec4 viewport;
  vec4 ambient;
  vec4 counts;
  vec4 hair_centre;
  vec4 hair_axes;
  vec4 light_vectors[{MAX_LIGHTS}];
  vec4 light_colours[{MAX_LIGHTS}];
  vec4 shadow;
  mat4 light_view_projection[{opacity_map.MAX_SHADOWED_LIGHTS}];
  vec4 light_shadow[{opacity_map.MAX_SHADOWED_LIGHTS}];
  vec4 world_grid_lower;
  vec4 world_grid_extent;
  vec4 scattering;
}};
"""


def frame_block(*args, **kwargs):
    """The HairFrame uniform block (frame_data's values) as a GPUUniformBuf."""
    return _uniform_block(frame_data(*args, **kwargs))


def _uniform_block(data):
    return gpu.types.GPUUniformBuf(gpu.types.Buffer('FLOAT', data.size, data))


def frame_data(model, view_projection, camera, viewport, ambient, light_count, light_vectors, light_colours,
               hair_volume, shadow_strength, strand_radius, shadows, control_points=0, strand_coverage=False,
               strands_follow_surface=False, occlusion=None, scattering_albedo=(0.0, 0.0, 0.0)):
    """The HairFrame uniform block's values, float32 (matrices column-major, as std140 stores them).
    viewport = (width, height, the hair layer's sample: 0, the first after a change (for_sample), 0);
    counts = (lights, control points per strand, 1 to draw strands and thick hairs by coverage (coverage_choice.glsl), 1 when
    the strands move by their surface transforms);
    hair_centre.w carries the self-shadowing sigma = strength x extinction (hairlod.self_shadow) of the
    lights without an opacity map; shadow = (the strands' radius in world units, 0, strength, 0) and
    the mapped lights' views (opacity_maps.LightShadows) those of the maps; world_grid_lower = (the
    world occlusion grid's lower corner, strength x its depth factor; 0: no grid, the world through the
    ellipsoid) and world_grid_extent = (its extent, 0) place `occlusion`
    (hairlod.world_occlusion.WorldOcclusion, the texture of world_depths); scattering = (the hair's
    scattering albedo rho, 0: hairlod.preview_luts.scattering_albedo, for the share of the world's light
    the hair around a point scatters on to it, hairlod.self_shadow.scattered_share)."""
    model = np.asarray(model, np.float64)
    data = np.concatenate([model.T.ravel(), np.asarray(view_projection, np.float32).T.ravel(),
                           np.linalg.inv(model).T.ravel(), np.asarray(camera, np.float32), (*viewport, 0.0, 0.0),
                           np.asarray(ambient, np.float32), (float(light_count), float(control_points), float(strand_coverage),
                            float(strands_follow_surface)),
                           (*hair_volume.centre, shadow_strength * hair_volume.extinction), (*hair_volume.semi_axes, 0.0),
                           light_vectors.ravel(), light_colours.ravel(), (strand_radius, 0.0, shadow_strength, 0.0),
                           np.transpose(shadows.view_projection, (0, 2, 1)).ravel(), shadows.light_shadow.ravel(),
                           _grid_placement(occlusion, shadow_strength), (*np.asarray(scattering_albedo, np.float64), 0.0)])
    return np.ascontiguousarray(data, dtype=np.float32)


def _grid_placement(occlusion, strength):
    """frame_data's world_grid_lower and world_grid_extent."""
    if occlusion is None:
        return np.zeros(8)
    return np.concatenate([occlusion.lower, (strength * occlusion.depth_factor,), occlusion.extent, (0.0,)])


# Where the view-projection matrix and the viewport's (width, height, sample) lie in frame_data's values
# (column-major, after the model matrix; after the camera).
_VIEW_PROJECTION = slice(16, 32)
_SAMPLE = 54


def for_sample(values, sample, viewport):
    """frame_data's values for sample `sample` of the hair layer on a viewport of `viewport` = (width,
    height) pixels: the view-projection moved by hair_layer.SAMPLE_OFFSETS[sample] pixels (clip x and y
    gain 2 offset / size times clip w; the depth is unchanged), and the sample in frame.viewport.z, which
    draws another choice of the strands and thick hairs by coverage (coverage_choice.glsl)."""
    offset = hair_layer.SAMPLE_OFFSETS[sample]
    moved = np.array(values, dtype=np.float32)
    columns = moved[_VIEW_PROJECTION].reshape(4, 4)  # one row per column of the matrix
    columns[:, 0] += 2.0 * offset[0] / viewport[0] * columns[:, 3]
    columns[:, 1] += 2.0 * offset[1] / viewport[1] * columns[:, 3]
    moved[_VIEW_PROJECTION] = columns.ravel()
    moved[_SAMPLE] = float(sample)
    return moved


def anti_aliasing_samples():
    """How many samples the hair layer averages at rest: as many as Blender redraws a viewport for its
    own anti-aliasing (Preferences > Viewport > Anti-Aliasing; 1 for No Anti-Aliasing and FXAA)."""
    setting = getattr(bpy.context.preferences.system, "viewport_aa", "8")
    return min(int(setting), hair_layer.MAX_SAMPLES) if setting.isdigit() else 1


# What the thick hairs' varyings hold, constant for a strand (one hair of radius r: no ellipse, n = 1,
# rho = 1, the line drawn through its middle); the direction to the camera from the fragment's position.
STRAND_CONSTANTS = """#define v_across 0.0
#define v_widen 1.0
#define v_ellipse vec3(0.0)
#define v_cluster vec2(1.0)
#define v_to_camera (frame.camera.xyz - v_position * frame.camera.w)
"""


# What shades a strand (hair_shading.glsl, one hair: n = 1, rho = 1). HAIRLOD_SINGLE_HAIR leaves out of
# aggregated_bcsdf.glsl what depends on n (6 % of a near view's redraw when every fragment shaded).
STRAND_SHADING = "#define HAIRLOD_SINGLE_HAIR\n#define HAIRLOD_DEFERRED_STRANDS\n"


def _declare_shading(info):
    """Declares on a GPUShaderCreateInfo what hair_radiance (hair_shading.glsl) reads, and returns the
    fragment source's libraries it needs, up to hair_shading.glsl (a typedef_source holding FRAME_BLOCK
    and world_srbf.WORLD_BLOCK, and the HairFrame block, are the caller's)."""
    from . import bcsdf_textures

    world_srbf.declare(info)
    world_occlusion_texture.declare(info)
    bcsdf_textures.declare(info)
    view_transform.declare(info)
    opacity_maps.declare(info)
    return (view_transform.GLSL_CONSTANTS + opacity_maps.glsl_constants() +
            glsl_source("aggregated_bcsdf.glsl", "srbf_world.glsl", "self_shadow.glsl", "world_occlusion.glsl", "opacity_map.glsl",
                        "view_transform.glsl", "hair_shading.glsl"))


def _create_shader(kind, purpose="shade", test_level=True, pulled=False):
    """The program drawing a level of `kind` ("thick" or "strand") for `purpose`: "shade" (the
    viewport), or a light's pass of the opacity maps, "depth" or "opacity". A shading program without
    `test_level` draws segments all selected at its level (no selection test, no discard); a `pulled`
    one (thick, shading, without the test) draws a sparse level's selected segments from textures
    (pulled_strips) instead of vertex attributes. Strands' shading is deferred to the hair layer's pass
    (strand_shading_shader): their shading program only leaves what it needs in the layer."""
    if pulled and (kind != "thick" or purpose != "shade" or test_level):
        raise ValueError("only the thick hairs' shading without the selection test is drawn pulled")

    # Strands pass on only what varies along them (a strand is one hair: STRAND_CONSTANTS), and the
    # selection's key only where the fragment tests it: every varying is set up per primitive and
    # interpolated per fragment, which on a software GPU costs as much as the shading.
    selection_varyings = purpose != "shade" or test_level
    interface = gpu.types.GPUStageInterfaceInfo(f"hairlod_{kind}_{purpose}_{int(selection_varyings)}_{int(pulled)}_interface")
    interface.smooth('VEC3', "v_position")
    interface.smooth('VEC3', "v_tangent")
    if kind == "thick":
        interface.smooth('VEC3', "v_to_camera")
        interface.smooth('FLOAT', "v_across")
        interface.smooth('FLOAT', "v_widen")
        interface.flat('VEC3', "v_ellipse")
        interface.flat('VEC2', "v_cluster")
    if selection_varyings:
        interface.flat('INT', "v_select_cluster")
        interface.smooth('FLOAT', "v_select_point")
    info = gpu.types.GPUShaderCreateInfo()
    # Per-frame data in a uniform block (push constants are limited to 128 bytes).
    info.typedef_source(FRAME_BLOCK + world_srbf.WORLD_BLOCK)
    info.uniform_buf(0, "HairFrame", "frame")
    info.push_constant('INT', "draw_level")
    info.sampler(SELECTION_SLOT, 'FLOAT_2D', "selection_levels")
    info.sampler(SKIN_SLOT, 'FLOAT_2D', "skin_maps")
    if kind == "strand":
        info.sampler(SURFACE_SLOT, 'FLOAT_2D', "strand_frames")
    if purpose == "shade":
        info.push_constant('VEC4', "level_colour")
        info.push_constant('INT', "shading_mode")
        shading = _declare_shading(info) if kind == "thick" else STRAND_SHADING
    else:
        info.push_constant('INT', "shadow_light")
        opacity_maps.declare(info, depth=purpose == "opacity", opacity=False)
    pulled_defines = pulled_strips.declare(info) if pulled else ""
    if not pulled:
        for slot, (name, length) in enumerate(_attributes(kind)):
            info.vertex_in(slot, f'VEC{length}', name)
    info.vertex_out(interface)
    info.fragment_out(0, 'VEC4', "fragColor")
    if purpose == "shade":
        info.fragment_out(1, 'VEC4', "strandPosition")  # the hair layer's second buffer
    defines = ("" if selection_varyings else "#define HAIRLOD_ALL_AT_DRAW_LEVEL\n") + \
        ("" if kind == "thick" else STRAND_CONSTANTS)
    info.vertex_source(defines + pulled_defines + f"#define SKIN_MAP_TEXELS {lod.SKIN_MAP_TEXELS}\n#define SURFACE_ROW {SURFACE_ROW}\n" +
                       glsl_source("skinning.glsl", "coverage_choice.glsl",
                                   "thick_hair.vert.glsl" if kind == "thick" else "strand.vert.glsl"))
    if purpose == "shade":
        info.fragment_source(defines + glsl_source("selection.glsl") + shading + glsl_source("hair.frag.glsl"))
    else:
        info.fragment_source(defines + opacity_maps.glsl_constants(purpose == "opacity") +
                             glsl_source("selection.glsl", "opacity_map.glsl", "opacity_pass.frag.glsl"))
    return gpu.shader.create_from_info(info)


def shader(kind, purpose="shade", test_level=True, pulled=False):
    key = (kind, purpose, bool(test_level), bool(pulled))
    if key not in _shaders:
        _shaders[key] = _create_shader(kind, purpose, test_level, pulled)
    return _shaders[key]


def strand_shading_shader():
    """The hair layer's pass that shades the strands left in it (strand_shading.frag.glsl:
    hair_radiance once per pixel where a strand is the nearest hair)."""
    key = ("strand shading",)
    if key not in _shaders:
        info = gpu.types.GPUShaderCreateInfo()
        info.typedef_source(FRAME_BLOCK + world_srbf.WORLD_BLOCK)
        info.uniform_buf(0, "HairFrame", "frame")
        hair_layer.declare_strand_shading(info)
        info.fragment_source(STRAND_SHADING + _declare_shading(info) + glsl_source("strand_shading.frag.glsl"))
        _shaders[key] = gpu.shader.create_from_info(info)
    return _shaders[key]


def compile_shaders():
    """Builds the preview's shaders now (once a session), so that a first frame does not wait for them."""
    for kind in ("thick", "strand"):
        for purpose in ("shade", "depth", "opacity"):
            shader(kind, purpose)
        shader(kind, "shade", test_level=False)
    shader("thick", "shade", test_level=False, pulled=True)
    strand_shading_shader()


def _attributes(kind):
    """(name, components) of the vertex attributes of a level's buffers, in shader input order."""
    common = (("position", 3), ("tangent", 3))
    if kind == "thick":
        return common + (("major", 3), ("minor", 3), ("cluster", 2), ("select_key", 2))
    return common + (("select_key", 2),)


def _vertex_buffers(kind, arrays):
    """One vertex buffer per attribute (strand_batch.attribute_buffer), in shader input order."""
    return [attribute_buffer(name, arrays[name]) for name, _ in _attributes(kind)]


def _matrix_array(matrix, dtype=np.float32):
    """A 4 x 4 mathutils Matrix as an array of its rows. np.fromiter over the rows' values: about 5
    times faster than np.array, which reads the Matrix as a sequence of Vectors (7 us a matrix)."""
    return np.fromiter(itertools.chain.from_iterable(matrix), dtype, 16).reshape(4, 4)


def _batch(kind, buffers, elements):
    primitive = 'TRIS' if kind == "thick" else 'LINES'
    batch = gpu.types.GPUBatch(type=primitive, buf=buffers[0],
                               elem=gpu.types.GPUIndexBuf(type=primitive, seq=elements.view(np.int32)))
    for buffer in buffers[1:]:
        batch.vertbuf_add(buffer)
    return batch


def skin_texture(maps):
    """The skinning maps [clusters, n_c, SKIN_MAP_TEXELS, 4] (FrameSkinning.maps) as the RGBA32F
    texture skinning.glsl reads: SKIN_MAP_TEXELS n_c texels wide, one row per L0 cluster."""
    clusters, control_points, texels = maps.shape[:3]
    data = np.ascontiguousarray(maps, dtype=np.float32).ravel()
    return gpu.types.GPUTexture((texels * control_points, clusters), format='RGBA32F',
                                data=gpu.types.Buffer('FLOAT', data.size, data))


def surface_rows(strands):
    """The strands' transforms are laid out for surface_texture in an array of this many [3, 4] maps:
    `strands` rounded up to whole rows of SURFACE_ROW (at least one)."""
    return max(1, -(-strands // SURFACE_ROW)) * SURFACE_ROW


def surface_texture(transforms):
    """The strands' surface transforms [S, 3, 4] (hierarchy order) as the RGBA32F texture strand.vert.glsl
    reads: SURFACE_ROW strands per row, the 3 rows of strand i's map at texels 3 (i mod SURFACE_ROW) + r
    of row i / SURFACE_ROW. An array already laid out (float32, C-contiguous, surface_rows(S) maps, the
    rows past the strands unread) is uploaded as it is: for 100k strands the padded copy of 4.8 MB into
    new memory took 15 ms of a frame's draw."""
    strands = len(transforms)
    data = transforms
    if not (strands == surface_rows(strands) and isinstance(data, np.ndarray) and data.dtype == np.float32 and
            data.flags.c_contiguous):
        data = np.zeros((surface_rows(strands), 3, 4), np.float32)
        data[:strands] = transforms
    data = data.reshape(-1)
    return gpu.types.GPUTexture((3 * SURFACE_ROW, len(data) // (12 * SURFACE_ROW)), format='RGBA32F',
                                data=gpu.types.Buffer('FLOAT', data.size, data))


class LevelBlocks:
    """The static batches of one level: blocks of whole L0 clusters, all their segments; for the
    strands also the same blocks at the longer strides of the vertex LoD, made on first use."""

    def __init__(self, kind, buffers, item_first, control_points):
        self.bounds = np.asarray(preview_buffers.cluster_blocks(item_first, control_points, preview_buffers.BLOCK_SEGMENTS),
                                 dtype=np.int64)
        self.segments = np.diff(np.asarray(item_first, np.int64)[self.bounds]) * (control_points - 1)  # per block
        self.kind, self.buffers, self.item_first, self.control_points = kind, buffers, item_first, control_points
        primitive = "strips" if kind == "thick" else "lines"
        # Every segment's elements at once, cut per block: item-major, so a block's clusters are one
        # run of rows (2 triangles per strip segment, 1 line per strand segment).
        elements = preview_buffers.block_indices(item_first, 0, len(item_first) - 1, control_points, primitive)
        row_first = np.asarray(item_first, np.int64) * (control_points - 1) * (2 if kind == "thick" else 1)
        self.batches = []
        for first, end in zip(self.bounds[:-1], self.bounds[1:]):
            rows = elements[row_first[first]:row_first[end]]
            self.batches.append(_batch(kind, buffers, rows) if rows.size else None)
        self._strided = {}  # (block, stride index) -> GPUBatch or None

    def batch(self, block, stride_index=0):
        """The batch of `block` at STRAND_STRIDES[stride_index] (strands only; 0 for a thick level)."""
        if stride_index == 0:
            return self.batches[block]
        key = (int(block), int(stride_index))
        if key not in self._strided:
            lines = preview_buffers.strided_lines(self.item_first, self.bounds[block], self.bounds[block + 1],
                                                  self.control_points, preview_buffers.STRAND_STRIDES[stride_index])
            self._strided[key] = _batch(self.kind, self.buffers, lines) if lines.size else None
        return self._strided[key]


class ViewState:
    """The selection of one viewport, its texture and how each level is drawn."""

    def __init__(self, selection, level_count):
        self.selection = selection
        self.texture = None                  # GPUTexture [segments x clusters] of selected levels, -1 when culled
        self.to_draw = [None] * level_count  # per dense level: bool per block; None for a sparse level
        self.one_level = [None] * level_count  # per dense level: bool per block, every segment at the level
        self.exact = [None] * level_count    # per sparse level: its selected segments (strands: a GPUBatch,
                                             # thick hairs: a pulled_strips.PulledDraw), or None
        self.exact_keys = [None] * level_count  # the selected segments each exact batch was built for
        self.level_versions = None  # ViewSelection.level_versions the texture and the levels' flags are of
        self.block_strides = None  # per block of the strand level: index into STRAND_STRIDES (vertex LoD)
        self.strides_key = None    # the view and pose block_strides were chosen for
        self.block_order = {}      # level drawn from blocks -> its blocks nearest first (blocks_near_to_far)
        self.order_key = None      # the view and pose block_order was made for
        self.segments = None       # segments drawn per level (LodPreview.segments_drawn), counted when read
        self.hair_layer = None     # hair_layer.HairLayer the hair is drawn into, made at the first draw
        self.drawn_key = None      # what the hair layer was last drawn from (LodPreview.draw)

    def upload_again(self):
        """The next draw uploads the selection and chooses how to draw each level from scratch, as if
        every level's selected segments had moved."""
        self.texture = self.level_versions = None
        self.exact_keys = [None] * len(self.exact_keys)


class LodPreview:
    """The GPU state of one object's LoD asset: vertex buffers per level and a ViewState per view."""

    def __init__(self, asset):
        self.asset = asset
        self.views = {}  # RegionView3D pointer -> ViewState
        self.vertex_buffers = None
        self.blocks = None       # per level: LevelBlocks
        self.pulled_points = None  # per thick level: its control points' texture (pulled_strips)
        self.slot_batches = pulled_strips.SlotBatches()
        self.hair_volume = None  # self_shadow.HairVolume of the rest strands, with the vertex buffers
        self.last_draw = None    # (ViewState, its timings) of the last draw, what `stats` reports
        self.max_hair_count = None
        self.textures = None
        self.textures_key = None
        self.world = None  # (key, WorldLights or None, reason, uniform block, response texture)
        self.packed = False
        # Following the hair's deformation: the vertex buffers hold the rest pose, skinned on the GPU
        # by the maps of `skinning` (uploaded as `skin_texture`) for the guides last read.
        self.skinning = None
        self.skin_texture = None
        self.maps_array = None  # the array the maps are written into for their texture (_skin_maps)
        self.guides = None          # the guides drawn [G, n_c, 3]; None: the rest pose
        self.pending_guides = None  # guides read by a handler, applied by the next draw
        self.pending_skinned = False  # the handler that read them has skinned to them (the maps are theirs)
        # Hair attached to a mesh: its strands' transforms (surface_attachment.SurfaceFollow, hierarchy
        # order, made on the first read; False when the hair is not attached or cannot be bound), the
        # transforms read with the pending guides (None: the strands follow the maps) and their texture
        # (None: the strands follow the maps; an empty texture is bound in its place).
        self.surface = None
        self.pending_surface = None
        self.surface_texture = None
        self.no_surface_texture = None
        self.guide_items = None  # the guides' positions in hierarchy order
        self.guide_tolerance = None  # SURFACE_AGREEMENT of the hair's size (_agrees_with_guides)
        self.surface_transforms = None  # the transforms of the texture
        self.surface_arrays = None  # the two arrays the transforms are written into (_surface_target)
        self.rest_volume = None     # (HairVolume of the rest strands, bounding box of the rest clusters)
        self.occlusion = None       # world_occlusion.WorldOcclusion of the strands at the pose drawn
        self.rest_occlusion = None  # ... at rest
        self.occlusion_texture = None  # world_occlusion_texture of rest_occlusion, made at the first shaded draw
        self.follow_status = ""     # why the preview does not follow the hair, when it does not
        self.follow_stats = {}
        self.pose_version = 0       # counts the poses skinned to (the opacity maps are drawn per pose)
        self.strand_radius = 0.0    # mean strand radius, object space
        self.opacity = None         # opacity_maps.OpacityMaps, made at the first shaded draw
        self.shadow_selection = None  # (level, selection texture drawing every cluster at that level) of the maps
        # The strands' vertex LoD: per L0 cluster and stride, how far the chords stray from the
        # skipped control points (object space, rest pose), and the clusters' bounding spheres at the
        # pose drawn.
        self.stride_deviation = None
        self.cluster_bounds = None
        self.block_centres = None  # (pose_version, per level preview_buffers.block_centres)

    @property
    def level_count(self):
        return len(self.asset.levels) + 1

    def _build_vertex_buffers(self):
        vertices = self.asset.preview_vertices()
        control_points = self.asset.control_points
        self.blocks = []
        buffers = []
        for index, arrays in enumerate(vertices["levels"]):
            item_first = preview_buffers.cluster_items(self.asset, index)
            buffers.append(_vertex_buffers("thick", arrays))
            self.blocks.append(LevelBlocks("thick", buffers[-1], item_first, control_points))
        self.pulled_points = [pulled_strips.points_texture(arrays) for arrays in vertices["levels"]]
        strands = vertices["rest_strands"]
        item_first = preview_buffers.cluster_items(self.asset, len(self.asset.levels))
        buffers.append(_vertex_buffers("strand", vertices["strands"]))
        self.blocks.append(LevelBlocks("strand", buffers[-1], item_first, control_points))
        self.vertex_buffers = buffers
        self.hair_volume = self_shadow.strands_volume(strands)
        self.strand_radius = float(np.mean(strands.radius, dtype=np.float64))
        self.pose_version += 1
        self.stride_deviation = preview_buffers.stride_deviation(vertices["strands"]["position"], control_points, item_first)
        self.skinning = self.asset.frame_skinning()
        self.pending_skinned = False  # a new skinning: any pending guides are skinned again
        self.cluster_bounds = self.skinning.cluster_bounds
        self.rest_volume = (self.hair_volume, _spheres_box(self.cluster_bounds))
        self.occlusion = self.rest_occlusion = world_occlusion.strands_occlusion(strands)
        self.occlusion_texture = None
        self.skin_texture = skin_texture(self._skin_maps())
        if self.pending_guides is None and self.guides is not None:
            self.pending_guides, self.guides = self.guides, None  # buffers rebuilt: skin them again
            self.pending_surface = self.surface_transforms

    def read_guides(self, obj, depsgraph):
        """Reads the guides of ``obj``'s evaluated hair (only the guide curves are gathered and
        resampled) for the next draw to skin to; nothing when they have not moved. When the hair's
        curves no longer match the asset, the preview stays at the last pose and says why."""
        from ..curves import evaluated_curve_subset

        if obj.type != 'CURVES':
            return False  # an asset shown on another object (Load LoD Asset) has no hair to follow
        start = time.perf_counter()
        try:
            curves = evaluated_curve_subset(obj, self.asset.guide_strands, depsgraph, self.asset.strand_count)
            guides = self.asset.resample_guides(curves)
        except ValueError as error:
            self.follow_status = f"Not following the hair: {error}"
            return False
        self.follow_status = ""
        if self.surface is None:
            self.bind_surface(obj, depsgraph, guides)
        current = self.pending_guides if self.pending_guides is not None else self.guides
        if np.array_equal(guides, self.asset.rest_guides if current is None else current):
            self.follow_stats["read_ms"] = 1e3 * (time.perf_counter() - start)
            return False
        self.pending_surface = self.read_surface(obj, depsgraph, guides)
        self.follow_stats["read_ms"] = 1e3 * (time.perf_counter() - start)
        self.pending_guides = guides
        self._skin_pending_guides()
        return True

    def _skin_pending_guides(self):
        """The maps for the guides just read, computed now, in the handler that read them: the GPU is
        idle between frames there, where in the draw llvmpipe's threads still rasterise what Blender drew
        before the preview, and share the cores with the skinning's (15-16 ms there against 4 ms)."""
        self.pending_skinned = False
        if self.skinning is None:  # no draw yet: the first one builds the buffers and skins
            return
        start = time.perf_counter()
        try:
            self.skinning.update(self.pending_guides)
        except ValueError as error:
            self.follow_status = f"Not following the hair: {error}"
            self.pending_guides = self.pending_surface = None
            return
        self.pending_skinned = True
        self.follow_stats["skin_ms"] = 1e3 * (time.perf_counter() - start)

    def _agrees_with_guides(self, points, guides):
        """Whether guide points [G, n_c, 3] lie on `guides` to SURFACE_AGREEMENT of the hair's size."""
        if self.guide_tolerance is None:
            extent = np.ptp(self.asset.rest_guides.reshape(-1, 3), axis=0).max()
            self.guide_tolerance = SURFACE_AGREEMENT * max(float(extent), 1e-30)
        return bool(np.abs(points - guides).max() <= self.guide_tolerance)

    def bind_surface(self, obj, depsgraph, guides):
        """Binds the strands to the mesh `obj` is attached to, once (self.surface; False when the hair
        is not attached or cannot be bound): to its original mesh, or, where the surface's modifiers
        change its mesh (a Subdivision Surface), to the mesh they make while the hair is at the pose
        the LoD was built at (its guides are `guides`), and until then not at all."""
        from .. import surface

        try:
            changed = surface.changes_topology(obj, depsgraph)
            if changed is None:
                self.surface = False
                return
            if changed:
                if not self._agrees_with_guides(self.asset.rest_guides, guides):
                    self.follow_stats["surface"] = (f"Strands follow the guides until the hair is back at the pose the "
                                                    f"LoD was built at (the modifiers of '{surface.attachment(obj)[0].name}' "
                                                    f"change its mesh)")
                    return
            self.surface = surface.follow(obj, depsgraph, order=self.asset.strand_order, evaluated=changed)
        except ValueError as error:
            self.surface = False
            self.follow_stats["surface"] = f"Strands follow the guides ({error})"

    def read_surface(self, obj, depsgraph, guides):
        """The strands' transforms to the pose of the mesh `obj` is attached to, when the
        guides moved by theirs are `guides` (the hair moves exactly with its surface), else None (the
        strands follow the maps): the hair is not attached or not bound (bind_surface), or something
        else deforms it too, or the LoD was built from hair its surface had already deformed (the
        transforms start from the surface's original mesh, as Blender's node does). The transforms are
        [surface_rows(S), 3, 4], laid out for surface_texture: the first S are the strands'."""
        from .. import surface
        from ... import surface_attachment

        if not self.surface:  # not attached, not bound, or not yet bound
            return None
        laid_out = self._surface_target()
        try:
            transforms = surface.posed_transforms(self.surface, obj, depsgraph, out=laid_out[:self.asset.strand_count])
        except ValueError as error:
            self.follow_stats["surface"] = f"Strands follow the guides ({error})"
            return None
        if self.guide_items is None:
            items = np.empty(self.asset.strand_count, np.int64)
            items[self.asset.strand_order] = np.arange(self.asset.strand_count)
            self.guide_items = items[self.asset.guide_strands]
        if not self._agrees_with_guides(surface_attachment.apply(transforms[self.guide_items], self.asset.rest_guides), guides):
            self.follow_stats["surface"] = ("Strands follow the guides (the hair moves otherwise than its surface, or the "
                                            "LoD was built away from the surface's rest pose)")
            return None
        self.follow_stats["surface"] = f"Strands follow the surface '{surface.attachment(obj)[0].name}'"
        return laid_out

    def _surface_target(self):
        """The array the next pose's surface transforms are written into, laid out for surface_texture:
        one of two kept from pose to pose (memory already mapped), not the one the current texture was
        made from (surface_transforms, which a rebuild of the buffers uploads again)."""
        if self.surface_arrays is None:
            shape = (surface_rows(self.asset.strand_count), 3, 4)
            self.surface_arrays = (np.zeros(shape, np.float32), np.zeros(shape, np.float32))
        first, second = self.surface_arrays
        return second if self.surface_transforms is first else first

    def _apply_pending_guides(self):
        """Skins to the guides a handler read: new maps, their texture, the views' selection
        geometry and the self-shadowing volume. O(clusters n_c): no strand is touched on the CPU."""
        guides, self.pending_guides = self.pending_guides, None
        transforms, self.pending_surface = self.pending_surface, None
        start = time.perf_counter()
        if not self.pending_skinned:  # else the handler that read them skinned to them
            try:
                self.skinning.update(guides)
            except ValueError as error:
                self.follow_status = f"Not following the hair: {error}"
                return
            self.follow_stats["skin_ms"] = 1e3 * (time.perf_counter() - start)
        self.pending_skinned = False
        skinned = time.perf_counter()
        self.skin_texture = skin_texture(self._skin_maps())
        self.surface_transforms = transforms
        self.surface_texture = None if transforms is None else surface_texture(transforms)
        uploaded = time.perf_counter()
        for state in self.views.values():
            state.selection.set_geometry(self.skinning)
        self.cluster_bounds = self.skinning.cluster_bounds
        rest_volume, rest_box = self.rest_volume
        self.hair_volume = self_shadow.moved_volume(rest_volume, rest_box, _spheres_box(self.cluster_bounds))
        self.occlusion = world_occlusion.moved_occlusion(self.rest_occlusion, rest_box, _spheres_box(self.cluster_bounds))
        self.guides = guides
        self.pose_version += 1
        self.follow_stats.update(upload_ms=1e3 * (uploaded - skinned))

    def _skin_maps(self):
        """The skinning's maps, written into one array kept from frame to frame: memory already mapped,
        where a new 2.6 MB array per frame (1000 clusters) cost about 1.3 ms of page faults in the draw."""
        if self.maps_array is None:
            self.maps_array = self.skinning.maps
        return self.skinning.maps_into(self.maps_array)

    def view_state(self, key):
        if key not in self.views:
            self.views[key] = ViewState(self.asset.view_selection(skinning=self.skinning), self.level_count)
        return self.views[key]

    def hair_coverage(self, region_3d):
        """(the share of the hair layer's samples holding hair per pixel, float32 [height, width] with rows
        bottom-up, how many samples) of the viewport `region_3d` as last drawn; None before its first draw."""
        pixels = self.hair_pixels(region_3d)
        return None if pixels is None else pixels[1:]

    def hair_pixels(self, region_3d):
        """(the hair's colour per pixel as the composite writes it, float32 [height, width, 3]; the share of
        the samples holding hair, float32 [height, width]; how many samples) of the viewport `region_3d` as
        last drawn (HairLayer.pixels), rows bottom-up; None before its first draw."""
        state = self.views.get(region_3d.as_pointer())
        if state is None or state.hair_layer is None or state.hair_layer.size is None:
            return None
        return (*state.hair_layer.pixels(), state.hair_layer.samples)

    def upload_selection(self, state):
        """The selection as a texture (level per L0 cluster and segment), and per level what to draw:
        the flagged blocks of a dense level, or its selected segments alone for a sparse one
        (sparse_draw). Only what a change needs: the texture and a level's flags when some level's
        selected segments moved (ViewSelection.level_versions), the strands' list when their strides
        did. A few tens of kB per frame and a small index list."""
        versions = state.selection.level_versions
        present = whole = selected = None
        state.segments = None  # counted again when the statistics are read
        if state.texture is None or versions != state.level_versions:
            values, present, whole = state.selection.frame_levels()
            clusters, segments = values.shape
            state.texture = gpu.types.GPUTexture((segments, clusters), format='R32F',
                                                 data=gpu.types.Buffer('FLOAT', values.size, values.ravel()))
            selected = state.selection.segments_per_level()
        for level, blocks in enumerate(self.blocks):
            thick = level < self.level_count - 1
            if state.level_versions is None or versions[level] != state.level_versions[level]:
                # The level's selected segments moved: dense or sparse again, and its flags.
                if selected[level] > EXACT_SEGMENTS:
                    to_draw, one_level = preview_buffers.level_blocks(present, whole, level, blocks.bounds)
                    if not (thick and preview_buffers.blocks_wasteful(blocks.segments, to_draw, selected[level])):
                        state.to_draw[level], state.one_level[level] = to_draw, one_level
                        state.exact[level], state.exact_keys[level] = None, None
                        continue
                state.to_draw[level] = None
            elif state.to_draw[level] is not None:
                continue  # dense, the same blocks (the strands' strides are read as they are drawn)
            # A sparse level's list: its selected segments (their version) decide it, and the strands'
            # strides their chords.
            strides = None if thick else self.cluster_strides(state)
            key = (versions[level], None if strides is None else strides.tobytes())
            if key == state.exact_keys[level]:
                continue
            state.exact_keys[level] = key
            state.exact[level] = self.sparse_draw(state, level, strides)
        state.level_versions = versions

    def sparse_draw(self, state, level, strides=None):
        """What draws a sparse level's selected segments (ViewState.exact), None when it has none: a
        thick level's selected segments pulled by the shader from textures (pulled_strips: no index list
        to make), the strands' chords at `strides` per L0 cluster (vertex LoD) as an index list."""
        if level < self.level_count - 1:
            starts = state.selection.indices(level, "segments")
            return self.slot_batches.draw_of(starts, self.pulled_points[level]) if starts.size else None
        lines = state.selection.strided_strand_lines(strides)
        return _batch("strand", self.vertex_buffers[level], lines) if lines.size else None

    def update_strides(self, state, model_view, projection, viewport_size, tolerance_px):
        """Per block of the strand level, the longest stride of the vertex LoD whose chords stay within
        `tolerance_px` pixels of the control points they skip, at this view; True when it changed."""
        key = (model_view.tobytes(), projection.tobytes(), viewport_size, tolerance_px, self.pose_version)
        if key == state.strides_key:
            return False
        state.strides_key = key
        strides = preview_buffers.view_block_strides(self.stride_deviation, self.cluster_bounds, model_view, projection,
                                                     viewport_size, tolerance_px, self.blocks[-1].bounds)
        changed = state.block_strides is None or not np.array_equal(strides, state.block_strides)
        state.block_strides = strides
        return changed

    def update_block_order(self, state, model_view):
        """For each level drawn from its blocks, the blocks nearest the camera first; made again when
        the view or the pose changed (the blocks' centres once per pose)."""
        key = (model_view.tobytes(), self.pose_version)
        if key != state.order_key:
            state.order_key, state.block_order = key, {}
        if self.block_centres is None or self.block_centres[0] != self.pose_version:
            self.block_centres = (self.pose_version, [None] * self.level_count)
        centres = self.block_centres[1]
        for level, flags in enumerate(state.to_draw):
            if flags is None or level in state.block_order:
                continue
            if centres[level] is None:
                centres[level] = preview_buffers.block_centres(self.cluster_bounds, self.blocks[level].bounds)
            state.block_order[level] = preview_buffers.blocks_near_to_far(centres[level], model_view)

    def cluster_strides(self, state):
        """int32 [clusters]: the stride each L0 cluster's strands are drawn at (its block's)."""
        return preview_buffers.cluster_strides(state.block_strides, self.blocks[-1].bounds)

    def segments_drawn(self, state):
        """Segments per level as drawn: the thick levels' selected segments, and the strands' chords
        at their strides that span a selected segment."""
        segments = state.selection.segments_per_level()
        if state.block_strides.any():  # else every block at stride 1: what was selected
            segments[-1] = state.selection.strided_strand_segments(self.cluster_strides(state))
        return segments

    def _draw_level(self, state, level, program_for):
        """Draws `level` with program_for(test_level, pulled=False), which binds the level's program with
        or without the per-fragment test of the selection: the blocks whose every segment is at this
        level go without it (no discard, so the GPU can test depth before shading), the others with it;
        a sparse thick level's pulled segments with the pulled program."""
        thick = level < self.level_count - 1
        if state.to_draw[level] is None:
            if state.exact[level] is not None:
                # A thick level's pulled segments are all selected at it; the strands' chords may span
                # segments selected at other levels (vertex LoD), which the test drops.
                state.exact[level].draw(program_for(False, pulled=True) if thick else program_for(True))
            return
        blocks = self.blocks[level]
        strides = None if thick else state.block_strides
        order = state.block_order[level]
        for test_level in (False, True):
            chosen = order[(state.to_draw[level] & (state.one_level[level] != test_level))[order]]
            if not chosen.size:
                continue
            program = program_for(test_level)
            for block in chosen:
                batch = blocks.batch(block, 0 if strides is None else strides[block])
                if batch is not None:
                    batch.draw(program)

    def bind_skinning(self, program, kind):
        """Binds what moves a level's vertices: the maps, and for the strands their surface transforms."""
        program.uniform_sampler("skin_maps", self.skin_texture)
        if kind == "strand":
            if self.surface_texture is None and self.no_surface_texture is None:
                self.no_surface_texture = surface_texture(np.zeros((0, 3, 4), np.float32))
            program.uniform_sampler("strand_frames", self.surface_texture if self.surface_texture is not None
                                    else self.no_surface_texture)

    @property
    def shadow_level(self):
        """The level the opacity maps draw (opacity_map.shadow_level of the levels' segment counts)."""
        segments = [len(level.n_total) * (self.asset.control_points - 1) for level in self.asset.levels]
        segments.append(self.asset.strand_count * (self.asset.control_points - 1))
        return opacity_map.shadow_level(segments)

    def render_opacity_maps(self, obj, state, light_count, light_vectors, strength):
        """The lights' deep opacity maps (opacity_maps), drawn again only when the lights, the object's
        matrix or the pose changed; returns the LightShadows the shading reads and the strands' radius
        in world units."""
        model = np.asarray(obj.matrix_world, np.float64)
        scale = abs(float(np.linalg.det(model[:3, :3]))) ** (1.0 / 3.0)
        strand_radius = self.strand_radius * scale
        centre, radius = _world_sphere(self.hair_volume, model)
        if strength <= 0.0 or not radius > 0.0:
            return opacity_maps.LightShadows(), strand_radius
        shadows = opacity_maps.light_shadows(light_count, light_vectors, centre, radius)
        mapped = shadows.mapped
        if not mapped.size:
            return shadows, strand_radius
        if self.opacity is None:
            self.opacity = opacity_maps.OpacityMaps()
        level = self.shadow_level
        if self.shadow_selection is None or self.shadow_selection[0] != level:
            values = np.full((state.texture.height, state.texture.width), float(level), np.float32)
            self.shadow_selection = (level, gpu.types.GPUTexture((state.texture.width, state.texture.height), format='R32F',
                                                                 data=gpu.types.Buffer('FLOAT', values.size, values.ravel())))
        key = (shadows.view_projection.tobytes(), shadows.light_shadow.tobytes(), model.tobytes(), self.pose_version, level)
        no_colours = np.zeros((MAX_LIGHTS, 4), np.float32)
        tiles = [(int(k), frame_block(obj.matrix_world, shadows.view_projection[k], light_vectors[k],
                                      (float(opacity_map.TILE), float(opacity_map.TILE)), (0.0, 0.0, 0.0, 0.0), light_count,
                                      light_vectors, no_colours, self.hair_volume, strength, strand_radius, shadows,
                                      strands_follow_surface=self.surface_texture is not None))
                 for k in mapped]
        kind = "thick" if level < self.level_count - 1 else "strand"

        def pass_program(purpose):
            def bind(index, frame):
                program = shader(kind, purpose)
                program.bind()
                program.uniform_block("frame", frame)
                program.uniform_int("draw_level", level)
                program.uniform_int("shadow_light", index)
                program.uniform_sampler("selection_levels", self.shadow_selection[1])
                self.bind_skinning(program, kind)
                return program
            return bind

        def draw_all(program):
            for batch in self.blocks[level].batches:
                if batch is not None:
                    batch.draw(program)

        self.opacity.render(key, tiles, (pass_program("depth"), pass_program("opacity")), draw_all)
        return shadows, strand_radius

    def bcsdf_textures(self, obj, settings):
        """The BCSDF tables for the hair's current parameters, baked again only when they change;
        n covers the asset's largest crossing count (tables cover only the range in use)."""
        from ... import bcsdf, hair_params, preview_luts
        from . import bcsdf_textures

        params = object_hair_params(obj)
        if self.max_hair_count is None:
            self.max_hair_count = max(2.0, bcsdf.lod_hair_count_range(self.asset)[0])
        key = (repr(hair_params.params_to_dict(params)), self.max_hair_count)
        if self.textures is None or self.textures_key != key:
            tables = preview_luts.shader_tables(params, max_hair_count=self.max_hair_count)
            self.textures = bcsdf_textures.BcsdfTextures(tables)
            self.textures_key = key
        return self.textures

    def world_lighting(self, obj, settings):
        """(HairWorld block, srbf_lut texture) for the scene's world: its SRBF lights and the hair's
        response table when the world is one world_srbf reads and World Lighting is SRBF, else the
        ambient path. Fitted and tabulated again only when the world or the hair's parameters change;
        `self.world_status` says which path is in use and why."""
        from ... import hair_params, preview_luts

        world = bpy.context.scene.world
        params = object_hair_params(obj)
        key = (settings.world_lighting, world_srbf.world_key(world), repr(hair_params.params_to_dict(params)))
        if self.world is None or self.world[0] != key:
            lights, reason = (None, "World is Ambient") if settings.world_lighting == 'AMBIENT' else \
                world_srbf.world_lights(world)
            if lights is None:
                texture = world_srbf.empty_texture()
            else:
                # A uniform world (the default one, any world colour) has no lobes: its row alone.
                lobes = bool(world_srbf.lit_lobes(lights).any())
                texture = world_srbf.response_texture(preview_luts.srbf_tables(params, lights.lam, lobes=lobes))
            self.world = (key, lights, reason, world_srbf.world_block(lights), texture)
        return self.world[3], self.world[4]

    @property
    def world_status(self):
        """A line for the panel: the world's fit error, or why the ambient term is used."""
        if self.world is None:
            return ""
        lights, reason = self.world[1], self.world[2]
        if lights is None:
            return f"World: ambient ({reason})"
        lobes = world_srbf.lit_lobes(lights)
        sun = "" if lights.sun_direction is None else " and its sun"
        if not lobes.any():
            return f"World: uniform (no SRBF lobes){sun}, {100.0 * lights.relative_error:.1f}% error"
        return f"World: {int(lobes.sum())} SRBF lights{sun}, {100.0 * lights.relative_error:.1f}% error"

    def draw(self, obj, region, region_3d, settings):
        # With Statistics on, the GPU's queue is drained before and after the preview's commands, so the
        # draw time holds the GPU's work (a little slower; Python has no GPU timer queries).
        finish = gpu_finish() if settings.show_statistics else None
        if finish is not None:
            finish()
        start = time.perf_counter()
        if self.vertex_buffers is None:
            self._build_vertex_buffers()
        follow_start = time.perf_counter()
        if self.pending_guides is not None:
            self._apply_pending_guides()
        follow_seconds = time.perf_counter() - follow_start  # in follow_stats, not in the selection's time
        state = self.view_state(region_3d.as_pointer())
        model_view = region_3d.view_matrix @ obj.matrix_world
        projection = region_3d.window_matrix
        model_view_array, projection_array = _matrix_array(model_view), _matrix_array(projection)
        changed = state.selection.update(model_view_array, projection_array, (region.width, region.height), settings.width_px)
        strides_changed = self.update_strides(state, model_view_array, projection_array, (region.width, region.height),
                                              settings.vertex_tolerance_px)
        if changed or strides_changed or state.texture is None:
            self.upload_selection(state)
        selected = time.perf_counter()
        # The order the blocks are drawn in (part of drawing, not of the selection: counted in draw_ms).
        self.update_block_order(state, model_view_array)

        textures = self.bcsdf_textures(obj, settings)
        view_lut, self.view_transform_exact = _view_transforms.texture(bpy.context.scene, on_baked=_tag_viewports)
        world_block, world_texture = self.world_lighting(obj, settings)
        view_to_world = region_3d.view_matrix.inverted_safe()
        if region_3d.is_perspective:
            camera = (*view_to_world.translation, 1.0)
        else:  # orthographic: the direction towards the viewer
            camera = (*(view_to_world.to_3x3() @ Vector((0.0, 0.0, 1.0))).normalized(), 0.0)
        light_count, light_vectors, light_colours = scene_lights(bpy.context.scene, camera, self.world[1])
        world = bpy.context.scene.world
        ambient = (*(world.color if world is not None else (0.05, 0.05, 0.05)), 0.0)
        shaded = settings.overlay == 'SHADED'
        shadows, strand_radius = self.render_opacity_maps(obj, state, light_count, light_vectors,
                                                          settings.self_shadowing if shaded else 0.0)
        # The hair's depth range only, in the preview's own hair layer (depth_range says why).
        view_array = _matrix_array(region_3d.view_matrix, np.float64)
        fitted = depth_range.fitted_projection(projection_array, view_array,
                                               *_world_sphere(self.hair_volume, _matrix_array(obj.matrix_world, np.float64)))
        values = frame_data(obj.matrix_world, fitted.projection @ view_array, camera,
                            (float(region.width), float(region.height)), ambient, light_count, light_vectors,
                            light_colours, self.hair_volume, settings.self_shadowing, strand_radius, shadows,
                            self.asset.control_points, settings.strand_coverage, self.surface_texture is not None,
                            self.occlusion, textures.scattering_albedo)
        if self.occlusion_texture is None:
            self.occlusion_texture = world_occlusion_texture.texture(self.rest_occlusion)
        if state.hair_layer is None:
            state.hair_layer = hair_layer.HairLayer()
        # The hair layer already holds this hair when nothing it is drawn from changed: the frame's values
        # (view, lights, world colour, volume, maps' views), the pose, the selection, the tables, the mode
        # and Statistics (turned on, the hair is drawn once more, timed with the GPU's work). Blender
        # redraws a viewport at rest once per sample of its anti-aliasing (Preferences > Viewport >
        # Anti-Aliasing, 8 by default): those redraws each add one more sample of the hair, moved within
        # the pixel (hair_layer.SAMPLE_OFFSETS), until the layer holds as many as Blender's setting; later
        # redraws composite the layer again (7 ms) instead of drawing the same pixels (a near view of 100k
        # strands: 0.75 s a draw on llvmpipe).
        drawn_key = (values.tobytes(), shaded, self.pose_version, textures, view_lut, self.view_transform_exact,
                     world_block, world_texture, settings.show_statistics)
        at_rest = not (changed or strides_changed) and drawn_key == state.drawn_key
        layer = state.hair_layer
        if at_rest and layer.samples >= anti_aliasing_samples():
            layer.composite(fitted)
            if finish is not None:
                finish()
            if self.last_draw is not None:  # the last full draw's figures; the selection did not change
                self.last_draw = (self.last_draw[0], {**self.last_draw[1], "changed": False})
            return changed
        if at_rest:
            values = for_sample(values, layer.samples, (region.width, region.height))
        frame = _uniform_block(values)  # kept referenced until the batches are drawn

        def bind_shading(program):
            program.uniform_block("frame", frame)
            textures.bind(program)
            if self.opacity is not None:
                self.opacity.bind(program)
            program.uniform_block("hair_world", world_block)
            program.uniform_sampler("srbf_lut", world_texture)
            program.uniform_sampler("view_lut", view_lut)
            program.uniform_sampler("world_depths", self.occlusion_texture)

        with layer.drawing((region.width, region.height)):
            self._draw_levels(state, frame, bind_shading, shaded)
        if shaded:
            layer.shade_strands(strand_shading_shader(), bind_shading)
        layer.accumulate(first=not at_rest)
        layer.composite(fitted)
        state.drawn_key = drawn_key
        if finish is not None:
            finish()

        self.last_draw = (state, {"select_ms": 1e3 * (selected - start - follow_seconds),
                                  "draw_ms": 1e3 * (time.perf_counter() - start),
                                  "changed": bool(changed), "gpu_timed": finish is not None})
        return changed

    def _draw_levels(self, state, frame, bind_shading, shaded):
        """Every level's selected segments, into the bound framebuffer (the hair layer), depth tested;
        bind_shading(program) binds what hair_radiance reads."""
        gpu.state.depth_test_set('LESS_EQUAL')
        gpu.state.depth_mask_set(True)
        # The strands first, then the thick levels: the strands, drawn nearest first, fill the depth
        # buffer, and the thick hairs behind them (at a near view, the far side's clusters) are then
        # dropped by the depth test before their fragments cost anything. Drawn first, the thick
        # hairs' fragments cost a near view of 100k strands about 50 ms a redraw on llvmpipe, which
        # the strands then mostly covered.
        for level in [self.level_count - 1, *range(self.level_count - 1)]:
            if state.exact[level] is None and (state.to_draw[level] is None or not state.to_draw[level].any()):
                continue
            def program_for(test_level, level=level, pulled=False):
                program = shader("thick" if level < self.level_count - 1 else "strand", test_level=test_level, pulled=pulled)
                program.bind()
                program.uniform_block("frame", frame)
                program.uniform_float("level_colour", (*level_colour(level, self.level_count), 1.0))
                program.uniform_int("shading_mode", 0 if shaded else 1)
                if test_level:  # else the compiler drops them
                    program.uniform_int("draw_level", level)
                    program.uniform_sampler("selection_levels", state.texture)
                self.bind_skinning(program, "thick" if level < self.level_count - 1 else "strand")
                if shaded and level < self.level_count - 1:  # the strands are shaded in the composite
                    bind_shading(program)
                return program

            self._draw_level(state, level, program_for)
        gpu.state.depth_mask_set(False)
        gpu.state.depth_test_set('NONE')

    def draw_again(self):
        """The next draw of every view draws the hair again even where nothing changed (benchmarks timing
        a draw of the same view)."""
        for state in self.views.values():
            state.drawn_key = None

    @property
    def stats(self):
        """The last draw's statistics: segments drawn (in all and per level), those selected, its
        selection + update and draw times in ms, whether the selection changed and whether the draw time
        holds the GPU's work (a redraw that only composited the unchanged layer again leaves them). The
        segments are counted here, when read (the panel reads them only with Statistics on), not in every
        frame's selection."""
        if self.last_draw is None:
            return {}
        state, timings = self.last_draw
        if state.segments is None:
            state.segments = self.segments_drawn(state)
        return {"segments": int(state.segments.sum()), "segments_per_level": state.segments.tolist(),
                "selected_segments": int(state.selection.segments_per_level().sum()), **timings}


def gpu_finish():
    """A function that returns once the GPU has done the work queued for the framebuffer being drawn:
    reading one of its pixels back must wait for it (the gpu module has no finish; bgl's glFinish is
    deprecated in 4.x and gone in 5.x)."""
    framebuffer = gpu.state.active_framebuffer_get()
    return lambda: framebuffer.read_color(0, 0, 1, 1, 4, 0, 'UBYTE')


def _world_sphere(volume, model):
    """(centre, radius) in world space of a sphere holding the hair volume's box (object space) under
    the 4 x 4 matrix `model`."""
    corners = volume.centre + volume.semi_axes * np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)])
    world = corners @ model[:3, :3].T + model[:3, 3]
    centre = world.mean(axis=0)
    return centre, float(np.linalg.norm(world - centre, axis=1).max())


def _spheres_box(spheres):
    """(lower, upper) float64 of the box holding the spheres [n, 4] (centre, radius)."""
    spheres = np.asarray(spheres, dtype=np.float64)
    return (spheres[:, :3] - spheres[:, 3:]).min(axis=0), (spheres[:, :3] + spheres[:, 3:]).max(axis=0)


def uses_material(obj, settings):
    """Whether the preview shades with the object's Principled Hair BSDF (Material is on and the
    object has one), so that the panel's hair parameters have no effect."""
    return settings.use_material and material_params(obj) is not None


def scene_lights(scene, camera, world_sun=None):
    """World-space lights for the shader: (count, vectors [MAX_LIGHTS, 4], colours [MAX_LIGHTS, 4]).
    Suns give (direction towards the sun, 0) and their irradiance (strength x colour); point lights
    give (position, 1) and their intensity, power / (4 pi) x colour, which the shader divides by the
    squared distance. Other light types and hidden lights are skipped. The world's own sun
    (`world_sun`: WorldLights with a sun taken out of its image, hairlod.world_lighting.extract_sun)
    comes after them, where there is room. With no light, a headlight at the viewer (irradiance 3)
    keeps the hair visible."""
    vectors = np.zeros((MAX_LIGHTS, 4), np.float32)
    colours = np.zeros((MAX_LIGHTS, 4), np.float32)
    count = 0
    for obj in scene.objects:
        if count == MAX_LIGHTS:
            break
        if obj.type != 'LIGHT' or not obj.visible_get() or obj.data.type not in {'SUN', 'POINT'}:
            continue
        light = obj.data
        colour = np.array(light.color, np.float32) * light.energy
        if light.type == 'SUN':
            vectors[count] = (*(obj.matrix_world.to_3x3() @ Vector((0.0, 0.0, 1.0))).normalized(), 0.0)
            colours[count, :3] = colour
        else:
            vectors[count] = (*obj.matrix_world.translation, 1.0)
            colours[count, :3] = colour / (4.0 * np.pi)
        count += 1
    if world_sun is not None and world_sun.sun_direction is not None and count < MAX_LIGHTS:
        vectors[count] = (*world_sun.sun_direction, 0.0)
        colours[count, :3] = world_sun.sun_irradiance
        count += 1
    if count == 0:
        vectors[0] = camera
        colours[0, :3] = 3.0
        count = 1
    return count, vectors, colours


def replace_source_display(obj, preview_on):
    """While its preview is on, the LoD replaces the object's own drawing in the viewport: the object
    draws as its bounds (its render is unchanged, and hiding it hides the preview too). Off, or without
    a preview, the object's own display type comes back. Not while Blender draws (it changes data).
    An empty holding a preview keeps its own display: it has no geometry the LoD replaces, and Blender
    5 draws an empty displayed as bounds as a cube of its display size (one an older release set to
    bounds still gets its display back when the preview goes off)."""
    if preview_on:
        if obj.type == 'EMPTY':
            return
        if SOURCE_DISPLAY_PROPERTY not in obj:
            obj[SOURCE_DISPLAY_PROPERTY] = obj.display_type
        obj.display_type = 'BOUNDS'
    elif SOURCE_DISPLAY_PROPERTY in obj:
        obj.display_type = obj[SOURCE_DISPLAY_PROPERTY]
        del obj[SOURCE_DISPLAY_PROPERTY]


def attach(obj, asset, packed=False):
    """Shows `asset` (an hairlod.lod.LodAsset in `obj`'s local space) in the viewport for `obj`, in
    place of the object's own drawing while the preview is on. `packed`: the asset is the one packed
    into `obj` (Build Hair LoD), and goes when that does (undo, or the property removed)."""
    if not isinstance(asset, lod.LodAsset):
        raise TypeError(f"asset must be an hairlod.lod.LodAsset, got {type(asset).__name__}")
    preview = LodPreview(asset)
    preview.packed = packed
    _previews[obj.name] = preview
    if obj.hairlod_lod_preview.enabled:
        preview.read_guides(obj, bpy.context.evaluated_depsgraph_get())  # the current frame's pose
    replace_source_display(obj, obj.hairlod_lod_preview.enabled)
    _tag_viewports()


def attach_packed_assets():
    """Previews the asset packed into every object that has one and no preview yet (after loading a
    .blend or enabling the add-on). An asset that cannot be read is reported once and skipped."""
    from ..packed_asset import PACKED_PROPERTY, packed_asset

    for obj in bpy.data.objects:
        if PACKED_PROPERTY not in obj or obj.name in _previews:
            continue
        try:
            attach(obj, packed_asset(obj), packed=True)
        except ValueError as error:
            print(f"hairlod: no LoD preview for '{obj.name}': {error}")


def detach(obj_name):
    _previews.pop(obj_name, None)
    obj = bpy.data.objects.get(obj_name)
    if obj is not None:
        replace_source_display(obj, False)
    _tag_viewports()


def preview_of(obj):
    return _previews.get(obj.name)


def _tag_viewports():
    window_manager = getattr(bpy.context, "window_manager", None)
    for window in window_manager.windows if window_manager else ():
        for area in window.screen.areas:
            if area.type == 'VIEW_3D':
                area.tag_redraw()


def _draw():
    from ..packed_asset import PACKED_PROPERTY

    context = bpy.context
    region, region_3d = context.region, context.region_data
    if region is None or region_3d is None:
        return
    for name, preview in list(_previews.items()):
        obj = bpy.data.objects.get(name)
        if obj is None:
            _previews.pop(name)
            continue
        if preview.packed and PACKED_PROPERTY not in obj:
            _previews.pop(name)  # undone or removed
            continue
        settings = obj.hairlod_lod_preview
        if not settings.enabled or not obj.visible_get():
            continue
        preview.draw(obj, region, region_3d, settings)


def _read_deformations(depsgraph, names=None):
    """Reads the guides of every previewed object (or of those in ``names``) whose preview is on,
    and redraws the viewports when one moved."""
    moved = False
    for name, preview in list(_previews.items()):
        obj = bpy.data.objects.get(name)
        if obj is None or (names is not None and name not in names) or not obj.hairlod_lod_preview.enabled:
            continue
        moved = preview.read_guides(obj, depsgraph) or moved
    if moved:
        _tag_viewports()


@persistent
def _on_frame_change(scene, depsgraph=None):
    """Playback and scrubbing: the hair may have moved (armature, Geometry Nodes, a cache)."""
    _read_deformations(depsgraph if depsgraph is not None else bpy.context.evaluated_depsgraph_get())


@persistent
def _on_depsgraph_update(scene, depsgraph):
    """Edits (a modifier's input, a pose, sculpting): the objects whose geometry was updated."""
    names = {update.id.original.name for update in depsgraph.updates
             if isinstance(update.id, bpy.types.Object) and update.is_updated_geometry}
    if names & _previews.keys():
        _read_deformations(depsgraph, names)


@persistent
def _on_load(_):
    _previews.clear()
    attach_packed_assets()


def _attach_after_register():
    attach_packed_assets()
    return None


# (the bpy.app.handlers list, handler) pairs the preview registers.
_HANDLERS = ((lambda: bpy.app.handlers.load_post, _on_load),
             (lambda: bpy.app.handlers.frame_change_post, _on_frame_change),
             (lambda: bpy.app.handlers.depsgraph_update_post, _on_depsgraph_update))


def register_handler():
    """Draws previews in every 3D viewport; nothing in background mode (no GPU, nothing to see)."""
    global _handle
    if bpy.app.background:
        return
    if _handle is None:
        _handle = bpy.types.SpaceView3D.draw_handler_add(_draw, (), 'WINDOW', 'POST_VIEW')
    for handlers, handler in _HANDLERS:
        if handler not in handlers():
            handlers().append(handler)
    # bpy.data is not readable while add-ons register: look for packed assets just after.
    bpy.app.timers.register(_attach_after_register, first_interval=0.0)


def unregister_handler():
    global _handle
    for handlers, handler in _HANDLERS:
        if handler in handlers():
            handlers().remove(handler)
    if bpy.app.timers.is_registered(_attach_after_register):
        bpy.app.timers.unregister(_attach_after_register)
    if _handle is not None:
        bpy.types.SpaceView3D.draw_handler_remove(_handle, 'WINDOW')
        _handle = None
    _previews.clear()
    _shaders.clear()
