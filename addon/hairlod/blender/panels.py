"""The "Hair LoD" tab of the 3D viewport sidebar."""

import bpy

from .hair_mesh_operators import HAIRLOD_OT_generate_strands, HAIRLOD_OT_hair_mesh_from_faces
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
        draw_build_settings(box, obj)
        box.operator(HAIRLOD_OT_build_lod.bl_idname, icon='MOD_PARTICLES')


def draw_build_settings(layout, obj):
    """Build Hair LoD's parameters of `obj`, which the button uses for whatever it is not given."""
    settings = obj.hairlod_lod_build
    column = layout.column()
    column.use_property_split = True
    column.use_property_decorate = False
    block = column.column(align=True)
    for key in ("guides", "levels", "control_points", "seed"):
        block.prop(settings, key)
    # Check boxes with their names across the full width.
    options = layout.column(align=True)
    options.prop(settings, "scene_cameras")
    step = options.row(align=True)
    step.active = settings.scene_cameras
    step.prop(settings, "frame_step")
    # The preview's width, the one threshold of the object: Cameras Only keeps what it selects.
    step = options.row(align=True)
    step.active = settings.scene_cameras
    step.prop(obj.hairlod_lod_preview, "width_px")
    options.prop(settings, "level_objects")


class VIEW3D_PT_hairlod_hair_mesh(bpy.types.Panel):
    bl_space_type = 'VIEW_3D'
    bl_region_type = 'UI'
    bl_category = "Hair LoD"
    bl_label = "Hair Mesh"
    bl_parent_id = "VIEW3D_PT_hairlod"

    def draw(self, context):
        from .hair_mesh import is_hair_mesh_object

        layout = self.layout
        layout.operator(HAIRLOD_OT_hair_mesh_from_faces.bl_idname, icon='MOD_SOLIDIFY')
        obj = context.active_object
        if not is_hair_mesh_object(obj):
            layout.label(text="No active hair mesh", icon='INFO')
            return
        settings = obj.hairlod_strands
        column = layout.column()
        column.use_property_split = True
        column.use_property_decorate = False
        for group in (("count", "vertices", "seed", "subdivision", "lod"),
                      ("curl_radius", "curl_frequency", "wave_amplitude", "wave_frequency"),
                      ("clump_amount", "frizz_amplitude", "frizz_frequency", "trim_amount")):
            block = column.column(align=True)
            for key in group:
                block.prop(settings, key)
        row = layout.row(align=True)
        row.operator(HAIRLOD_OT_generate_strands.bl_idname, icon='OUTLINER_OB_CURVES')
        row.prop(settings, "live_preview", toggle=True, icon='HIDE_OFF')
        row = layout.row(align=True)
        row.prop(settings, "viewport_strands", toggle=True, icon='STRANDS')
        row.prop(settings, "full_detail_px", text="Full Detail")
        if settings.viewport_strands:
            from .hair_mesh_gpu_preview import preview_state

            state = preview_state(obj)
            if state is not None and state.error:
                layout.label(text=state.error, icon='ERROR')
            elif state is not None and state.timings:
                milliseconds = 1e3 * (state.timings["generate_s"] + state.timings["upload_s"])
                layout.label(text=f"{state.batch.strand_count:,} strands, LoD {state.level:.2f}, {milliseconds:.0f} ms",
                             icon='INFO')
