"""Hair meshes in Blender: the Mesh bridge (hairlod.blender.hair_mesh) and its operators."""

import bmesh
import bpy
import numpy as np
import pytest

from hairlod import HairMesh


def grid_object(name="Scalp", cells=4):
    """A flat grid of cells x cells unit quads in z = 0, from (0, 0) to (cells, cells)."""
    coordinates = np.arange(cells + 1, dtype=float)
    vertices = [(x, y, 0.0) for y in coordinates for x in coordinates]
    row = cells + 1
    faces = [(y * row + x, y * row + x + 1, (y + 1) * row + x + 1, (y + 1) * row + x)
             for y in range(cells) for x in range(cells)]
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(vertices, [], faces)
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.collection.objects.link(obj)
    bpy.context.view_layer.objects.active = obj
    return obj


def select_faces(obj, mask):
    """Selects the faces of ``mask`` and their vertices, so that edit mode keeps the selection."""
    mesh = obj.data
    mask = np.asarray(mask, bool)
    mesh.polygons.foreach_set("select", mask)
    sizes = np.array([len(polygon.vertices) for polygon in mesh.polygons])
    loops = np.empty(len(mesh.loops), np.int32)
    mesh.loops.foreach_get("vertex_index", loops)
    vertex_selected = np.zeros(len(mesh.vertices), bool)
    vertex_selected[loops[np.repeat(mask, sizes)]] = True
    mesh.vertices.foreach_set("select", vertex_selected)
    edges = np.empty((len(mesh.edges), 2), np.int32)
    mesh.edges.foreach_get("vertices", edges.ravel())
    mesh.edges.foreach_set("select", vertex_selected[edges].all(axis=1))
    bpy.context.tool_settings.mesh_select_mode = (False, False, True)


def face_centres(obj):
    centres = np.empty((len(obj.data.polygons), 3), np.float32)
    obj.data.polygons.foreach_get("center", centres.ravel())
    return centres


def vertex_attribute(obj, name):
    values = np.empty(len(obj.data.vertices), np.int32)
    obj.data.attributes[name].data.foreach_get("value", values)
    return values


def raise_top_layer(obj):
    """Moves the hair mesh's last layer up by 1 through the mesh data (Object Mode, as a script would)."""
    layer = vertex_attribute(obj, "hair_layer")
    positions = np.empty((len(obj.data.vertices), 3), np.float32)
    obj.data.vertices.foreach_get("co", positions.ravel())
    positions[layer == layer.max(), 2] += 1.0
    obj.data.vertices.foreach_set("co", positions.ravel())
    obj.data.update()
    bpy.context.view_layer.update()


def raise_top_layer_in_edit_mode(obj):
    """Enters Edit Mode and moves the hair mesh's last layer up by 1, as an artist would."""
    bpy.ops.object.mode_set(mode='EDIT')
    editable = bmesh.from_edit_mesh(obj.data)
    layer = editable.verts.layers.int["hair_layer"]
    top = max(vertex[layer] for vertex in editable.verts)
    for vertex in editable.verts:
        if vertex[layer] == top:
            vertex.co.z += 1.0
    bmesh.update_edit_mesh(obj.data)
    bpy.context.view_layer.update()


def left_half_hair_mesh(layers=3, length=1.0):
    """Hair mesh from the 2 x 4 left cells of a 4 x 4 grid: 15 roots, 8 faces, 22 root edges."""
    scalp = grid_object()
    select_faces(scalp, face_centres(scalp)[:, 0] < 2)
    assert bpy.ops.hairlod.hair_mesh_from_faces(layers=layers, length=length, taper=0.0) == {'FINISHED'}
    return bpy.context.active_object


def sample_hair_mesh():
    rng = np.random.default_rng(5)
    base = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [2, 0, 0], [2, 1, 0]], np.float32)
    layers = np.stack([base + [0, 0, 0.4 * k] + rng.normal(0, 0.05, base.shape) for k in range(4)]).astype(np.float32)
    uv = rng.random((7, 2), dtype=np.float32)
    w = rng.random((4, 6), dtype=np.float32)
    return HairMesh(layers, np.array([4, 3], np.int32), np.array([0, 1, 2, 3, 1, 4, 5], np.int32), uv, w)


