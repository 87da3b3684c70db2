"""Build Hair LoD's parameters, declared once: kept on each hair object (HAIRLOD_PG_lod_build, set in
the sidebar before the build) and on the operator (its redo panel), whose defaults they are. The
screen-width threshold is not among them: Cameras Only keeps the levels the LoD preview's Width
(HAIRLOD_PG_lod_preview.width_px) selects, the one width property of an object."""

import bpy
from bpy.props import BoolProperty, IntProperty

from .. import lod


def build_property_annotations(options):
    """The build's parameters as property annotations: stored per object (the sidebar's settings)
    and on the operator (its redo panel), declared once."""
    return {
        "guides": IntProperty(name="Guides", description="Guide hairs chosen by k-means (0: automatic, one per 128 "
                              "strands, 16 to 256)", default=lod.LOD_DEFAULTS["guides"], min=0,
                              options=options),
        "levels": IntProperty(name="Levels", description="LoD levels including the strands themselves",
                              default=lod.LOD_DEFAULTS["levels"], min=lod.MIN_LEVELS, max=lod.MAX_LEVELS,
                              options=options),
        "control_points": IntProperty(name="Points", description="Control points per hair",
                                      default=lod.LOD_DEFAULTS["control_points"], min=lod.MIN_CONTROL_POINTS,
                                      max=lod.MAX_CONTROL_POINTS, soft_max=64, options=options),
        # IntProperty holds 32 bits; the core's seed takes 64.
        "seed": IntProperty(name="Seed", description="Random seed of the k-means seeding",
                            default=lod.LOD_DEFAULTS["seed"], min=0, options=options),
        "scene_cameras": BoolProperty(
            name="Cameras Only",
            description="Keep only the levels that some camera of the scene selects over the frame range "
                        "(at the render resolution, every Frame Step frames)", default=False, options=options),
        "frame_step": IntProperty(name="Frame Step", description="Frames between camera samples", default=1, min=1,
                                  options=options),
        "level_objects": BoolProperty(
            name="Level Objects", description="Also add one Curves object per thick level to the \"Hair LoD\" "
            "collection, hidden and not rendered (the preview draws the LoD; Export Hair LoD writes the levels "
            "either way)", default=False, options=options),
    }


BUILD_PROPERTIES = tuple(build_property_annotations(set()))


class HAIRLOD_PG_lod_build(bpy.types.PropertyGroup):
    """Build Hair LoD's parameters of one hair object, set in the sidebar before the build."""

    __annotations__ = build_property_annotations({'ANIMATABLE'})


def register_properties():
    bpy.types.Object.hairlod_lod_build = bpy.props.PointerProperty(type=HAIRLOD_PG_lod_build)


def unregister_properties():
    del bpy.types.Object.hairlod_lod_build
