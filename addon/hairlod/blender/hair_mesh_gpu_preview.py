"""Viewport strands of hair meshes, drawn by a SpaceView3D draw handler (GPU preview).

For every visible hair-mesh object whose Viewport Strands setting is on, the strands generated from
it are drawn as shaded lines (preview.strand_batch) in its object space, so transforms only move
them. A ``depsgraph_update_post`` handler reads the hair mesh when the object changes (edit-mode
edits, settings); the draw callback regenerates lazily, once per redraw at most, when the hair
mesh, the settings or the level of detail changed. The level of detail follows the camera
distance (hair-meshes-realtime.txt Eq. 7), quantised to quarter octaves so that orbiting the view
regenerates only when the level moves by about 19 %. With several 3D views the nearest one sets
the level of the one set of strands that all of them draw, so views never take turns regenerating.
"""

import math
import time

import bpy
import numpy as np
from bpy.app.handlers import persistent

from .strand_settings import StrandSettings

# Root and tip colours of the shading ramp (linear RGB); the root's alpha is the ambient fraction.
ROOT_COLOUR = (0.10, 0.06, 0.035, 0.35)
TIP_COLOUR = (0.55, 0.38, 0.22, 1.0)
# Steps of the level of detail per octave: a regeneration happens when the level crosses a step.
LOD_STEPS_PER_OCTAVE = 4


class PreviewState:
    """What the preview of one hair-mesh object holds between redraws."""

    def __init__(self):
        from .preview.strand_batch import StrandBatch

        self.hair_mesh = None
        self.mesh_key = None          # bytes of the hair mesh arrays that self.hair_mesh holds
        self.error = None             # the reason why the current hair mesh cannot be previewed
        self.generator = None
        self.generator_key = None
        self.drawn_key = None         # (mesh key, settings, level) of the strands in self.batch
        self.batch = StrandBatch()
        self.strands = None           # the generator's output, overwritten in place by each regeneration
        self.level = 1.0
        self.timings = {}             # seconds of the last regeneration: generate_s, upload_s


_states = {}
_draw_handle = None


def preview_state(obj):
    """The PreviewState of ``obj`` (None before its first update)."""
    return _states.get(obj.name)


def read_hair_mesh(obj):
    """Reads the hair mesh of ``obj`` into its state; keeps the previous one while the mesh is
    invalid (mid-edit states often are) and records why."""
    from .hair_mesh import hair_mesh_from_object

    state = _states.setdefault(obj.name, PreviewState())
    try:
        hair_mesh = hair_mesh_from_object(obj)
    except ValueError as error:
        state.error = str(error)
        return state
    key = (hair_mesh.layers.tobytes(), hair_mesh.face_vertices.tobytes(), hair_mesh.face_sizes.tobytes(),
           None if hair_mesh.uv is None else hair_mesh.uv.tobytes())
    if key != state.mesh_key:
        state.hair_mesh, state.mesh_key = hair_mesh, key
    state.error = None
    return state


def world_bounds(obj):
    """(lower, upper) corners of the world-space box around the object's local bounding box."""
    corners = np.array([tuple(corner) for corner in obj.bound_box], np.float64)
    matrix = np.array(obj.matrix_world, np.float64)
    world = corners @ matrix[:3, :3].T + matrix[:3, 3]
    return world.min(axis=0), world.max(axis=0)


def camera_detail_level(bounds, view_matrix, window_matrix, is_perspective, resolution_px, full_detail_px):
    """Level of detail L of Eq. 7 (hair-meshes-realtime.txt), L = min(1, alpha h R / (d tan theta)),
    for a model in the world box ``bounds`` seen by a view with these matrices.

    h is the box diagonal, R the view height in pixels, d the distance from the viewpoint to the
    nearest point of the box, and tan(theta) the view height per unit distance, 2 / P[1][1] of the
    projection P (for an orthographic view d tan(theta) is the view height 2 / P[1][1], as the paper
    says). alpha = 1 / full_detail_px: L = 1 while the model spans at least that many pixels.
    """
    from ..hairmesh import detail_level

    lower, upper = (np.asarray(corner, np.float64) for corner in bounds)
    model_size = float(np.linalg.norm(upper - lower))
    view_height_per_distance = 2.0 / float(window_matrix[1][1])
    if is_perspective:
        viewpoint = np.array(view_matrix.inverted().translation, np.float64)
        distance = float(np.linalg.norm(viewpoint - np.clip(viewpoint, lower, upper)))
    else:
        distance = 1.0
    if model_size <= 0.0 or distance <= 0.0:
        return 1.0
    return detail_level(model_size, float(resolution_px), distance, math.atan(view_height_per_distance),
                        1.0 / float(full_detail_px))


def quantised_level(level):
    """``level`` rounded to the nearest of 2^(-k / LOD_STEPS_PER_OCTAVE), at most 1."""
    steps = round(-math.log2(max(level, 1e-6)) * LOD_STEPS_PER_OCTAVE)
    return min(1.0, 2.0 ** (-max(steps, 0) / LOD_STEPS_PER_OCTAVE))


