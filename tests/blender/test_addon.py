"""The add-on inside Blender: registration, operators, menus, undo, .blend round trip."""

import bpy
import numpy as np
import pytest

BANGS = "Bangs_100.hair"


def menu_draw_functions(menu):
    return menu._dyn_ui_initialize()


def hairlod_menu_entries(menu):
    return [function for function in menu_draw_functions(menu) if function.__module__.startswith("hairlod.")]


def registered():
    return {
        "import": hasattr(bpy.types, "HAIRLOD_OT_import_hair"),
        "export": hasattr(bpy.types, "HAIRLOD_OT_export_hair"),
        "panel": hasattr(bpy.types, "VIEW3D_PT_hairlod"),
        "hair mesh from faces": hasattr(bpy.types, "HAIRLOD_OT_hair_mesh_from_faces"),
        "generate strands": hasattr(bpy.types, "HAIRLOD_OT_generate_strands"),
        "hair mesh panel": hasattr(bpy.types, "VIEW3D_PT_hairlod_hair_mesh"),
        "strand settings": hasattr(bpy.types.Object, "hairlod_strands"),
        "preview handler": any(handler.__module__.startswith("hairlod.")
                               for handler in bpy.app.handlers.depsgraph_update_post),
        "import menu": len(hairlod_menu_entries(bpy.types.TOPBAR_MT_file_import)) == 1,
        "export menu": len(hairlod_menu_entries(bpy.types.TOPBAR_MT_file_export)) == 1,
    }


def test_enable_disable_enable_is_clean():
    import addon_utils

    import_menu_before = len(menu_draw_functions(bpy.types.TOPBAR_MT_file_import))
    for _ in range(2):
        assert addon_utils.enable("hairlod", default_set=True) is not None
        assert all(registered().values()), registered()
        assert len(menu_draw_functions(bpy.types.TOPBAR_MT_file_import)) == import_menu_before + 1
        addon_utils.disable("hairlod", default_set=True)
        assert not any(registered().values()), registered()
        assert len(menu_draw_functions(bpy.types.TOPBAR_MT_file_import)) == import_menu_before
        assert not hairlod_menu_entries(bpy.types.TOPBAR_MT_file_export)


def test_import_creates_selected_active_curves(empty_scene, addon, shared_data):
    import hairlod.io

    path = str(shared_data / BANGS)
    assert bpy.ops.hairlod.import_hair(filepath=path) == {'FINISHED'}
    obj = bpy.context.active_object
    assert obj.name == "Bangs_100" and obj.type == 'CURVES'
    assert len(obj.data.curves) == 100 and len(obj.data.points) == 1165
    assert obj.select_get() and list(bpy.context.selected_objects) == [obj]
    assert list(obj.users_collection) == [bpy.context.collection]
    expected = hairlod.io.read(path)
    points = np.empty((1165, 3), np.float32)
    obj.data.attributes["position"].data.foreach_get("vector", points.ravel())
    np.testing.assert_array_equal(points, expected.points)


def test_import_of_a_bad_file_reports_and_creates_nothing(empty_scene, addon, tmp_path):
    bad = tmp_path / "broken.hair"
    bad.write_bytes(b"HAIR not really")
    objects, curves = len(bpy.data.objects), len(bpy.data.hair_curves)
    # In background mode an operator's ERROR report surfaces as RuntimeError.
    with pytest.raises(RuntimeError, match="Cannot import .*broken.hair"):
        bpy.ops.hairlod.import_hair(filepath=str(bad))
    with pytest.raises(RuntimeError, match="Cannot import .*missing.hair"):
        bpy.ops.hairlod.import_hair(filepath=str(tmp_path / "missing.hair"))
    assert (len(bpy.data.objects), len(bpy.data.hair_curves)) == (objects, curves)


@pytest.mark.parametrize("extension", [".hair", ".data"])
def test_export_reads_back_identical(empty_scene, addon, shared_data, tmp_path, extension):
    import hairlod.io
    from hairlod.blender.curves import curves_to_strands

    bpy.ops.hairlod.import_hair(filepath=str(shared_data / BANGS))
    target = tmp_path / ("exported" + extension)
    assert bpy.ops.hairlod.export_hair(filepath=str(target)) == {'FINISHED'}
    written = hairlod.io.read(str(target))
    expected = curves_to_strands(bpy.context.active_object)
    np.testing.assert_array_equal(written.offsets, expected.offsets)
    np.testing.assert_array_equal(written.points, expected.points)
    if extension == ".hair":  # .data stores no thickness
        np.testing.assert_allclose(written.radius, expected.radius, rtol=1e-6)


def test_export_needs_active_hair_curves(empty_scene, addon, tmp_path):
    mesh_obj = bpy.data.objects.new("Mesh", bpy.data.meshes.new("Mesh"))
    bpy.context.collection.objects.link(mesh_obj)
    bpy.context.view_layer.objects.active = mesh_obj
    assert not bpy.ops.hairlod.export_hair.poll()


def test_export_failure_reports_and_writes_nothing(empty_scene, addon, shared_data, tmp_path):
    bpy.ops.hairlod.import_hair(filepath=str(shared_data / BANGS))
    target = tmp_path / "unsupported.ply"
    with pytest.raises(RuntimeError, match="Cannot export"):
        bpy.ops.hairlod.export_hair(filepath=str(target))
    assert list(tmp_path.iterdir()) == []


def test_import_is_undoable(empty_scene, addon, shared_data):
    assert {'REGISTER', 'UNDO'} <= bpy.types.HAIRLOD_OT_import_hair.bl_options
    bpy.ops.ed.undo_push(message="before import")
    bpy.ops.hairlod.import_hair(filepath=str(shared_data / BANGS))
    bpy.ops.ed.undo_push(message="import")
    assert "Bangs_100" in bpy.data.objects
    bpy.ops.ed.undo()
    assert "Bangs_100" not in bpy.data.objects
    bpy.ops.ed.redo()
    assert len(bpy.data.objects["Bangs_100"].data.curves) == 100


def test_blend_file_keeps_imported_curves(empty_scene, addon, shared_data, tmp_path):
    bpy.ops.hairlod.import_hair(filepath=str(shared_data / BANGS))
    original = np.empty(1165 * 3, np.float32)
    bpy.data.objects["Bangs_100"].data.attributes["position"].data.foreach_get("vector", original)
    blend = str(tmp_path / "saved.blend")
    bpy.ops.wm.save_as_mainfile(filepath=blend)
    bpy.ops.wm.read_homefile(use_empty=True)
    assert "Bangs_100" not in bpy.data.objects
    bpy.ops.wm.open_mainfile(filepath=blend)
    obj = bpy.data.objects["Bangs_100"]
    assert obj.type == 'CURVES' and len(obj.data.curves) == 100 and len(obj.data.points) == 1165
    assert "curve_type" not in obj.data.attributes and "radius" in obj.data.attributes
    reopened = np.empty(1165 * 3, np.float32)
    obj.data.attributes["position"].data.foreach_get("vector", reopened)
    np.testing.assert_array_equal(reopened, original)
