"""Build Hair LoD: the active hair Curves object -> one Curves object per thick level."""

import bpy
import numpy as np
from bpy.props import IntProperty

COLLECTION_NAME = "Hair LoD"


def _level_strands(level, level_id):
    """A thick level as Strands with the attributes artists and shaders read."""
    from .. import Strands

    hairs, control_points = level.centres.shape[:2]
    strands = Strands.from_counts(level.centres.reshape(-1, 3), np.full(hairs, control_points),
                                  np.ascontiguousarray(level.radii[..., 0].reshape(-1)))
    strands.set_attribute("major_radius", np.ascontiguousarray(level.radii[..., 0].reshape(-1)))
    strands.set_attribute("minor_radius", np.ascontiguousarray(level.radii[..., 1].reshape(-1)))
    strands.set_attribute("major_axis", np.ascontiguousarray(level.major_axis.reshape(-1, 3)))
    strands.set_attribute("minor_axis", np.ascontiguousarray(level.minor_axis.reshape(-1, 3)))
    strands.set_attribute("density", np.ascontiguousarray(level.density.reshape(-1)))
    # Curve-domain attributes are floats in Blender's hair attributes, like the rest.
    strands.set_attribute("n_total", level.n_total.astype(np.float32), domain="curve")
    cluster = np.repeat(np.arange(len(level.cluster_first) - 1), np.diff(level.cluster_first))
    strands.set_attribute("cluster", cluster.astype(np.float32), domain="curve")
    strands.set_attribute("level", np.full(hairs, level_id, np.float32), domain="curve")
    return strands


class HAIRLOD_OT_build_lod(bpy.types.Operator):
    """Build guide hairs, clusters and elliptical thick hairs from the active hair Curves object,
    adding one Curves object per level to the "Hair LoD" collection"""

    bl_idname = "hairlod.build_lod"
    bl_label = "Build Hair LoD"
    bl_options = {'REGISTER', 'UNDO'}

    guides: IntProperty(name="Guides", description="Guide hairs chosen by k-means", default=256, min=1)
    levels: IntProperty(name="Levels", description="LoD levels including the strands themselves",
                        default=6, min=2, max=16)
    control_points: IntProperty(name="Control Points", description="Control points per hair", default=16, min=2, max=64)
    seed: IntProperty(name="Seed", description="Random seed of the k-means seeding", default=0, min=0)

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        return obj is not None and obj.type == 'CURVES'

    def execute(self, context):
        from .. import lod
        from .curves import curves_to_strands, strands_to_curves

        source = context.active_object
        window_manager = context.window_manager
        window_manager.progress_begin(0, self.levels + 2)
        collection = bpy.data.collections.get(COLLECTION_NAME)
        created_collection = collection is None
        created = []
        try:
            strands = curves_to_strands(source, depsgraph=context.evaluated_depsgraph_get())
            window_manager.progress_update(1)
            asset = lod.build_lod(strands, guides=self.guides, levels=self.levels,
                                  control_points=self.control_points, seed=self.seed)
            window_manager.progress_update(2)
            if created_collection:
                collection = bpy.data.collections.new(COLLECTION_NAME)
                context.scene.collection.children.link(collection)
            for position, level in enumerate(asset.levels):
                level_id = asset.level_ids[position]
                obj = strands_to_curves(_level_strands(level, level_id), f"{source.name} LoD L{level_id}", collection)
                obj.matrix_world = source.matrix_world
                created.append(obj)
                window_manager.progress_update(3 + position)
        except Exception as error:  # reported in the UI; nothing half-made stays behind
            for obj in created:
                data = obj.data
                bpy.data.objects.remove(obj)
                bpy.data.hair_curves.remove(data)
            if created_collection and collection is not None:
                bpy.data.collections.remove(collection)
            self.report({'ERROR'}, f"Cannot build the hair LoD of {source.name}: {error}")
            return {'CANCELLED'}
        finally:
            window_manager.progress_end()
        coverage = ", ".join(f"{c:.3f}" for c in asset.coverage)
        self.report({'INFO'}, f"Built {len(created)} thick levels from {asset.strand_count:,} strands "
                              f"({asset.cluster_count} clusters; coverage {coverage})")
        return {'FINISHED'}
