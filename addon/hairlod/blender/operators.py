"""File > Import / Export operators for hair files."""

import os

import bpy
from bpy.props import FloatProperty, StringProperty
from bpy_extras.io_utils import ExportHelper, ImportHelper

from .. import io


def _file_filter(formats):
    return ";".join("*" + extension for extension in formats)


class HAIRLOD_OT_import_hair(bpy.types.Operator, ImportHelper):
    """Import a hair file as a hair Curves object"""

    bl_idname = "hairlod.import_hair"
    bl_label = "Import Hair File"
    bl_options = {'REGISTER', 'UNDO'}

    filter_glob: StringProperty(default=_file_filter(io.READ_FORMATS), options={'HIDDEN'})

    default_radius: FloatProperty(
        name="Default Radius",
        description="Radius of the points for formats that store no thickness "
                    "(0: 1/10000 of the bounding box diagonal)",
        default=0.0,
        min=0.0,
        precision=5,
        unit='LENGTH',
    )

    def execute(self, context):
        from .curves import strands_to_curves

        name = os.path.splitext(os.path.basename(self.filepath))[0]
        window_manager = context.window_manager
        window_manager.progress_begin(0, 2)
        try:
            strands = io.read(self.filepath, default_radius=self.default_radius or None)
            window_manager.progress_update(1)
            obj = strands_to_curves(strands, name, context.collection)
        except Exception as error:  # reported to the user; strands_to_curves leaves nothing behind
            self.report({'ERROR'}, f"Cannot import {self.filepath}: {error}")
            return {'CANCELLED'}
        finally:
            window_manager.progress_end()

        for selected in context.selected_objects:
            selected.select_set(False)
        obj.select_set(True)
        context.view_layer.objects.active = obj
        self.report({'INFO'}, f"Imported {len(strands):,} strands, {strands.point_count:,} points")
        return {'FINISHED'}


class HAIRLOD_OT_export_hair(bpy.types.Operator, ExportHelper):
    """Export the active hair Curves object (with its modifiers) to a hair file"""

    bl_idname = "hairlod.export_hair"
    bl_label = "Export Hair File"

    filename_ext = ".hair"
    filter_glob: StringProperty(default=_file_filter(io.WRITE_FORMATS), options={'HIDDEN'})

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        return obj is not None and obj.type == 'CURVES'

    def invoke(self, context, event):
        if not self.filepath:
            self.filepath = bpy.path.clean_name(context.active_object.name) + self.filename_ext
        return ExportHelper.invoke(self, context, event)

    def check(self, context):
        # The typed extension picks the format; anything else gets the default one.
        if os.path.splitext(self.filepath)[1].lower() in io.WRITE_FORMATS:
            return False
        self.filepath += self.filename_ext
        return True

    def execute(self, context):
        from .curves import curves_to_strands

        window_manager = context.window_manager
        window_manager.progress_begin(0, 2)
        try:
            strands = curves_to_strands(context.active_object, depsgraph=context.evaluated_depsgraph_get())
            window_manager.progress_update(1)
            io.write(self.filepath, strands)
        except Exception as error:  # reported to the user; io.write leaves no partial file
            self.report({'ERROR'}, f"Cannot export {self.filepath}: {error}")
            return {'CANCELLED'}
        finally:
            window_manager.progress_end()
        self.report({'INFO'}, f"Exported {len(strands):,} strands, {strands.point_count:,} points")
        return {'FINISHED'}


def _menu_text(formats):
    return f"Hair Strands ({', '.join(formats)})"


def menu_func_import(self, context):
    self.layout.operator(HAIRLOD_OT_import_hair.bl_idname, text=_menu_text(io.READ_FORMATS))


def menu_func_export(self, context):
    self.layout.operator(HAIRLOD_OT_export_hair.bl_idname, text=_menu_text(io.WRITE_FORMATS))
