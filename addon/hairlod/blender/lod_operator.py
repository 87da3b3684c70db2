"""Build Hair LoD: the active hair Curves object -> its LoD asset, packed into the object (and, on
request, one hidden, non-rendering Curves object per thick level).

Its parameters live on the object (HAIRLOD_PG_lod_build, drawn in the sidebar) and are the
operator's defaults: a parameter the caller does not pass comes from the active object's settings.

The build (LodBuildJob) runs in a worker thread polled from a modal timer, with a progress bar; Esc
cancels it and removes whatever it had made.
"""

import bpy

from .lod_build_job import LodBuildJob
from .lod_build_settings import BUILD_PROPERTIES, build_property_annotations


class HAIRLOD_OT_build_lod(bpy.types.Operator):
    """Build guide hairs, clusters and elliptical thick hairs from the active hair Curves object and
    preview them in the viewport (Esc cancels)"""

    bl_idname = "hairlod.build_lod"
    bl_label = "Build Hair LoD"
    bl_options = {'REGISTER', 'UNDO'}

    # SKIP_SAVE: a parameter the caller leaves unset comes from the object's settings (the sidebar),
    # not from the operator's previous run; redo passes every parameter, so it repeats the build.
    __annotations__ = build_property_annotations({'SKIP_SAVE'})

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
                               self.scene_cameras, self.frame_step, source.hairlod_lod_preview.width_px,
                               self.level_objects)
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
        # Nothing in the viewport changes until the build is done (the preview then replaces the hair's
        # drawing): a change makes Blender redraw a viewport once per sample of its anti-aliasing (8 by
        # default), which on a software GPU took the CPU from the build (1.56-1.67x the direct call with
        # the source shown as its bounds from the start, 1.16-1.24x without; docs/preview.md).
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
