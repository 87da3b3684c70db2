"""Blender side of hairlod: the only package that imports bpy."""

import bpy

from .lod_operator import HAIRLOD_OT_build_lod
from .operators import HAIRLOD_OT_export_hair, HAIRLOD_OT_import_hair, menu_func_export, menu_func_import
from .panels import VIEW3D_PT_hairlod

classes = (
    HAIRLOD_OT_import_hair,
    HAIRLOD_OT_export_hair,
    HAIRLOD_OT_build_lod,
    VIEW3D_PT_hairlod,
)


def register():
    for cls in classes:
        bpy.utils.register_class(cls)
    bpy.types.TOPBAR_MT_file_import.append(menu_func_import)
    bpy.types.TOPBAR_MT_file_export.append(menu_func_export)


def unregister():
    bpy.types.TOPBAR_MT_file_export.remove(menu_func_export)
    bpy.types.TOPBAR_MT_file_import.remove(menu_func_import)
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
