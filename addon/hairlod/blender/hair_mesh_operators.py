"""Operators that make hair meshes from scalp faces and grow strands from them."""

import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, PointerProperty

# Strand vertex counts the generator accepts: 2^e + 1 (and 2, a straight segment).
_VERTEX_COUNTS = (2, 3, 5, 9, 17, 33, 65, 129)


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

        from .. import HairMesh
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
        if not selected.any():
            selected[:] = True
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

        sizes = loop_totals[selected]
        first_in_output = np.cumsum(sizes) - sizes
        loops = np.repeat(loop_starts[selected] - first_in_output, sizes) + np.arange(int(sizes.sum()))
        used, root_of_loop = np.unique(loop_vertices[loops], return_inverse=True)

        # Smooth normals of the selected faces only, area-weighted, so that unselected
        # neighbours do not bend the extrusion at the selection's border.
        normals = np.zeros((len(used), 3), np.float64)
        np.add.at(normals, root_of_loop, np.repeat(face_normals[selected] * face_areas[selected, None], sizes, axis=0))
        normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-30)

        step = np.arange(self.layers + 1)[:, None, None]
        offset_layers = positions[used][None] + normals[None] * (self.length * step / self.layers)
        centres = offset_layers.mean(axis=1, keepdims=True)
        layers = centres + (offset_layers - centres) * (1.0 - self.taper) ** step

        uv = None
        if mesh.uv_layers.active is not None:
            loop_uv = np.empty((len(mesh.loops), 2), np.float32)
            mesh.uv_layers.active.data.foreach_get("uv", loop_uv.ravel())
            uv = loop_uv[loops]
        try:
            hair_mesh = HairMesh(layers.astype(np.float32), sizes, root_of_loop.astype(np.int32), uv)
            obj = object_from_hair_mesh(hair_mesh, f"{scalp.name}_hair_mesh", context.collection)
        except ValueError as error:
            self.report({'ERROR'}, f"Cannot make a hair mesh from '{scalp.name}': {error}")
            return {'CANCELLED'}
        obj.matrix_world = scalp.matrix_world

        for other in context.selected_objects:
            other.select_set(False)
        obj.select_set(True)
        context.view_layer.objects.active = obj
        self.report({'INFO'}, f"Hair mesh with {hair_mesh.face_count} faces and {self.layers + 1} layers")
        return {'FINISHED'}


def _tag_owner(settings, context):
    # Tagging the hair-mesh object that holds the settings lets the live preview handler see the change.
    if isinstance(settings.id_data, bpy.types.Object):
        settings.id_data.update_tag()