def test_round_trip_is_exact(empty_scene, addon):
    from hairlod.blender.hair_mesh import hair_mesh_from_object, object_from_hair_mesh

    expected = sample_hair_mesh()
    obj = object_from_hair_mesh(expected, "cage")
    assert obj.type == 'MESH' and len(obj.data.vertices) == 4 * 6
    # Root faces, then side quads along the 7 distinct root edges for each of the 3 layer gaps.
    assert len(obj.data.polygons) == 2 + 7 * 3
    actual = hair_mesh_from_object(obj)
    assert (actual.layer_count, actual.vertex_count, actual.face_count) == (4, 6, 2)
    np.testing.assert_array_equal(actual.layers, expected.layers)
    np.testing.assert_array_equal(actual.face_sizes, expected.face_sizes)
    np.testing.assert_array_equal(actual.face_vertices, expected.face_vertices)
    np.testing.assert_array_equal(actual.uv, expected.uv)
    np.testing.assert_array_equal(actual.w, expected.w)


def test_faces_off_the_root_layer_are_ignored(empty_scene, addon):
    from hairlod.blender.hair_mesh import hair_mesh_from_object, object_from_hair_mesh

    expected = sample_hair_mesh()
    obj = object_from_hair_mesh(expected, "cage")
    # A cap on the last layer (vertices 18-21 lie above the root quad 0-3), as an artist might add.
    editable = bmesh.new()
    editable.from_mesh(obj.data)
    editable.verts.ensure_lookup_table()
    editable.faces.new([editable.verts[index] for index in (18, 19, 20, 21)])
    editable.to_mesh(obj.data)
    editable.free()
    actual = hair_mesh_from_object(obj)
    np.testing.assert_array_equal(actual.face_vertices, expected.face_vertices)
    np.testing.assert_array_equal(actual.layers, expected.layers)


@pytest.mark.parametrize("break_it, message", [
    (lambda mesh: mesh.attributes.remove(mesh.attributes["hair_layer"]), "no integer vertex attribute 'hair_layer'"),
    (lambda mesh: mesh.attributes["hair_root"].data[7].__setattr__("value", 8), "not a root-layer vertex"),
    (lambda mesh: mesh.attributes["hair_layer"].data[7].__setattr__("value", 2), "layer 1 has 5 vertices"),
    (lambda mesh: mesh.attributes["hair_root"].data[2].__setattr__("value", 3), "not its own index"),
])
def test_invalid_hair_meshes_name_the_problem(empty_scene, addon, break_it, message):
    from hairlod.blender.hair_mesh import hair_mesh_from_object, object_from_hair_mesh

    obj = object_from_hair_mesh(sample_hair_mesh(), "cage")
    break_it(obj.data)
    with pytest.raises(ValueError, match=f"'cage'.*{message}"):
        hair_mesh_from_object(obj)


def test_extrude_selected_faces_of_a_grid(empty_scene, addon):
    from hairlod.blender.hair_mesh import hair_mesh_from_object

    obj = left_half_hair_mesh(layers=3, length=1.5)
    assert obj.name == "Scalp_hair_mesh" and obj.select_get()
    assert len(obj.data.vertices) == 4 * 15 and len(obj.data.polygons) == 8 + 22 * 3
    layer, root = vertex_attribute(obj, "hair_layer"), vertex_attribute(obj, "hair_root")
    np.testing.assert_array_equal(np.bincount(layer), [15] * 4)
    np.testing.assert_array_equal(layer[root], 0)
    hair_mesh = hair_mesh_from_object(obj)
    assert (hair_mesh.layer_count, hair_mesh.vertex_count, hair_mesh.face_count) == (4, 15, 8)
    # A flat scalp extrudes straight up; without taper every layer keeps the root layer's shape.
    layers = hair_mesh.layers
    np.testing.assert_allclose(layers[:, :, 2], np.repeat([[0.0], [0.5], [1.0], [1.5]], 15, axis=1), atol=1e-6)
    np.testing.assert_allclose(layers[:, :, :2], np.broadcast_to(layers[0, :, :2], (4, 15, 2)), atol=1e-6)
    assert layers[0, :, 0].max() == 2.0


