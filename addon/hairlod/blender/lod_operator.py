"""Build Hair LoD: the active hair Curves object -> its LoD asset, packed into the object (and, on
request, one hidden, non-rendering Curves object per thick level).

Its parameters live on the object (HAIRLOD_PG_lod_build, drawn in the sidebar) and are the
operator's defaults: a parameter the caller does not pass comes from the active object's settings.

The build runs in a worker thread (the C++ build releases the GIL) polled from a modal timer, with a
progress bar; Esc cancels it and removes whatever it had made. The asset is packed into the source
object (custom property PACKED_PROPERTY), so it is saved with the .blend; packed_asset() reads it.
"""

import threading

import bpy
import numpy as np
from bpy.props import BoolProperty, FloatProperty, IntProperty

COLLECTION_NAME = "Hair LoD"
PACKED_PROPERTY = "hairlod_lod_asset"
# Share of the progress bar for the build; the rest is for making the level objects.
BUILD_SHARE = 0.8


def _level_strands(level, level_id):
    """A thick level as Strands with the attributes artists and shaders read."""
    from .. import Strands

    hairs, control_points = level.centres.shape[:2]
    strands = Strands.from_counts(level.centres.reshape(-1, 3), np.full(hairs, control_points),
                                  np.ascontiguousarray(level.radii[..., 0].reshape(-1)))
    strands.set_attribute("major_radius", np.ascontiguousarray(level.radii[..., 0].reshape(-1)))
    strands.set_attribute("minor_radius", np.ascontiguousarray(level.radii[..., 1].reshape(-1)))
    strands.set_attribute("major_axis", np.ascontiguousarray(level.major_axis.reshape(-1, 3)))
    strands.set_attribute("minor_axis", np.ascontiguousarray(level.minor_axis.reshape(-1, 3)))
    strands.set_attribute("density", np.ascontiguousarray(level.density.reshape(-1)))
    # Curve-domain attributes are floats in Blender's hair attributes, like the rest.
    strands.set_attribute("n_total", level.n_total.astype(np.float32), domain="curve")
    cluster = np.repeat(np.arange(len(level.cluster_first) - 1), np.diff(level.cluster_first))
    strands.set_attribute("cluster", cluster.astype(np.float32), domain="curve")
    strands.set_attribute("level", np.full(hairs, level_id, np.float32), domain="curve")
    return strands


def scene_cameras(context, source, frame_step=1):
    """Every camera object of the scene at every frame_step-th frame of frame_start..frame_end, as
    hairlod.lod cameras in the source object's space (view = camera^-1 x source) at the render
    resolution. The current frame is restored."""
    scene, render = context.scene, context.scene.render
    scale = render.resolution_percentage / 100.0
    width, height = max(1, round(render.resolution_x * scale)), max(1, round(render.resolution_y * scale))
    camera_objects = [obj for obj in scene.objects if obj.type == 'CAMERA']
    original_frame, original_subframe = scene.frame_current, scene.frame_subframe
    cameras = []
    try:
        for frame in range(scene.frame_start, scene.frame_end + 1, max(1, frame_step)):
            scene.frame_set(frame)
            depsgraph = context.evaluated_depsgraph_get()
            to_world = np.array(source.evaluated_get(depsgraph).matrix_world)
            for camera in camera_objects:
                evaluated = camera.evaluated_get(depsgraph)
                projection = evaluated.calc_matrix_camera(depsgraph, x=width, y=height, scale_x=render.pixel_aspect_x,
                                                          scale_y=render.pixel_aspect_y)
                cameras.append({"view": np.array(evaluated.matrix_world.inverted()) @ to_world,
                                "projection": np.array(projection), "viewport": (float(width), float(height))})
    finally:
        scene.frame_set(original_frame, subframe=original_subframe)
    return cameras


def packed_asset(obj):
    """The LoD asset packed into `obj` by Build Hair LoD (None if it has none)."""
    from .. import lod

    data = obj.get(PACKED_PROPERTY)
    return None if data is None else lod.unpack(data, where=f"object {obj.name}: {PACKED_PROPERTY}")


def store_packed_asset(obj, asset):
    """Packs `asset` into `obj` (replacing what a previous build packed there)."""
    from .. import lod

    # Blender 4.3 cuts bytes assigned over an existing bytes property at their first NUL (a fresh
    # property keeps them whole), so the old one is removed first.
    if PACKED_PROPERTY in obj:
        del obj[PACKED_PROPERTY]
    obj[PACKED_PROPERTY] = lod.pack(asset)


