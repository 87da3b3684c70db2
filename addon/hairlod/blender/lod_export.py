"""Export Hair LoD: the active object's packed LoD asset and its baked BCSDF tables to a folder."""

import bpy
from bpy.props import BoolProperty, StringProperty


class HAIRLOD_OT_export_lod(bpy.types.Operator):
    """Write the active object's LoD asset (one .hair of thick hairs per level, manifest, arrays) and
    the BCSDF lookup tables baked for its hair material (OpenEXR + manifest) into a folder"""

    bl_idname = "hairlod.export_lod"
    bl_label = "Export Hair LoD"
    bl_options = {'REGISTER'}

    directory: StringProperty(subtype='DIR_PATH')
    bake: BoolProperty(name="Bake BCSDF Tables", description="Also bake the aggregated BCSDF's lookup tables "
                       "for the object's Principled Hair BSDF", default=True)
    animation: BoolProperty(name="Guide Animation", description="Also store the guides at every frame of the scene's "
                            "frame range (guide_animation.npy in the LoD folder): the asset's skinning turns them "
                            "into the strands and thick hairs of each frame", default=False)

    @classmethod
    def poll(cls, context):
        from .packed_asset import PACKED_PROPERTY

        obj = context.active_object
        return obj is not None and PACKED_PROPERTY in obj

    def invoke(self, context, event):
        context.window_manager.fileselect_add(self)
        return {'RUNNING_MODAL'}

    def execute(self, context):
        from .pipeline import export_lod

        obj = context.active_object
        if not self.directory:
            self.report({'ERROR'}, "Export Hair LoD: no folder chosen")
            return {'CANCELLED'}
        scene = context.scene
        frames = range(scene.frame_start, scene.frame_end + 1, scene.frame_step) if self.animation else None
        window_manager = context.window_manager
        if frames is not None:
            window_manager.progress_begin(0, len(frames))
        try:
            summary = export_lod(obj, self.directory, bake=self.bake, frames=frames,
                                 progress=lambda done, total: window_manager.progress_update(done))
        except (OSError, ValueError, RuntimeError) as error:
            self.report({'ERROR'}, f"Cannot export the hair LoD of {obj.name}: {error}")
            return {'CANCELLED'}
        finally:
            if frames is not None:
                window_manager.progress_end()
        baked = f" and BCSDF tables ({summary['material']})" if self.bake else ""
        animated = f", guides of {summary['frames']} frames" if summary["frames"] else ""
        self.report({'INFO'}, f"Exported {len(summary['levels'])} thick levels{baked}{animated} to {self.directory}")
        return {'FINISHED'}
