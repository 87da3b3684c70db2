"""Settings, operators and panel of the viewport LoD preview (preview/lod_preview.py)."""

import textwrap

import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, PointerProperty, StringProperty

from .. import lod, preview_buffers


def _redraw(self, context):
    from .preview import lod_preview

    lod_preview._tag_viewports()


def _enabled_changed(self, context):
    from .preview import lod_preview

    obj = self.id_data
    preview = lod_preview.preview_of(obj)
    lod_preview.replace_source_display(obj, self.enabled and preview is not None)
    if self.enabled and preview is not None:
        # The handlers read the hair only while the preview is on: catch up with the current frame.
        preview.read_guides(obj, context.evaluated_depsgraph_get())
    lod_preview._tag_viewports()


class HAIRLOD_PG_lod_preview(bpy.types.PropertyGroup):
    enabled: BoolProperty(name="LoD Preview", description="Draw the object's hair LoD in the viewport in place of "
                          "the object's own drawing (it draws as its bounds meanwhile; renders are unchanged)",
                          default=True, update=_enabled_changed)
    width_px: FloatProperty(name="Width (px)", description="Largest on-screen width of a thick hair, in "
                            "pixels (eps_w): smaller values draw finer levels. Build Hair LoD's Cameras Only "
                            "keeps the levels this width selects", default=lod.DEFAULT_WIDTH_PX,
                            min=lod.MIN_WIDTH_PX, soft_max=32.0, update=_redraw)
    vertex_tolerance_px: FloatProperty(name="Vertex LoD (px)", description="Strands far away are drawn through "
                                       "every 2nd, 4th, 8th or 16th control point where the chords stay within this "
                                       "many pixels of the points they skip; 0 draws every control point",
                                       default=preview_buffers.PREVIEW_VERTEX_TOLERANCE_PX, min=0.0, soft_max=2.0,
                                       update=_redraw)
    strand_coverage: BoolProperty(name="Strand Coverage", description="Draw each strand thinner than a pixel with the "
                                  "probability of its width, and each sparse thick hair with the share of its "
                                  "strip its strands cover, so that the hair covers as much of the view as in a "
                                  "render (off: every strand a pixel wide and every thick hair solid, sparse hair "
                                  "looks denser)",
                                  default=True, update=_redraw)
    overlay: EnumProperty(name="Overlay", description="How the preview colours the hair",
                          items=(('SHADED', "Shaded", "The aggregated BCSDF under the scene's sun and point lights"),
                                 ('LEVELS', "Levels", "Each LoD level in its own colour")),
                          default='SHADED', update=_redraw)
    use_material: BoolProperty(name="Material", description="Shade with the Principled Hair BSDF of the "
                               "object's material when it has one (else with the hair parameters below)",
                               default=True, update=_redraw)
    melanin: FloatProperty(name="Melanin", description="Melanin concentration (Principled Hair BSDF)",
                           default=0.5, min=0.0, max=1.0, subtype='FACTOR', update=_redraw)
    melanin_redness: FloatProperty(name="Melanin Redness", description="Pheomelanin share of the melanin",
                                   default=0.3, min=0.0, max=1.0, subtype='FACTOR', update=_redraw)
    roughness: FloatProperty(name="Roughness", description="Longitudinal roughness", default=0.3, min=0.01,
                             max=1.0, subtype='FACTOR', update=_redraw)
    radial_roughness: FloatProperty(name="Radial Roughness", description="Azimuthal roughness", default=0.3,
                                    min=0.01, max=1.0, subtype='FACTOR', update=_redraw)
    self_shadowing: FloatProperty(name="Shadowing", description="Self-shadowing of the lights and the world through the "
                                  "hair: the optical depth of the strands on the way (a deep opacity map per light for "
                                  "the first four lights) times this, each strand passing its forward-scattered light "
                                  "on (1: the strands' own; 0 disables)",
                                  default=1.0, min=0.0, soft_max=2.0, update=_redraw)
    world_lighting: EnumProperty(name="World", description="How the scene's world lights the shaded preview",
                                 items=(('SRBF', "SRBF", "The world fitted by SRBF lights (Xu et al. 2011) where "
                                         "it can be read (a colour or an equirectangular Environment Texture, whose "
                                         "sun becomes a light of its own), else ambient"),
                                        ('AMBIENT', "Ambient", "The world colour times the hair's albedo")),
                                 default='SRBF', update=_redraw)
    show_statistics: BoolProperty(name="Statistics", description="Show segments drawn per level and the draw "
                                  "time, GPU included (the preview then waits for the GPU each frame to time it)",
                                  default=False)