def test_extrude_in_edit_mode_with_taper(empty_scene, addon):
    bpy.ops.mesh.primitive_uv_sphere_add(segments=16, ring_count=8, radius=1.0)
    sphere = bpy.context.active_object
    upper = face_centres(sphere)[:, 2] > 0
    select_faces(sphere, upper)
    roots = len({v for polygon in sphere.data.polygons if polygon.select for v in polygon.vertices})
    bpy.ops.object.mode_set(mode='EDIT')

    assert bpy.ops.hairlod.hair_mesh_from_faces(layers=2, length=0.5, taper=0.2) == {'FINISHED'}
    obj = bpy.context.active_object
    assert sphere.mode == 'OBJECT' and obj.name == "Sphere_hair_mesh"
    np.testing.assert_array_equal(np.bincount(vertex_attribute(obj, "hair_layer")), [roots] * 3)
    from hairlod.blender.hair_mesh import hair_mesh_from_object

    layers = hair_mesh_from_object(obj).layers
    assert hair_mesh_from_object(obj).face_count == int(upper.sum())
    # Taper shrinks layer k by 0.8^k about its centre compared with the untapered extrusion.
    bpy.context.view_layer.objects.active = sphere
    assert bpy.ops.hairlod.hair_mesh_from_faces(layers=2, length=0.5, taper=0.0) == {'FINISHED'}
    untapered = hair_mesh_from_object(bpy.context.active_object).layers
    assert (untapered[1:, :, 2].mean(axis=1) > untapered[:-1, :, 2].mean(axis=1)).all()
    ratio = np.linalg.norm(layers - layers.mean(axis=1, keepdims=True), axis=2) / \
        np.linalg.norm(untapered - untapered.mean(axis=1, keepdims=True), axis=2)
    np.testing.assert_allclose(ratio, np.broadcast_to([[1.0], [0.8], [0.64]], ratio.shape), rtol=1e-4)


def test_generate_strands_on_the_root_faces_and_replaces_the_previous(empty_scene, addon):
    obj = left_half_hair_mesh()
    obj.location = (5, 0, 0)
    material = bpy.data.materials.new("Hair")
    assert bpy.ops.hairlod.generate_strands(count=500, vertices="9", curl_radius=0.05, clump_amount=0.3) == {'FINISHED'}
    strands_obj = bpy.data.objects["Scalp_hair_mesh_strands"]
    assert strands_obj.type == 'CURVES' and bpy.context.active_object == obj
    assert len(strands_obj.data.curves) == 500 and len(strands_obj.data.points) == 500 * 9
    assert tuple(strands_obj.matrix_world.translation) == (5, 0, 0)
    assert obj.hairlod_strands.count == 500 and obj.hairlod_strands.vertices == "9"

    from hairlod.blender.curves import curves_to_strands

    strands = curves_to_strands(strands_obj, evaluated=False)
    roots = strands.points[strands.offsets[:-1]]
    tolerance = 1e-5 * np.linalg.norm([2, 4, 3])  # the hair mesh's bounding-box diagonal
    assert np.abs(roots[:, 2]).max() < tolerance
    assert roots[:, 0].min() > -tolerance and roots[:, 0].max() < 2 + tolerance
    assert roots[:, 1].min() > -tolerance and roots[:, 1].max() < 4 + tolerance

    strands_obj.data.materials.append(material)
    assert bpy.ops.hairlod.generate_strands(count=300, vertices="5") == {'FINISHED'}
    replaced = bpy.data.objects["Scalp_hair_mesh_strands"]
    assert len(replaced.data.curves) == 300 and len(replaced.data.points) == 300 * 5
    assert list(replaced.data.materials) == [material]
    assert [o.name for o in bpy.data.objects if o.type == 'CURVES'] == ["Scalp_hair_mesh_strands"]
    assert len(bpy.data.hair_curves) == 1


