"""Operators that make hair meshes from scalp faces and grow strands from them."""

import bpy
from bpy.props import FloatProperty, IntProperty

from .operators import select_only
from .strand_settings import StrandSettings


class HAIRLOD_OT_hair_mesh_from_faces(bpy.types.Operator):
    """Extrude the selected faces (all faces when none is selected) of the active mesh along their
    normals into the layers of a new hair-mesh object"""

    bl_idname = "hairlod.hair_mesh_from_faces"
    bl_label = "New Hair Mesh from Faces"
    bl_options = {'REGISTER', 'UNDO'}

    layers: IntProperty(
        name="Layers",
        description="Layers above the root layer (the selected faces)",
        default=4,
        min=1,
        soft_max=32,
    )
    length: FloatProperty(
        name="Length",
        description="Distance from the root layer to the last layer along the normals",
        default=0.3,
        min=0.0,
        unit='LENGTH',
    )
    taper: FloatProperty(
        name="Taper",
        description="Shrink of each layer towards its centre relative to the layer below (0: none)",
        default=0.05,
        min=0.0,
        max=0.99,
        subtype='FACTOR',
    )

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        return obj is not None and obj.type == 'MESH'

    def execute(self, context):
        import numpy as np

        from ..hairmesh import extrude_faces
        from .hair_mesh import object_from_hair_mesh

        scalp = context.active_object
        if scalp.mode == 'EDIT':
            # Leaving edit mode writes the edit mesh (and its selection) back to the mesh.
            bpy.ops.object.mode_set(mode='OBJECT')
        mesh = scalp.data
        face_count = len(mesh.polygons)
        if face_count == 0:
            self.report({'ERROR'}, f"'{scalp.name}' has no faces to extrude")
            return {'CANCELLED'}

        selected = np.empty(face_count, bool)
        mesh.polygons.foreach_get("select", selected)
        loop_starts = np.empty(face_count, np.int32)
        loop_totals = np.empty(face_count, np.int32)
        mesh.polygons.foreach_get("loop_start", loop_starts)
        mesh.polygons.foreach_get("loop_total", loop_totals)
        face_normals = np.empty((face_count, 3), np.float32)
        mesh.polygons.foreach_get("normal", face_normals.ravel())
        face_areas = np.empty(face_count, np.float32)
        mesh.polygons.foreach_get("area", face_areas)
        loop_vertices = np.empty(len(mesh.loops), np.int32)
        mesh.loops.foreach_get("vertex_index", loop_vertices)
        positions = np.empty((len(mesh.vertices), 3), np.float32)
        mesh.vertices.foreach_get("co", positions.ravel())
        loop_uv = None
        if mesh.uv_layers.active is not None:
            loop_uv = np.empty((len(mesh.loops), 2), np.float32)
            mesh.uv_layers.active.data.foreach_get("uv", loop_uv.ravel())
        try:
            hair_mesh = extrude_faces(positions, loop_vertices, loop_starts, loop_totals, face_normals, face_areas,
                                      selected, self.layers, self.length, self.taper, loop_uv)
            obj = object_from_hair_mesh(hair_mesh, f"{scalp.name}_hair_mesh", context.collection)
        except ValueError as error:
            self.report({'ERROR'}, f"Cannot make a hair mesh from '{scalp.name}': {error}")
            return {'CANCELLED'}
        obj.matrix_world = scalp.matrix_world

        select_only(context, obj)
        self.report({'INFO'}, f"Hair mesh with {hair_mesh.face_count} faces and {self.layers + 1} layers")
        return {'FINISHED'}

class HAIRLOD_OT_generate_strands(StrandSettings, bpy.types.Operator):
    """Grow strands from the active hair mesh into the hair Curves object "<name>_strands",
    replacing the previously generated one"""

    bl_idname = "hairlod.generate_strands"
    bl_label = "Generate Strands"
    bl_options = {'REGISTER', 'UNDO'}

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        return obj is not None and obj.type == 'MESH'

    def invoke(self, context, event):
        self.copy_settings(context.active_object.hairlod_strands)
        return self.execute(context)

    def execute(self, context):
        from ..hairmesh import generate_strands
        from .curves import replace_generated_curves
        from .hair_mesh import hair_mesh_from_object

        source = context.active_object
        window_manager = context.window_manager
        window_manager.progress_begin(0, 3)
        try:
            hair_mesh = hair_mesh_from_object(source)
            window_manager.progress_update(1)
            strands = generate_strands(hair_mesh, count=self.count, vertices=int(self.vertices), styling=self.styling(),
                                       seed=self.seed, lod=self.lod, subdivision=self.subdivision)
            window_manager.progress_update(2)
            replace_generated_curves(source, strands, f"{source.name}_strands", context.collection)
        except (TypeError, ValueError) as error:
            self.report({'ERROR'}, f"Cannot generate strands: {error}")
            return {'CANCELLED'}
        finally:
            window_manager.progress_end()

        source.hairlod_strands.copy_settings(self)
        self.report({'INFO'}, f"Generated {len(strands):,} strands, {strands.point_count:,} points")
        return {'FINISHED'}