class StrandSettings:
    """Strand generation settings: the Generate Strands operator's properties, also kept on each
    hair-mesh object (``Object.hairlod_strands``) so that the sidebar shows and edits them."""

    count: IntProperty(
        name="Strands",
        description="Number of strands at full level of detail",
        default=10000,
        min=1,
        soft_max=200000,
        update=_tag_owner,
    )
    vertices: EnumProperty(
        name="Vertices",
        description="Vertices per strand at full level of detail",
        items=[(str(count), str(count), f"{count} vertices per strand") for count in _VERTEX_COUNTS],
        default="17",
        update=_tag_owner,
    )
    seed: IntProperty(
        name="Seed",
        description="Seed of every random choice (roots, per-strand styling)",
        default=0,
        min=0,
        update=_tag_owner,
    )
    subdivision: IntProperty(
        name="Subdivision",
        description="Smooth refinement level of the hair mesh before growing strands",
        default=0,
        min=0,
        max=3,
        update=_tag_owner,
    )
    lod: FloatProperty(
        name="Level of Detail",
        description="Fraction of the strands and vertices kept (1: all)",
        default=1.0,
        min=0.001,
        max=1.0,
        subtype='FACTOR',
        update=_tag_owner,
    )
    curl_radius: FloatProperty(
        name="Curl Radius",
        description="Radius of the curl helix (0: no curl)",
        default=0.0,
        min=0.0,
        unit='LENGTH',
        update=_tag_owner,
    )
    curl_frequency: FloatProperty(
        name="Curl Frequency",
        description="Curl turns per unit of strand length",
        default=10.0,
        min=0.0,
        update=_tag_owner,
    )
    wave_amplitude: FloatProperty(
        name="Wave Amplitude",
        description="Amplitude of the planar wave (0: no wave)",
        default=0.0,
        min=0.0,
        unit='LENGTH',
        update=_tag_owner,
    )
    wave_frequency: FloatProperty(
        name="Wave Frequency",
        description="Wave periods per unit of strand length",
        default=3.0,
        min=0.0,
        update=_tag_owner,
    )
    clump_amount: FloatProperty(
        name="Clump",
        description="Pull of the tips towards their bundle's centre (0: no clumping)",
        default=0.0,
        min=0.0,
        max=1.0,
        subtype='FACTOR',
        update=_tag_owner,
    )
    frizz_amplitude: FloatProperty(
        name="Frizz",
        description="Amplitude of the per-strand noise (0: no frizz)",
        default=0.0,
        min=0.0,
        unit='LENGTH',
        update=_tag_owner,
    )
    frizz_frequency: FloatProperty(
        name="Frizz Frequency",
        description="Frizz noise cells per unit of strand length",
        default=20.0,
        min=0.0,
        update=_tag_owner,
    )
    trim_amount: FloatProperty(
        name="Trim",
        description="Random shortening: each strand keeps between 1 - trim and all of its length (0: no trim)",
        default=0.0,
        min=0.0,
        max=1.0,
        subtype='FACTOR',
        update=_tag_owner,
    )

    def copy_settings(self, source):
        for key in StrandSettings.__annotations__:
            setattr(self, key, getattr(source, key))

    def styling(self):
        """The styling operations whose amount is not zero, in a fixed order."""
        from ..hairmesh import Clump, Curl, Frizz, Trim, Wave

        operations = []
        if self.curl_radius > 0:
            operations.append(Curl(radius=self.curl_radius, frequency=self.curl_frequency))
        if self.wave_amplitude > 0:
            operations.append(Wave(amplitude=self.wave_amplitude, frequency=self.wave_frequency))
        if self.clump_amount > 0:
            operations.append(Clump(amount=self.clump_amount))
        if self.frizz_amplitude > 0:
            operations.append(Frizz(amplitude=self.frizz_amplitude, frequency=self.frizz_frequency))
        if self.trim_amount > 0:
            operations.append(Trim(amount=self.trim_amount))
        return operations


def _live_preview_toggled(settings, context):
    from .hair_mesh_preview import refresh_preview

    refresh_preview(settings.id_data)


def _viewport_strands_toggled(settings, context):
    from .hair_mesh_gpu_preview import viewport_strands_toggled

    viewport_strands_toggled(settings, context)


def _viewport_strands_changed(settings, context):
    from .hair_mesh_gpu_preview import tag_view3d_redraw

    tag_view3d_redraw()


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


def replace_generated_curves(source, strands, name, collection):
    """Writes ``strands`` into a new Curves object named ``name`` placed like ``source``. An earlier
    Curves object of that name passes on its materials and collections and is deleted; without one
    the new object goes to ``collection``. Another kind of object of that name is left alone (the
    new one gets a numbered name)."""
    from .curves import strands_to_curves

    previous = bpy.data.objects.get(name)
    if previous is not None and previous.type != 'CURVES':
        previous = None
    if previous is not None and previous.users_collection:
        collection = previous.users_collection[0]
    obj = strands_to_curves(strands, name, collection)
    obj.matrix_world = source.matrix_world
    if previous is None:
        return obj
    for material in previous.data.materials:
        obj.data.materials.append(material)
    for other in previous.users_collection:
        if obj.name not in other.objects:
            other.objects.link(obj)
    name, data_name = previous.name, previous.data.name
    old_data = previous.data
    bpy.data.objects.remove(previous)
    if old_data.users == 0:
        bpy.data.hair_curves.remove(old_data)
    obj.name, obj.data.name = name, data_name
    return obj


def register_properties():
    bpy.types.Object.hairlod_strands = PointerProperty(type=HAIRLOD_PG_strand_settings)


def unregister_properties():
    del bpy.types.Object.hairlod_strands