def test_generate_from_a_plain_mesh_reports_and_creates_nothing(empty_scene, addon):
    grid_object("Plain")
    counts = (len(bpy.data.objects), len(bpy.data.hair_curves), len(bpy.data.meshes))
    with pytest.raises(RuntimeError, match="Cannot generate strands: 'Plain' has no integer vertex attribute"):
        bpy.ops.hairlod.generate_strands(count=100)
    assert (len(bpy.data.objects), len(bpy.data.hair_curves), len(bpy.data.meshes)) == counts


def test_operators_are_undoable(empty_scene, addon):
    for operator in (bpy.types.HAIRLOD_OT_hair_mesh_from_faces, bpy.types.HAIRLOD_OT_generate_strands):
        assert {'REGISTER', 'UNDO'} <= operator.bl_options
    grid_object()
    bpy.ops.ed.undo_push(message="scalp")
    bpy.ops.hairlod.hair_mesh_from_faces()
    bpy.ops.ed.undo_push(message="hair mesh")
    bpy.ops.hairlod.generate_strands(count=200)
    bpy.ops.ed.undo_push(message="strands")
    assert {"Scalp_hair_mesh", "Scalp_hair_mesh_strands"} <= set(bpy.data.objects.keys())
    bpy.ops.ed.undo()
    assert "Scalp_hair_mesh_strands" not in bpy.data.objects and "Scalp_hair_mesh" in bpy.data.objects
    bpy.ops.ed.undo()
    assert "Scalp_hair_mesh" not in bpy.data.objects
    bpy.ops.ed.redo()
    bpy.ops.ed.redo()
    assert len(bpy.data.objects["Scalp_hair_mesh_strands"].data.curves) == 200


def test_panel_is_registered_and_recognises_hair_meshes(empty_scene, addon):
    assert bpy.types.VIEW3D_PT_hairlod_hair_mesh.bl_parent_id == "VIEW3D_PT_hairlod"
    from hairlod.blender.hair_mesh import is_hair_mesh_object

    scalp = grid_object()
    assert not is_hair_mesh_object(scalp)
    assert is_hair_mesh_object(left_half_hair_mesh())


def preview_points(obj):
    curves = bpy.data.objects[f"{obj.name}_preview"].data
    points = np.empty((len(curves.points), 3), np.float32)
    curves.attributes["position"].data.foreach_get("vector", points.ravel())
    return points


def test_live_preview_follows_edits_capped_and_goes_away(empty_scene, addon):
    from hairlod.blender.hair_mesh_preview import PREVIEW_STRAND_LIMIT

    obj = left_half_hair_mesh()
    settings = obj.hairlod_strands
    settings.count, settings.vertices = 5000, "5"
    assert "Scalp_hair_mesh_preview" not in bpy.data.objects
    settings.live_preview = True
    preview = bpy.data.objects["Scalp_hair_mesh_preview"]
    assert len(preview.data.curves) == PREVIEW_STRAND_LIMIT and len(preview.data.points) == PREVIEW_STRAND_LIMIT * 5
    before = preview_points(obj)

    # An update that changes none of the inputs keeps the preview object.
    pointer = preview.as_pointer()
    bpy.context.view_layer.update()
    obj.update_tag()
    bpy.context.view_layer.update()
    assert bpy.data.objects["Scalp_hair_mesh_preview"].as_pointer() == pointer

    # Raising the top layer lengthens the strands.
    raise_top_layer(obj)
    after = preview_points(obj)
    assert after.shape == before.shape and after[:, 2].max() > before[:, 2].max() + 0.5
    assert bpy.data.objects["Scalp_hair_mesh_preview"].as_pointer() == pointer  # rewritten in place

    # Another vertex count changes the curves' sizes: a new preview object replaces the old one.
    settings.vertices = "9"
    bpy.context.view_layer.update()
    assert len(bpy.data.objects["Scalp_hair_mesh_preview"].data.points) == PREVIEW_STRAND_LIMIT * 9

    # So does a transform, and the preview keeps its single object.
    obj.location.z = 2.0
    bpy.context.view_layer.update()
    assert bpy.data.objects["Scalp_hair_mesh_preview"].matrix_world.translation.z == 2.0
    assert [o.name for o in bpy.data.objects if o.type == 'CURVES'] == ["Scalp_hair_mesh_preview"]

    settings.live_preview = False
    assert "Scalp_hair_mesh_preview" not in bpy.data.objects and len(bpy.data.hair_curves) == 0


