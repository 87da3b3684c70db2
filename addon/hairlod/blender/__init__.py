"""Blender side of hairlod: the only package that imports bpy.

Its modules sit in layers, each importing only its own layer or lower ones: settings (property
declarations), bridges (Blender data <-> hairlod's), jobs (the LoD build, the headless pipeline),
previews (draw and depsgraph handlers), UI (operators, panels). This registration module, on top,
imports them all; tests/python/test_import_layers.py holds the table and checks it.
"""

import bpy

from .hair_mesh_gpu_preview import register_handlers as register_gpu_preview
from .hair_mesh_gpu_preview import unregister_handlers as unregister_gpu_preview
from .hair_mesh_operators import HAIRLOD_OT_generate_strands, HAIRLOD_OT_hair_mesh_from_faces
from .hair_mesh_preview import register_handler, unregister_handler
from .hair_mesh_settings import HAIRLOD_PG_strand_settings, register_properties, unregister_properties
from .lod_build_settings import HAIRLOD_PG_lod_build
from .lod_build_settings import register_properties as register_lod_build_properties
from .lod_build_settings import unregister_properties as unregister_lod_build_properties
from .lod_export import HAIRLOD_OT_export_lod
from .lod_operator import HAIRLOD_OT_build_lod
from .lod_preview_ui import (HAIRLOD_OT_load_lod_preview, HAIRLOD_PG_lod_preview, VIEW3D_PT_hairlod_lod_preview)
from .lod_preview_ui import register_properties as register_lod_preview_properties
from .lod_preview_ui import unregister_properties as unregister_lod_preview_properties
from .operators import HAIRLOD_OT_export_hair, HAIRLOD_OT_import_hair, menu_func_export, menu_func_import
from .panels import VIEW3D_PT_hairlod, VIEW3D_PT_hairlod_hair_mesh
from .preview import lod_preview

classes = (
    HAIRLOD_OT_import_hair,
    HAIRLOD_OT_export_hair,
    HAIRLOD_PG_strand_settings,
    HAIRLOD_OT_hair_mesh_from_faces,
    HAIRLOD_OT_generate_strands,
    HAIRLOD_PG_lod_build,
    HAIRLOD_OT_build_lod,
    HAIRLOD_PG_lod_preview,
    HAIRLOD_OT_load_lod_preview,
    HAIRLOD_OT_export_lod,
    VIEW3D_PT_hairlod,
    VIEW3D_PT_hairlod_hair_mesh,
    VIEW3D_PT_hairlod_lod_preview,
)


def register():
    for cls in classes:
        bpy.utils.register_class(cls)
    register_properties()
    register_lod_preview_properties()
    register_lod_build_properties()
    register_handler()
    lod_preview.register_handler()
    register_gpu_preview()
    bpy.types.TOPBAR_MT_file_import.append(menu_func_import)
    bpy.types.TOPBAR_MT_file_export.append(menu_func_export)


def unregister():
    bpy.types.TOPBAR_MT_file_export.remove(menu_func_export)
    bpy.types.TOPBAR_MT_file_import.remove(menu_func_import)
    lod_preview.unregister_handler()
    unregister_gpu_preview()
    unregister_handler()
    unregister_lod_build_properties()
    unregister_lod_preview_properties()
    unregister_properties()
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