class HAIRLOD_OT_load_lod_preview(bpy.types.Operator):
    """Load an LoD folder written by Build Hair LoD or `python3 -m hairlod lod` and preview it on
    the active object"""

    bl_idname = "hairlod.load_lod_preview"
    bl_label = "Load LoD Asset"
    bl_options = {'REGISTER'}

    directory: StringProperty(subtype='DIR_PATH')

    @classmethod
    def poll(cls, context):
        return context.active_object is not None

    def invoke(self, context, event):
        context.window_manager.fileselect_add(self)
        return {'RUNNING_MODAL'}

    def execute(self, context):
        from .. import lod
        from .preview import lod_preview

        try:
            asset = lod.load(self.directory)
        except (OSError, ValueError) as error:
            self.report({'ERROR'}, f"Cannot load the LoD asset in {self.directory}: {error}")
            return {'CANCELLED'}
        obj = context.active_object
        lod_preview.attach(obj, asset)
        obj.hairlod_lod_preview.enabled = True
        self.report({'INFO'}, f"Previewing {len(asset.levels)} thick levels of {asset.strand_count:,} strands "
                              f"on {obj.name}")
        return {'FINISHED'}


class VIEW3D_PT_hairlod_lod_preview(bpy.types.Panel):
    bl_space_type = 'VIEW_3D'
    bl_region_type = 'UI'
    bl_category = "Hair LoD"
    bl_label = "LoD Preview"
    bl_parent_id = "VIEW3D_PT_hairlod"

    def draw(self, context):
        from .preview import lod_preview

        layout = self.layout
        obj = context.active_object
        row = layout.row(align=True)
        row.operator(HAIRLOD_OT_load_lod_preview.bl_idname, text="Load", icon='FILEBROWSER')
        row.operator("hairlod.export_lod", text="Export", icon='EXPORT')
        preview = lod_preview.preview_of(obj) if obj is not None else None
        if preview is None:
            layout.label(text="Build or load an LoD", icon='INFO')
            return
        settings = obj.hairlod_lod_preview
        # One toggle: on, the LoD replaces the object's drawing; off, the object's own display returns.
        layout.prop(settings, "enabled", toggle=True, icon='HIDE_OFF' if settings.enabled else 'HIDE_ON')
        column = layout.column()
        column.active = settings.enabled
        column.use_property_split = True
        column.use_property_decorate = False
        column.prop(settings, "width_px")
        column.prop(settings, "vertex_tolerance_px")
        column.prop(settings, "strand_coverage")
        column.prop(settings, "overlay")
        if settings.overlay == 'SHADED':
            column.prop(settings, "self_shadowing")
            column.prop(settings, "world_lighting")
            if preview.world_status:
                for line in _wrapped(preview.world_status, context):
                    column.label(text=line)
            column.prop(settings, "use_material")
            # Sliders with their names inside (the full width): greyed out while a material shades the hair.
            material = column.column(align=True)
            material.use_property_split = False
            material.active = settings.enabled and not lod_preview.uses_material(obj, settings)
            for key in ("melanin", "melanin_redness", "roughness", "radial_roughness"):
                material.prop(settings, key, slider=True)
        if preview.follow_status:  # the hair no longer matches the asset: it is not followed
            for index, line in enumerate(_wrapped(preview.follow_status, context)):
                column.label(text=line, icon='ERROR' if index == 0 else 'BLANK1')
        column.prop(settings, "show_statistics")
        if settings.show_statistics and preview.stats:
            stats = preview.stats
            box = layout.box().column(align=True)
            box.label(text=f"Segments drawn: {stats['segments']:,}")
            box.label(text=f"  of {stats['selected_segments']:,} selected")
            for level, count in enumerate(stats["segments_per_level"]):
                name = "strands" if level == preview.level_count - 1 else f"L{preview.asset.level_ids[level]}"
                box.label(text=f"  {name}: {count:,}")
            box.label(text=f"Selection {stats['select_ms']:.2f} ms")
            box.label(text=f"Draw {stats['draw_ms']:.2f} ms" + (" with GPU" if stats.get("gpu_timed") else " (CPU)"))
            follow = preview.follow_stats
            if "skin_ms" in follow:  # the hair moved since the build: the last frame it followed
                box.label(text=f"Following: read {follow['read_ms']:.1f} ms, skin {follow['skin_ms']:.1f} ms, "
                               f"upload {follow['upload_ms']:.1f} ms")
            if "surface" in follow:  # the hair is attached to a mesh: how its strands follow it
                for line in _wrapped(follow["surface"], context):
                    box.label(text=line)


def _wrapped(text, context):
    """`text` in lines that fit the sidebar (labels do not wrap; about 6.5 pixels a character)."""
    scale = context.preferences.system.ui_scale
    return textwrap.wrap(text, max(16, int(context.region.width / (6.5 * scale)) - 2))


def register_properties():
    bpy.types.Object.hairlod_lod_preview = PointerProperty(type=HAIRLOD_PG_lod_preview)


def unregister_properties():
    del bpy.types.Object.hairlod_lod_preview