class LodBuildJob:
    """Build Hair LoD in steps. The constructor reads the strands (and the scene's cameras) and
    starts the build in a worker thread; step() does the next piece of main-thread work and returns
    True when all is done; cancel() stops the build and removes everything the job made."""

    def __init__(self, context, source, guides=0, levels=6, control_points=16, seed=0, scene_cameras_only=False,
                 frame_step=1, width_px=2.0, level_objects=False):
        from .. import lod
        from .curves import curves_to_strands

        self.source, self.scene, self.width_px, self.level_objects = source, context.scene, width_px, level_objects
        strands = curves_to_strands(source, depsgraph=context.evaluated_depsgraph_get())
        self.cameras = None
        if scene_cameras_only:
            self.cameras = scene_cameras(context, source, frame_step)
            if not self.cameras:
                raise ValueError("'Cameras Only' is on but the scene has no camera")
        self.progress = lod.BuildProgress()
        self.asset, self.error, self.selected_levels = None, None, None
        self.collection, self.created_collection, self.created = None, False, []
        self._levels_made = 0
        options = {"guides": guides, "levels": levels, "control_points": control_points, "seed": seed}
        self._thread = threading.Thread(target=self._build, args=(strands, options), daemon=True)
        self._thread.start()

    def _build(self, strands, options):
        from .. import lod

        try:
            self.asset = lod.build_lod(strands, progress=self.progress, **options)
        except BaseException as error:  # handed to the main thread by step()
            self.error = error

    @property
    def fraction(self):
        """Progress in [0, 1]."""
        built = self.progress.done / max(1, self.progress.total)
        if not self.level_objects:
            return built if self.asset is None else 1.0
        if self.asset is None:
            return BUILD_SHARE * built
        return BUILD_SHARE + (1 - BUILD_SHARE) * self._levels_made / max(1, len(self.asset.levels))

    def step(self):
        from .. import lod
        from .curves import strands_to_curves

        if self._thread.is_alive():
            return False
        if self.error is not None:
            raise self.error
        if self.cameras is not None and self.selected_levels is None:
            self.asset, self.selected_levels = lod.keep_scene_levels(self.asset, self.cameras, self.width_px)
        if not self.level_objects:
            store_packed_asset(self.source, self.asset)
            return True
        if self.collection is None:
            self.collection = bpy.data.collections.get(COLLECTION_NAME)
            if self.collection is None:
                self.created_collection = True
                self.collection = bpy.data.collections.new(COLLECTION_NAME)
                self.scene.collection.children.link(self.collection)
            return False
        if self._levels_made < len(self.asset.levels):
            level_id = self.asset.level_ids[self._levels_made]
            obj = strands_to_curves(_level_strands(self.asset.levels[self._levels_made], level_id),
                                    f"{self.source.name} LoD L{level_id}", self.collection)
            obj.matrix_world = self.source.matrix_world
            # Data for engines and scripts, not a second drawing of the hair: the preview shows the LoD, the
            # source renders.
            obj.hide_render = True
            obj.hide_set(True)
            self.created.append(obj)
            self._levels_made += 1
            return False
        store_packed_asset(self.source, self.asset)
        return True

    def cancel(self):
        """Stops the build (at its next step) and removes the objects and collection made so far."""
        self.progress.cancel()
        self._thread.join()
        for obj in self.created:
            data = obj.data
            bpy.data.objects.remove(obj)
            bpy.data.hair_curves.remove(data)
        self.created = []
        if self.created_collection and self.collection is not None:
            bpy.data.collections.remove(self.collection)
        self.collection, self.created_collection = None, False

    def run(self):
        """All steps now (blocking), for scripts; cancels and re-raises on an error."""
        try:
            while not self.step():
                self._thread.join()
        except BaseException:
            self.cancel()
            raise


def _build_properties(options):
    """The build's parameters as property annotations: stored per object (the sidebar's settings)
    and on the operator (its redo panel), declared once."""
    return {
        "guides": IntProperty(name="Guides", description="Guide hairs chosen by k-means (0: automatic, one per 128 "
                              "strands, 16 to 256)", default=0, min=0,
                              options=options),
        "levels": IntProperty(name="Levels", description="LoD levels including the strands themselves",
                              default=6, min=2, max=16, options=options),
        "control_points": IntProperty(name="Points", description="Control points per hair", default=16,
                                      min=2, max=64, options=options),
        "seed": IntProperty(name="Seed", description="Random seed of the k-means seeding", default=0, min=0,
                            options=options),
        "scene_cameras": BoolProperty(
            name="Cameras Only",
            description="Keep only the levels that some camera of the scene selects over the frame range "
                        "(at the render resolution, every Frame Step frames)", default=False, options=options),
        "frame_step": IntProperty(name="Frame Step", description="Frames between camera samples", default=1, min=1,
                                  options=options),
        "width_px": FloatProperty(name="Width (px)", description="Screen width threshold of the level selection",
                                  default=2.0, min=0.01, options=options),
        "level_objects": BoolProperty(
            name="Level Objects", description="Also add one Curves object per thick level to the \"Hair LoD\" "
            "collection, hidden and not rendered (the preview draws the LoD; Export Hair LoD writes the levels "
            "either way)", default=False, options=options),
    }


BUILD_PROPERTIES = tuple(_build_properties(set()))