def test_live_preview_follows_edit_mode_edits(empty_scene, addon):
    obj = left_half_hair_mesh()
    obj.hairlod_strands.live_preview = True
    before = preview_points(obj)
    raise_top_layer_in_edit_mode(obj)
    assert obj.mode == 'EDIT'
    assert preview_points(obj)[:, 2].max() > before[:, 2].max() + 0.5


def test_strand_line_indices_and_ramp_follow_the_offsets():
    from hairlod.blender.preview.strand_batch import along_strand, line_indices

    offsets = np.array([0, 3, 5, 9])
    # Brute force: every consecutive pair inside a curve.
    expected = [(i, i + 1) for c in range(3) for i in range(offsets[c], offsets[c + 1] - 1)]
    assert line_indices(offsets).tolist() == [list(pair) for pair in expected]
    assert line_indices(offsets).dtype == np.int32
    assert np.allclose(along_strand(offsets), [0, 0.5, 1, 0, 1, 0, 1 / 3, 2 / 3, 1])
    assert line_indices(np.array([0])).shape == (0, 2) and along_strand(np.array([0])).shape == (0,)
    # Curves of one size take a faster path: the same as the general one.
    uniform = np.arange(0, 5 * 7 + 1, 7)
    general = np.concatenate([uniform, [uniform[-1] + 2]])
    assert np.array_equal(line_indices(uniform), line_indices(general)[:-1])
    assert np.array_equal(along_strand(uniform), along_strand(general)[:-2])


def test_strand_chunks_hold_whole_curves_up_to_the_limit():
    from hairlod.blender.preview.strand_batch import chunk_curves

    rng = np.random.default_rng(3)
    offsets = np.concatenate([[0], np.cumsum(rng.integers(2, 40, 500))])
    offsets = np.concatenate([offsets, [offsets[-1] + 300]])  # one curve longer than a chunk
    bounds = chunk_curves(offsets, chunk_points=100)
    assert bounds[0] == 0 and bounds[-1] == len(offsets) - 1 and np.all(np.diff(bounds) >= 1)
    sizes = offsets[bounds[1:]] - offsets[bounds[:-1]]
    assert np.all((sizes <= 100) | (np.diff(bounds) == 1))
    # Greedy: adding the next curve would overflow the chunk.
    assert np.all(offsets[np.array(bounds[1:-1]) + 1] - offsets[bounds[:-2]] > 100)
    assert chunk_curves(np.array([0])) == [0]


class _View:
    """The view matrices camera_detail_level reads: a camera at `eye` looking down -z."""

    def __init__(self, eye, tan_half_fov=0.5, perspective=True):
        from mathutils import Matrix

        self.view_matrix = Matrix.Translation(eye).inverted()
        self.window_matrix = Matrix.Diagonal((1.0, 1.0 / tan_half_fov, 1.0, 1.0))
        self.is_perspective = perspective


def test_camera_detail_level_is_eq7_of_the_distance_to_the_bounds():
    from hairlod.blender.hair_mesh_gpu_preview import camera_detail_level, quantised_level

    bounds = (np.array([0.0, 0.0, 0.0]), np.array([3.0, 4.0, 0.0]))  # diagonal h = 5

    def level(eye, full_detail_px=100.0, perspective=True):
        view = _View(eye, perspective=perspective)
        return camera_detail_level(bounds, view.view_matrix, view.window_matrix, view.is_perspective, 500,
                                   full_detail_px)

    # Bhokare 2024 Eq. 7 with tan(theta) = 2 tan(fov / 2) = 1: L = h R / (d full_detail_px) = 25 / d.
    for distance in (50.0, 100.0, 400.0):
        assert level((1.0, 1.0, distance)) == pytest.approx(25.0 / distance, rel=1e-5)
    # d is measured to the nearest point of the box, not its centre.
    assert level((3.0 + 30.0, 4.0 + 40.0, 0.0)) == pytest.approx(0.5, rel=1e-5)
    assert level((1.0, 1.0, 0.0)) == 1.0  # inside the box
    # Orthographic: d tan(theta) is the view height (2 / P[1][1] = 1), whatever the distance.
    assert level((1.0, 1.0, 1e6), full_detail_px=5000.0, perspective=False) == pytest.approx(0.5, rel=1e-5)

    assert quantised_level(1.0) == 1.0 and quantised_level(3.0) == 1.0
    assert quantised_level(0.5) == pytest.approx(0.5) and quantised_level(0.52) == pytest.approx(0.5)
    assert quantised_level(0.55) == pytest.approx(2 ** -0.75)
    assert quantised_level(0.0) > 0.0


