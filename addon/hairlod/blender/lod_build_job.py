"""The LoD build of a hair Curves object as a job in steps (LodBuildJob): the Build Hair LoD operator
polls it from a modal timer, the headless pipeline (pipeline.build_lod) runs it to the end.

The build runs in a worker thread (the C++ build releases the GIL). The asset is packed into the source
object (packed_asset.py); on request the job also makes one hidden, non-rendering Curves object per
thick level in the "Hair LoD" collection. Cancelling removes whatever it had made.
"""

import threading

import bpy
import numpy as np

from .packed_asset import store_packed_asset

COLLECTION_NAME = "Hair LoD"
# Share of the progress bar for the build; the rest is for making the level objects.
BUILD_SHARE = 0.8


def _level_strands(level, level_id):
    """A thick level as Strands with the attributes artists and shaders read."""
    from .._core import Strands  # not from the hairlod package, whose register() imports hairlod.blender

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

class LodBuildJob:
    """Build Hair LoD in steps. The constructor reads the strands (and the scene's cameras) and
    starts the build in a worker thread; step() does the next piece of main-thread work and returns
    True when all is done; cancel() stops the build and removes everything the job made."""

    def __init__(self, context, source, guides, levels, control_points, seed, scene_cameras_only, frame_step,
                 width_px, level_objects):
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
