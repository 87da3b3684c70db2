"""File > Import / Export operators for hair files."""

import math
import os

import bpy
import numpy as np
from bpy.props import EnumProperty, FloatProperty, StringProperty
from bpy_extras.io_utils import ExportHelper, ImportHelper, axis_conversion, orientation_helper

from .. import io


def select_only(context, obj):
    """Makes `obj` (an object an operator just made) the only selected object and the active one."""
    for selected in context.selected_objects:
        selected.select_set(False)
    obj.select_set(True)
    context.view_layer.objects.active = obj


def _file_filter(formats):
    return ";".join("*" + extension for extension in formats)


# Import presets: where a file comes from -> (label, tooltip, Forward, Up, Scale). Forward and Up
# name the file's axes that become Blender's forward (+Y) and up (+Z) axes, as in Blender's own
# importers (OBJ, FBX: "-Z Forward, Y Up" for Y-up files).
IMPORT_SOURCES = {
    'BLENDER': ("Blender (Z Up, Metres)",
                "Z up in metres, like Blender: the points are used as they are", 'Y', 'Z', 1.0),
    'Y_UP': ("Y Up, Metres (TressFX, USC-HairSalon)",
             "Y up in metres: stands the hair upright (-Z Forward, Y Up, Scale 1)", '-Z', 'Y', 1.0),
    'Y_UP_CM': ("Y Up, Centimetres (Maya)",
                "Y up in centimetres, Maya's default unit: stands the hair upright and converts it "
                "to metres (-Z Forward, Y Up, Scale 0.01)", '-Z', 'Y', 0.01),
}
_CUSTOM_SOURCE = 'CUSTOM'


def _apply_source(self, _context):
    """Update of the Source property: sets Forward, Up and Scale to the chosen preset's."""
    if self.source == _CUSTOM_SOURCE:
        return
    _label, _tooltip, forward, up, scale = IMPORT_SOURCES[self.source]
    # Each axis' update moves the other off a clashing axis; setting both leaves exactly these.
    self.axis_forward, self.axis_up, self.global_scale = forward, up, scale


def _matching_source(properties):
    """The preset whose Forward, Up and Scale the import operator's properties have, or 'CUSTOM'."""
    for identifier, (_label, _tooltip, forward, up, scale) in IMPORT_SOURCES.items():
        if ((properties.axis_forward, properties.axis_up) == (forward, up)
                and math.isclose(properties.global_scale, scale, rel_tol=1e-6)):
            return identifier
    return _CUSTOM_SOURCE


def sync_source(properties):
    """Sets Source to the preset that Forward, Up and Scale match ('CUSTOM' when none does);
    True when it changed."""
    source = _matching_source(properties)
    if source == properties.source:
        return False
    properties.source = source
    return True


def _with_description(cls, name, description):
    """Gives a tooltip to a property a decorator added (orientation_helper's axes have none),
    keeping its items, default and update."""
    deferred = cls.__annotations__[name]
    cls.__annotations__[name] = deferred.function(**{**deferred.keywords, "description": description})


def to_blender_space(strands, rotation, scale):
    """Rotates (a 3x3 signed axis permutation, from axis_conversion) and scales the points, scales
    the radii; in place, on the whole arrays."""
    matrix = np.asarray(rotation, dtype=np.float64) * scale
    if not np.array_equal(matrix, np.eye(3)):
        points = strands.points
        points[:] = points @ matrix.T
    if scale != 1.0:
        radius = strands.radius
        radius *= np.float32(scale)


@orientation_helper(axis_forward='Y', axis_up='Z')
class HAIRLOD_OT_import_hair(bpy.types.Operator, ImportHelper):
    """Import a hair file as a hair Curves object"""

    bl_idname = "hairlod.import_hair"
    bl_label = "Import Hair Strands"
    bl_options = {'REGISTER', 'UNDO'}

    filter_glob: StringProperty(default=_file_filter(io.READ_FORMATS), options={'HIDDEN'})

    # Defined before Scale and the axes: a call that passes a Source and some of those as well gets
    # the preset with those values in place of the preset's (properties are set in this order).
    source: EnumProperty(
        name="Source",
        description="Where the file comes from: sets Forward, Up and Scale",
        items=[(identifier, label, tooltip) for identifier, (label, tooltip, *_) in IMPORT_SOURCES.items()]
        + [(_CUSTOM_SOURCE, "Custom", "Forward, Up and Scale as set below")],
        default='BLENDER',
        update=_apply_source,
    )

    global_scale: FloatProperty(
        name="Scale",
        description="Multiplies the points and radii, after Forward and Up: 0.01 for a file in "
                    "centimetres, 1 for metres",
        default=1.0,
        min=1e-6,
        max=1e6,
        soft_min=0.001,
        soft_max=1000.0,
        precision=4,
    )

    default_radius: FloatProperty(
        name="Default Radius",
        description="Radius of the points, in the scene (Scale does not change it), for formats that "
                    "store no thickness (0: 1/10000 of the hair's bounding box diagonal)",
        default=0.0,
        min=0.0,
        precision=5,
        unit='LENGTH',
    )

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        layout.prop(self, "source")
        axes = layout.column(align=True)
        axes.prop(self, "axis_forward")
        axes.prop(self, "axis_up")
        layout.prop(self, "global_scale")
        layout.prop(self, "default_radius")

    def check(self, context):
        # The file browser calls this after each change: keep the axes apart (ImportHelper) and
        # Source showing the preset the values match, "Custom" once they are edited by hand.
        changed = ImportHelper.check(self, context)
        return sync_source(self) or changed

    def execute(self, context):
        from .curves import strands_to_curves

        scale = self.global_scale
        if not math.isfinite(scale):  # the property's range clamps numbers but lets NaN through
            self.report({'ERROR'}, f"Cannot import {self.filepath}: Scale must be a positive number, got {scale}")
            return {'CANCELLED'}
        # What is remembered for the next import shows the preset these values are.
        sync_source(self)
        rotation = axis_conversion(from_forward=self.axis_forward, from_up=self.axis_up)

        name = os.path.splitext(os.path.basename(self.filepath))[0]
        window_manager = context.window_manager
        window_manager.progress_begin(0, 2)
        try:
            # The default radius is given in the scene: read it in the file's units.
            default_radius = self.default_radius / scale if self.default_radius else None
            strands = io.read(self.filepath, default_radius=default_radius)
            to_blender_space(strands, rotation, scale)
            if scale != 1.0:
                strands.require_float_range(f"Scale {scale:g}")
            window_manager.progress_update(1)
            obj = strands_to_curves(strands, name, context.collection)
        except Exception as error:  # reported to the user; strands_to_curves leaves nothing behind
            self.report({'ERROR'}, f"Cannot import {self.filepath}: {error}")
            return {'CANCELLED'}
        finally:
            window_manager.progress_end()

        select_only(context, obj)
        self.report({'INFO'}, f"Imported {len(strands):,} strands, {strands.point_count:,} points")
        return {'FINISHED'}


_with_description(HAIRLOD_OT_import_hair, "axis_forward",
                  "Axis of the file that becomes Blender's forward axis (Y)")
_with_description(HAIRLOD_OT_import_hair, "axis_up",
                  "Axis of the file that becomes Blender's up axis (Z)")


class HAIRLOD_OT_export_hair(bpy.types.Operator, ExportHelper):
    """Export the active hair Curves object (with its modifiers) to a hair file"""

    bl_idname = "hairlod.export_hair"
    bl_label = "Export Hair Strands"

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