class _RecordingBatch:
    """Stands in for the GPU StrandBatch, which needs a window (the gpu module raises in -b)."""

    def __init__(self):
        self.updates = []
        self.strand_count = 0

    def update(self, points, tangents, offsets):
        self.updates.append((np.array(points), np.array(tangents), np.array(offsets)))
        self.strand_count = len(offsets) - 1


def test_viewport_strands_follow_edits_settings_and_level(empty_scene, addon):
    from hairlod import generate_strands
    from hairlod.blender.hair_mesh import hair_mesh_from_object
    from hairlod.blender.hair_mesh_gpu_preview import preview_state, regenerate

    obj = left_half_hair_mesh()
    settings = obj.hairlod_strands
    settings.count, settings.vertices, settings.curl_radius = 3000, "9", 0.05
    assert preview_state(obj) is None
    settings.viewport_strands = True
    state = preview_state(obj)
    assert state is not None and state.hair_mesh is not None and state.error is None
    state.batch = _RecordingBatch()

    assert regenerate(obj, state, 1.0) and len(state.batch.updates) == 1
    points, tangents, offsets = state.batch.updates[-1]
    # The same strands as generate_strands with the panel's settings.
    expected = generate_strands(hair_mesh_from_object(obj), count=3000, vertices=9, styling=settings.styling())
    assert np.array_equal(points, expected.points) and np.array_equal(offsets, expected.offsets)
    assert np.array_equal(tangents, expected.attribute("tangent"))
    assert not regenerate(obj, state, 1.0), "nothing changed: no regeneration"
    assert set(state.timings) == {"generate_s", "upload_s"}

    # A lower camera level: fewer strands (Bhokare 2024 Eq. 8) and vertices (Eq. 9), from the cached generator.
    generator = state.generator
    assert regenerate(obj, state, 0.25) and state.generator is generator
    assert 0.2 * 3000 < state.batch.strand_count < 0.3 * 3000
    assert np.diff(state.batch.updates[-1][2]).max() < 9

    # An edit of the mesh reaches the state through the depsgraph handler.
    raise_top_layer(obj)
    assert regenerate(obj, state, 1.0)
    assert state.batch.updates[-1][0][:, 2].max() > points[:, 2].max() + 0.5

    # A settings change regenerates; a transform does not (strands are drawn in object space).
    settings.seed = 7
    assert regenerate(obj, state, 1.0)
    obj.location.x = 3.0
    bpy.context.view_layer.update()
    assert not regenerate(obj, state, 1.0)

    # A mid-edit invalid mesh keeps the last strands and says why.
    hair_layer = obj.data.attributes["hair_layer"]
    values = vertex_attribute(obj, "hair_layer")
    values[:] = 0
    hair_layer.data.foreach_set("value", values)
    obj.data.update()
    bpy.context.view_layer.update()
    assert state.error is not None and "layer" in state.error and state.hair_mesh is not None

    settings.viewport_strands = False
    assert preview_state(obj) is None


def test_viewport_strands_follow_edit_mode_edits(empty_scene, addon):
    from hairlod.blender.hair_mesh_gpu_preview import preview_state

    obj = left_half_hair_mesh()
    obj.hairlod_strands.viewport_strands = True
    before = preview_state(obj).hair_mesh.layers.copy()
    raise_top_layer_in_edit_mode(obj)
    assert obj.mode == 'EDIT'
    after = preview_state(obj).hair_mesh.layers
    assert np.allclose(after[-1, :, 2], before[-1, :, 2] + 1.0) and np.array_equal(after[:-1], before[:-1])