def regenerate(obj, state, level):
    """Regenerates the strands of ``obj`` at camera level ``level`` if anything changed; returns True
    when it did. Raises ValueError or RuntimeError for settings the generator rejects."""
    from ..hairmesh import resolve_inputs, strand_generator

    settings = obj.hairlod_strands
    values = tuple(getattr(settings, key) for key in StrandSettings.__annotations__)
    key = (state.mesh_key, values, level)
    if state.hair_mesh is None or key == state.drawn_key:
        return False
    start = time.perf_counter()
    generator_key = (state.mesh_key, settings.count, settings.seed, settings.subdivision)
    if generator_key != state.generator_key:
        # After an edit of the mesh alone the root sample sets usually stay the same: reuse them.
        same_roots = state.generator_key is not None and state.generator_key[1:] == generator_key[1:]
        state.generator = strand_generator(state.hair_mesh, settings.count, settings.seed, settings.subdivision,
                                           reuse=state.generator if same_roots else None)
        state.generator_key = generator_key
    mesh, styling, radius = resolve_inputs(state.generator.mesh, settings.styling())
    strand_lod = settings.lod * level
    # Reusing the previous output's memory saves its page faults (about as long as generating);
    # nothing keeps views of it, the batch copies what it needs.
    state.strands = state.generator.generate(vertices=int(settings.vertices), styling=styling,
                                             strand_lod=strand_lod, vertex_lod=strand_lod, radius=radius,
                                             out=state.strands)
    generated = time.perf_counter()
    strands = state.strands
    state.batch.update(strands.points, strands.attribute("tangent"), strands.offsets)
    state.timings = {"generate_s": generated - start, "upload_s": time.perf_counter() - generated}
    state.drawn_key, state.level = key, level
    return True


def view_light_direction(view_matrix, matrix_world):
    """Unit direction towards a light above and left of the viewer, in the object space of
    ``matrix_world``: with tangents t transformed by the matrix's 3x3 part M, (M t) . l = t . (M^T l)."""
    camera_to_world = np.array(view_matrix.inverted(), np.float64)[:3, :3]
    light_world = camera_to_world @ np.array([-0.4, 0.5, 1.0])
    light = np.array(matrix_world, np.float64)[:3, :3].T @ light_world
    norm = np.linalg.norm(light)
    return tuple(light / norm) if norm > 0.0 else (0.0, 0.0, 1.0)


def open_views(context):
    """(WINDOW region, RegionView3D) of every 3D view open in any window, quad views included."""
    window_manager = context.window_manager
    for window in (window_manager.windows if window_manager else ()):
        for area in window.screen.areas:
            if area.type != 'VIEW_3D':
                continue
            region = next((r for r in area.regions if r.type == 'WINDOW'), None)
            space = area.spaces.active
            if region is None or space is None:
                continue
            for region_3d in (space.region_3d, *space.region_quadviews):
                yield region, region_3d


def views_detail_level(obj, context, region, region_data):
    """The quantised level of detail the nearest open 3D view needs for ``obj`` (the drawing view's
    when the window manager lists none, as in some offscreen draws)."""
    bounds = world_bounds(obj)
    full_detail_px = obj.hairlod_strands.full_detail_px
    views = list(open_views(context)) or [(region, region_data)]
    return max(quantised_level(camera_detail_level(bounds, view.view_matrix, view.window_matrix, view.is_perspective,
                                                   view_region.height, full_detail_px))
               for view_region, view in views)


def draw_previews():
    """POST_VIEW callback: draws the strands of every visible hair mesh with Viewport Strands on."""
    from .hair_mesh import is_hair_mesh_object

    context = bpy.context
    region, region_data = context.region, context.region_data
    if region is None or region_data is None or context.view_layer is None:
        return
    for obj in context.view_layer.objects:
        if not (obj.type == 'MESH' and obj.hairlod_strands.viewport_strands and obj.visible_get()
                and is_hair_mesh_object(obj)):
            continue
        state = _states.get(obj.name)
        if state is None or state.hair_mesh is None:
            continue  # the depsgraph handler or the toggle reads the mesh; drawing must not
        level = views_detail_level(obj, context, region, region_data)
        try:
            regenerate(obj, state, level)
        except (ValueError, RuntimeError) as error:
            state.error = str(error)
        state.batch.draw(region_data.perspective_matrix @ obj.matrix_world,
                         view_light_direction(region_data.view_matrix, obj.matrix_world), ROOT_COLOUR, TIP_COLOUR)


def tag_view3d_redraw():
    window_manager = bpy.context.window_manager
    for window in (window_manager.windows if window_manager else ()):
        for area in window.screen.areas:
            if area.type == 'VIEW_3D':
                area.tag_redraw()


def viewport_strands_toggled(settings, context):
    """Update callback of the Viewport Strands setting."""
    obj = settings.id_data
    if settings.viewport_strands:
        read_hair_mesh(obj)
    else:
        _states.pop(obj.name, None)
    tag_view3d_redraw()


@persistent
def update_viewport_strands(scene, depsgraph):
    from .hair_mesh import is_hair_mesh_object

    for update in depsgraph.updates:
        if not isinstance(update.id, bpy.types.Object):
            continue
        obj = update.id.original
        # Transforms alone change nothing the strands are made of: they are drawn in object space.
        if (update.is_updated_geometry and is_hair_mesh_object(obj) and obj.hairlod_strands.viewport_strands):
            read_hair_mesh(obj)


@persistent
def forget_previews(*_):
    _states.clear()


def register_handlers():
    global _draw_handle
    bpy.app.handlers.depsgraph_update_post.append(update_viewport_strands)
    bpy.app.handlers.load_pre.append(forget_previews)
    if not bpy.app.background:
        _draw_handle = bpy.types.SpaceView3D.draw_handler_add(draw_previews, (), 'WINDOW', 'POST_VIEW')


def unregister_handlers():
    global _draw_handle
    if _draw_handle is not None:
        bpy.types.SpaceView3D.draw_handler_remove(_draw_handle, 'WINDOW')
        _draw_handle = None
    bpy.app.handlers.load_pre.remove(forget_previews)
    bpy.app.handlers.depsgraph_update_post.remove(update_viewport_strands)
    _states.clear()
