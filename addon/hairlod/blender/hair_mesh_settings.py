"""The strand settings each hair-mesh object keeps (``Object.hairlod_strands``), shown and edited in
the sidebar: StrandSettings and the switches of the two strand previews. The switches' update
callbacks turn those previews on and off, so this property group sits above them, with the UI."""

import bpy
from bpy.props import BoolProperty, FloatProperty, PointerProperty

from . import hair_mesh_gpu_preview, hair_mesh_preview
from .strand_settings import StrandSettings


def _live_preview_toggled(settings, context):
    hair_mesh_preview.refresh_preview(settings.id_data)


def _viewport_strands_toggled(settings, context):
    hair_mesh_gpu_preview.viewport_strands_toggled(settings, context)


def _viewport_strands_changed(settings, context):
    hair_mesh_gpu_preview.tag_view3d_redraw()


class HAIRLOD_PG_strand_settings(StrandSettings, bpy.types.PropertyGroup):
    live_preview: BoolProperty(
        name="Live Preview",
        description="Regenerate a preview of at most a few thousand strands whenever the hair mesh changes",
        default=False,
        update=_live_preview_toggled,
    )
    viewport_strands: BoolProperty(
        name="Viewport Strands",
        description="Draw the generated strands in the 3D viewport (GPU), regenerated as the hair mesh is edited, "
                    "with fewer strands as the view moves away",
        default=False,
        update=_viewport_strands_toggled,
    )
    full_detail_px: FloatProperty(
        name="Full Detail Height",
        description="Viewport Strands: all strands are drawn while the hair mesh spans at least this many pixels; "
                    "fewer as it gets smaller on screen",
        default=400.0,
        min=1.0,
        soft_max=4000.0,
        subtype='PIXEL',
        update=_viewport_strands_changed,
    )


def register_properties():
    bpy.types.Object.hairlod_strands = PointerProperty(type=HAIRLOD_PG_strand_settings)


def unregister_properties():
    del bpy.types.Object.hairlod_strands