class HAIRLOD_PG_lod_build(bpy.types.PropertyGroup):
    """Build Hair LoD's parameters of one hair object, set in the sidebar before the build."""

    __annotations__ = _build_properties({'ANIMATABLE'})


class HAIRLOD_OT_build_lod(bpy.types.Operator):
    """Build guide hairs, clusters and elliptical thick hairs from the active hair Curves object and
    preview them in the viewport (Esc cancels)"""

    bl_idname = "hairlod.build_lod"
    bl_label = "Build Hair LoD"
    bl_options = {'REGISTER', 'UNDO'}

    # SKIP_SAVE: a parameter the caller leaves unset comes from the object's settings (the sidebar),
    # not from the operator's previous run; redo passes every parameter, so it repeats the build.
    __annotations__ = _build_properties({'SKIP_SAVE'})

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        return obj is not None and obj.type == 'CURVES'

    def _start(self, context):
        source = context.active_object
        settings = source.hairlod_lod_build
        for name in BUILD_PROPERTIES:
            if not self.properties.is_property_set(name):
                setattr(self, name, getattr(settings, name))
        try:
            return LodBuildJob(context, source, self.guides, self.levels, self.control_points, self.seed,
                               self.scene_cameras, self.frame_step, self.width_px, self.level_objects)
        except Exception as error:
            self.report({'ERROR'}, f"Cannot build the hair LoD of {source.name}: {error}")
            return None

    def _finish(self, job):
        if not bpy.app.background:
            from .preview import lod_preview

            lod_preview.attach(job.source, job.asset, packed=True)
        coverage = ", ".join(f"{c:.3f}" for c in job.asset.coverage)
        objects = f", {len(job.created)} level objects" if job.created else ""
        self.report({'INFO'}, f"Built {len(job.asset.levels)} thick levels from {job.asset.strand_count:,} strands "
                              f"({job.asset.cluster_count} clusters{objects}; coverage {coverage})")
        return {'FINISHED'}

    def execute(self, context):
        job = self._start(context)
        if job is None:
            return {'CANCELLED'}
        try:
            job.run()
        except Exception as error:  # run() removed what it made
            self.report({'ERROR'}, f"Cannot build the hair LoD of {job.source.name}: {error}")
            return {'CANCELLED'}
        return self._finish(job)

    def invoke(self, context, event):
        if context.window is None:  # no window to run a modal timer in (background mode)
            return self.execute(context)
        self._job = self._start(context)
        if self._job is None:
            return {'CANCELLED'}
        from .preview import lod_preview

        # The preview will replace the hair's drawing: replaced now, the viewport does not redraw every
        # strand while the build runs beside it (on a software GPU that halved the build's speed).
        if self._job.source.hairlod_lod_preview.enabled:
            lod_preview.replace_source_display(self._job.source, True)
        window_manager = context.window_manager
        self._shaders_ready = False
        self._timer = window_manager.event_timer_add(0.1, window=context.window)
        window_manager.progress_begin(0, 100)
        window_manager.modal_handler_add(self)
        return {'RUNNING_MODAL'}

    def modal(self, context, event):
        if event.type == 'ESC':
            self.cancel(context)
            self.report({'WARNING'}, "Build Hair LoD cancelled")
            return {'CANCELLED'}
        if event.type != 'TIMER':
            return {'PASS_THROUGH'}
        if not self._shaders_ready:
            # Compiled and linked while the build runs, not in the preview's first frame (Mesa's llvmpipe
            # still generates its own code at the first draw: first frame 3.6 -> 3.1 s, 100k strands).
            from .preview import lod_preview

            lod_preview.compile_shaders()
            self._shaders_ready = True
        try:
            done = self._job.step()
        except Exception as error:
            self.cancel(context)
            self.report({'ERROR'}, f"Cannot build the hair LoD of {self._job.source.name}: {error}")
            return {'CANCELLED'}
        percent = round(100 * self._job.fraction)
        context.window_manager.progress_update(percent)
        if context.workspace is not None:
            context.workspace.status_text_set(f"Building hair LoD of {self._job.source.name}: {percent}% (Esc cancels)")
        if not done:
            return {'RUNNING_MODAL'}
        self._end_modal(context)
        return self._finish(self._job)

    def _end_modal(self, context):
        window_manager = context.window_manager
        window_manager.event_timer_remove(self._timer)
        window_manager.progress_end()
        if context.workspace is not None:
            context.workspace.status_text_set(None)

    def cancel(self, context):
        """Esc, an error, or Blender cancelling the modal operator: nothing half-made stays behind."""
        from .preview import lod_preview

        self._end_modal(context)
        self._job.cancel()
        source = self._job.source
        lod_preview.replace_source_display(source, source.hairlod_lod_preview.enabled and
                                           lod_preview.preview_of(source) is not None)


def register_properties():
    bpy.types.Object.hairlod_lod_build = bpy.props.PointerProperty(type=HAIRLOD_PG_lod_build)


def unregister_properties():
    del bpy.types.Object.hairlod_lod_build
