"""The "Hair LoD" tab of the 3D viewport sidebar."""

import bpy

from .lod_operator import HAIRLOD_OT_build_lod
from .operators import HAIRLOD_OT_export_hair, HAIRLOD_OT_import_hair


class VIEW3D_PT_hairlod(bpy.types.Panel):
    bl_space_type = 'VIEW_3D'
    bl_region_type = 'UI'
    bl_category = "Hair LoD"
    bl_label = "Hair LoD"

    def draw(self, context):
        layout = self.layout
        row = layout.row(align=True)
        row.operator(HAIRLOD_OT_import_hair.bl_idname, text="Import", icon='IMPORT')
        row.operator(HAIRLOD_OT_export_hair.bl_idname, text="Export", icon='EXPORT')

        obj = context.active_object
        box = layout.box()
        if obj is None or obj.type != 'CURVES':
            box.label(text="No active hair curves", icon='INFO')
            return
        # Counts of the original data: evaluating modifiers inside draw() would be too slow.
        box.label(text=obj.name, icon='OUTLINER_OB_CURVES')
        column = box.column(align=True)
        column.label(text=f"Strands: {len(obj.data.curves):,}")
        column.label(text=f"Points: {len(obj.data.points):,}")
        box.operator(HAIRLOD_OT_build_lod.bl_idname, icon='MOD_PARTICLES')
