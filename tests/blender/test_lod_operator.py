"""Build Hair LoD (hairlod.build_lod) on a hair Curves object, headless."""

import bpy
import numpy as np
import pytest

from hairlod import lod
from hairlod.blender.curves import curves_to_strands, strands_to_curves
from hairlod.blender.lod_build_job import COLLECTION_NAME, LodBuildJob, scene_cameras
from hairlod.blender.packed_asset import PACKED_PROPERTY, packed_asset
from hair_fixtures import hanging_hair

pytestmark = pytest.mark.usefixtures("addon")


def start_job(obj, guides, levels, control_points, seed=0, level_objects=False):
    """A LodBuildJob with the sidebar's defaults for what a test does not set."""
    return LodBuildJob(bpy.context, obj, guides, levels, control_points, seed, False, 1, lod.DEFAULT_WIDTH_PX,
                       level_objects)


@pytest.fixture
def hair_object():
    obj = strands_to_curves(hanging_hair(), "Hair")
    bpy.context.view_layer.objects.active = obj
    yield obj
    collection = bpy.data.collections.get(COLLECTION_NAME)
    if collection is not None:
        for child in list(collection.objects):
            bpy.data.objects.remove(child)
        bpy.data.collections.remove(collection)
    bpy.data.objects.remove(obj)


def test_build_lod_packs_the_asset_and_makes_no_objects_by_default(hair_object):
    objects, curves = len(bpy.data.objects), len(bpy.data.hair_curves)
    assert bpy.ops.hairlod.build_lod(guides=12, levels=4, control_points=6, seed=1) == {'FINISHED'}
    assert packed_asset(hair_object).strand_count == 600
    assert (len(bpy.data.objects), len(bpy.data.hair_curves)) == (objects, curves)
    assert COLLECTION_NAME not in bpy.data.collections


def test_build_lod_creates_one_hidden_curves_object_per_level_on_request(hair_object):
    assert bpy.ops.hairlod.build_lod(guides=12, levels=4, control_points=6, seed=1, level_objects=True) == {'FINISHED'}
    collection = bpy.data.collections[COLLECTION_NAME]
    objects = sorted(collection.objects, key=lambda o: o.name)
    assert [o.name for o in objects] == [f"Hair LoD L{level}" for level in range(len(objects))]
    assert 1 <= len(objects) <= 3
    # Data for engines and scripts: neither drawn over the hair nor rendered.
    assert all(obj.hide_get() and obj.hide_render for obj in objects)
    assert not hair_object.hide_get() and not hair_object.hide_render
    for level, obj in enumerate(objects):
        strands = curves_to_strands(obj)
        attributes = set(strands.attribute_names())
        assert {"major_radius", "minor_radius", "major_axis", "minor_axis", "n_total", "density", "cluster",
                "level"} <= attributes
        assert strands.attribute("n_total").sum() == 600
        assert np.all(strands.attribute("level") == level)
        assert np.allclose(strands.radius, strands.attribute("major_radius"))
        assert np.all(strands.attribute("major_radius") >= strands.attribute("minor_radius"))
        assert np.all(np.diff(strands.offsets) == 6)
    # The asset is packed into the source object, levels and all.
    asset = packed_asset(hair_object)
    assert asset.strand_count == 600 and asset.level_ids == list(range(len(objects)))


def test_unset_parameters_come_from_the_objects_build_settings(hair_object):
    settings = hair_object.hairlod_lod_build
    settings.guides, settings.levels, settings.control_points = 9, 3, 5
    assert bpy.ops.hairlod.build_lod() == {'FINISHED'}
    asset = packed_asset(hair_object)
    assert (asset.guide_count, len(asset.levels) + 1, asset.control_points) == (9, 3, 5)
    # A parameter the caller passes wins over the setting; the others still come from the object.
    del hair_object[PACKED_PROPERTY]
    assert bpy.ops.hairlod.build_lod(guides=7) == {'FINISHED'}
    asset = packed_asset(hair_object)
    assert (asset.guide_count, asset.control_points) == (7, 5)


def test_build_lod_needs_hair_curves():
    bpy.ops.object.select_all(action='DESELECT')
    bpy.context.view_layer.objects.active = None
    assert not bpy.ops.hairlod.build_lod.poll()
    with pytest.raises(RuntimeError):
        bpy.ops.hairlod.build_lod()


def test_failed_build_leaves_nothing_behind(hair_object):
    hair_object.data.attributes["position"].data.foreach_set("vector", np.full(600 * 8 * 3, np.nan, np.float32))
    objects_before = len(bpy.data.objects)
    with pytest.raises(RuntimeError, match="Cannot build"):
        bpy.ops.hairlod.build_lod(guides=4, levels=3, control_points=4)
    assert len(bpy.data.objects) == objects_before
    assert COLLECTION_NAME not in bpy.data.collections


def _assert_same_asset(a, b):
    arrays_a, arrays_b = a.arrays(), b.arrays()
    assert set(arrays_a) == set(arrays_b)
    for name in arrays_a:
        if name != "levels":
            assert np.array_equal(arrays_a[name], arrays_b[name]), name
    for level_a, level_b in zip(arrays_a["levels"], arrays_b["levels"]):
        for name in level_a:
            assert np.array_equal(level_a[name], level_b[name]), name
    assert a.scalars() == b.scalars() and a.level_ids == b.level_ids


def _lod_objects():
    collection = bpy.data.collections.get(COLLECTION_NAME)
    return [] if collection is None else list(collection.objects)


def test_cancel_before_the_build_ends_leaves_nothing(hair_object):
    objects, curves = len(bpy.data.objects), len(bpy.data.hair_curves)
    job = start_job(hair_object, guides=12, levels=4, control_points=6)
    job.cancel()  # what Esc in the modal operator calls
    assert job.progress.cancelled
    assert (len(bpy.data.objects), len(bpy.data.hair_curves)) == (objects, curves)
    assert COLLECTION_NAME not in bpy.data.collections and PACKED_PROPERTY not in hair_object


def test_cancel_after_some_levels_removes_them(hair_object):
    objects, curves = len(bpy.data.objects), len(bpy.data.hair_curves)
    job = start_job(hair_object, guides=12, levels=4, control_points=6, level_objects=True)
    fractions = []
    while len(job.created) < 2:
        assert not job.step()
        fractions.append(job.fraction)
    assert fractions == sorted(fractions) and 0 < fractions[-1] < 1
    assert len(_lod_objects()) == 2
    job.cancel()
    assert (len(bpy.data.objects), len(bpy.data.hair_curves)) == (objects, curves)
    assert COLLECTION_NAME not in bpy.data.collections and PACKED_PROPERTY not in hair_object


def test_stepped_job_matches_the_operator(hair_object):
    job = start_job(hair_object, guides=12, levels=4, control_points=6, seed=1, level_objects=True)
    while not job.step():
        pass
    assert job.fraction == 1.0 and len(_lod_objects()) == len(job.asset.levels)
    _assert_same_asset(packed_asset(hair_object), job.asset)


def test_packed_asset_survives_save_and_reopen(addon, tmp_path):
    obj = strands_to_curves(hanging_hair(), "Packed Hair")
    bpy.context.view_layer.objects.active = obj
    assert bpy.ops.hairlod.build_lod(guides=12, levels=4, control_points=6, seed=2, level_objects=True) == {'FINISHED'}
    before = packed_asset(obj)
    path = str(tmp_path / "packed.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)
    bpy.ops.wm.open_mainfile(filepath=path)
    reopened = bpy.data.objects["Packed Hair"]
    after = packed_asset(reopened)
    _assert_same_asset(before, after)
    rest_before, rest_after = before.skin(before.rest_guides), after.skin(after.rest_guides)
    assert np.array_equal(rest_before["strands"].points, rest_after["strands"].points)
    assert sorted(o.name for o in bpy.data.collections[COLLECTION_NAME].objects) == [
        f"Packed Hair LoD L{level}" for level in before.level_ids]
    bpy.ops.wm.read_homefile(use_empty=True)


def _animated_camera(locations, name="Camera"):
    """A camera looking at the origin from `locations` at frames 1, 2, ... (keyframed)."""
    from mathutils import Vector

    camera = bpy.data.objects.new(name, bpy.data.cameras.new(name))
    camera.data.clip_end = 10000.0
    bpy.context.scene.collection.objects.link(camera)
    for frame, location in enumerate(locations, start=1):
        camera.location = location
        camera.rotation_euler = (-Vector(location)).to_track_quat('-Z', 'Y').to_euler()
        camera.keyframe_insert("location", frame=frame)
        camera.keyframe_insert("rotation_euler", frame=frame)
    return camera


def test_scene_cameras_sample_every_camera_over_the_frame_range(addon, empty_scene):
    scene = empty_scene
    scene.frame_start, scene.frame_end, scene.frame_current = 1, 5, 3
    scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = 800, 600, 50
    source = strands_to_curves(hanging_hair(), "Hair")
    source.location = (0.5, 0, 0)
    moving = _animated_camera([(10 + 2 * f, 0, 1) for f in range(5)])
    _animated_camera([(0, 8, 0)] * 5, name="Still")
    cameras = scene_cameras(bpy.context, source, frame_step=2)
    assert len(cameras) == 3 * 2  # frames 1, 3, 5 x two cameras
    assert scene.frame_current == 3
    assert all(camera["viewport"] == (400.0, 300.0) for camera in cameras)
    # Frame 3 of the moving camera: view = camera^-1 x source, the camera at its frame-3 key.
    scene.frame_set(3)
    expected = np.array(moving.matrix_world.inverted()) @ np.array(source.matrix_world)
    assert np.allclose(cameras[2]["view"], expected, atol=1e-5)
    assert np.allclose(expected @ np.array([-0.5, 0, 0, 1]), np.array(moving.matrix_world.inverted()) @ [0, 0, 0, 1],
                       atol=1e-5)


def test_scene_cameras_option_drops_levels_no_camera_needs(addon, empty_scene):
    scene = empty_scene
    scene.frame_start, scene.frame_end = 1, 4
    scene.render.resolution_x, scene.render.resolution_y = 640, 480
    source = strands_to_curves(hanging_hair(curves=2000, points=8), "Hair")
    bpy.context.view_layer.objects.active = source
    options = {"guides": 12, "levels": 5, "control_points": 6, "seed": 1, "level_objects": True}
    assert bpy.ops.hairlod.build_lod(**options) == {'FINISHED'}
    every_level = packed_asset(source).level_ids
    assert len(every_level) == 4
    for obj in _lod_objects():
        bpy.data.objects.remove(obj)
    # A camera that only ever stays far away: the finest thick levels are not built.
    camera = _animated_camera([(1500 + 500 * f, 0, 0) for f in range(4)])
    assert bpy.ops.hairlod.build_lod(scene_cameras=True, frame_step=1, **options) == {'FINISHED'}
    far_levels = packed_asset(source).level_ids
    print("levels for the far camera", far_levels, "of", every_level)
    assert far_levels[0] == 0 and max(far_levels) < max(every_level)
    assert len(_lod_objects()) == len(far_levels)
    for obj in _lod_objects():
        bpy.data.objects.remove(obj)
    # The same camera flying in close at the last frame needs finer levels.
    bpy.data.objects.remove(camera)
    _animated_camera([(1500, 0, 0), (100, 0, 0), (10, 0, 0), (3, 0, 0)])
    assert bpy.ops.hairlod.build_lod(scene_cameras=True, frame_step=1, **options) == {'FINISHED'}
    close_levels = packed_asset(source).level_ids
    assert max(close_levels) > max(far_levels)
    # Cameras Only keeps what the object's one width threshold (the preview's) selects: a wider one
    # lets the same cameras do with the coarsest level alone.
    source.hairlod_lod_preview.width_px = 10000.0
    assert bpy.ops.hairlod.build_lod(scene_cameras=True, frame_step=1, **options) == {'FINISHED'}
    assert packed_asset(source).level_ids == [0]


def test_one_width_property_with_the_cores_default_and_minimum(hair_object):
    settings = hair_object.hairlod_lod_preview
    definition = settings.bl_rna.properties["width_px"]
    assert definition.default == pytest.approx(lod.DEFAULT_WIDTH_PX)
    assert definition.hard_min == pytest.approx(lod.MIN_WIDTH_PX)
    assert "width_px" not in hair_object.hairlod_lod_build.bl_rna.properties
    assert "width_px" not in bpy.types.HAIRLOD_OT_build_lod.bl_rna.properties


def test_scene_cameras_option_needs_a_camera(addon, empty_scene):
    source = strands_to_curves(hanging_hair(), "Hair")
    bpy.context.view_layer.objects.active = source
    with pytest.raises(RuntimeError, match="no camera"):
        bpy.ops.hairlod.build_lod(guides=4, levels=3, control_points=4, scene_cameras=True)
    assert COLLECTION_NAME not in bpy.data.collections


def _export(folder):
    return bpy.ops.hairlod.export_lod(directory=str(folder), bake=True)


def test_export_writes_lod_and_tables_beside_the_users_files(hair_object, tmp_path):
    from hairlod import lod

    assert bpy.ops.hairlod.build_lod(guides=12, levels=4, control_points=6, seed=1) == {'FINISHED'}
    (tmp_path / "notes.txt").write_text("mine")
    assert _export(tmp_path) == {'FINISHED'}
    assert lod.load(tmp_path / "lod").strand_count == 600
    assert (tmp_path / "bcsdf" / "manifest.json").is_file()
    # Exporting again replaces the folders it wrote, and only those.
    assert _export(tmp_path) == {'FINISHED'}
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bcsdf", "lod", "notes.txt"]
    assert (tmp_path / "notes.txt").read_text() == "mine"


def test_preview_bake_and_export_use_one_hair(hair_object, tmp_path):
    # No material: the export bakes the hair the preview shades (the panel's), not another default;
    # the panel's hair changes both; with a Principled Hair material, both use the material.
    import json

    from hairlod import hair_params
    from hairlod.blender.preview.lod_preview import uses_material
    from hairlod.blender.principled_hair import new_hair_material, object_hair_params

    assert bpy.ops.hairlod.build_lod(guides=12, levels=4, control_points=6, seed=1) == {'FINISHED'}
    settings = hair_object.hairlod_lod_preview

    def baked():
        assert _export(tmp_path) == {'FINISHED'}
        return json.loads((tmp_path / "bcsdf" / "manifest.json").read_text())["params"]

    assert baked() == hair_params.params_to_dict(object_hair_params(hair_object))
    settings.melanin = 0.9
    darker = baked()
    assert darker == hair_params.params_to_dict(object_hair_params(hair_object)) and darker["sigma_a"][0] > 0.5
    hair_object.data.materials.append(new_hair_material("Blond", {"parametrization": 'MELANIN', "melanin": 0.1}))
    assert uses_material(hair_object, settings)
    blond = baked()
    assert blond == hair_params.params_to_dict(object_hair_params(hair_object)) and blond["sigma_a"][0] < darker["sigma_a"][0]


@pytest.mark.skipif(bpy.app.version < (4, 0, 0), reason="Blender before 4.0 has no Huang hair model")
def test_a_default_huang_hair_material_works_in_every_operator(hair_object, tmp_path):
    # Blender 4.x's hair material: the Principled Hair BSDF in Huang mode with its default inputs. The
    # build, the preview's hair and the export with its bake all take it; the bake is made on the
    # Chiang fibre fitted to it, and the manifest says which fibre the material has.
    import json

    from hairlod.blender.preview.lod_preview import uses_material
    from hairlod.blender.principled_hair import new_hair_material, object_hair_params

    hair_object.data.materials.append(new_hair_material("Huang", {"model": "HUANG"}))
    settings = hair_object.hairlod_lod_preview
    assert uses_material(hair_object, settings)
    params = object_hair_params(hair_object)
    assert params.fibre == "huang" and params.aspect_ratio == pytest.approx(0.85)
    assert bpy.ops.hairlod.build_lod(guides=12, levels=4, control_points=6, seed=1) == {'FINISHED'}
    assert _export(tmp_path) == {'FINISHED'}
    baked = json.loads((tmp_path / "bcsdf" / "manifest.json").read_text())["params"]
    assert baked["fibre"] == "huang" and baked["microfacet_roughness"] == pytest.approx(0.3)


@pytest.mark.parametrize("foreign", ["lod", "bcsdf"])
def test_export_refuses_folders_it_did_not_write_and_changes_nothing(hair_object, tmp_path, foreign):
    assert bpy.ops.hairlod.build_lod(guides=12, levels=4, control_points=6, seed=1) == {'FINISHED'}
    (tmp_path / foreign).mkdir()
    (tmp_path / foreign / "mine.txt").write_text("mine")
    with pytest.raises(RuntimeError, match=f"Cannot export.*{foreign}.*not .* that hairlod wrote"):
        _export(tmp_path)
    assert sorted(p.name for p in tmp_path.iterdir()) == [foreign]
    assert [p.name for p in (tmp_path / foreign).iterdir()] == ["mine.txt"]


def test_build_settings_default_to_the_cores_options(hair_object):
    properties = hair_object.hairlod_lod_build.bl_rna.properties
    for name in ("guides", "levels", "control_points", "seed"):
        assert properties[name].default == lod.LOD_DEFAULTS[name], name
    assert (properties["levels"].hard_min, properties["levels"].hard_max) == (lod.MIN_LEVELS, lod.MAX_LEVELS)
    assert properties["control_points"].hard_min == lod.MIN_CONTROL_POINTS


def test_the_preview_replaces_a_hair_objects_drawing_and_leaves_an_empty_its_own(hair_object):
    """A hair object draws as its bounds while its preview is on and gets its own display back after;
    an empty that holds a preview keeps its display (Blender 5 would draw it as a cube)."""
    from hairlod.blender.preview import lod_preview

    hair_object.display_type = 'WIRE'
    lod_preview.replace_source_display(hair_object, True)
    assert hair_object.display_type == 'BOUNDS'
    lod_preview.replace_source_display(hair_object, False)
    assert hair_object.display_type == 'WIRE' and lod_preview.SOURCE_DISPLAY_PROPERTY not in hair_object
    empty = bpy.data.objects.new("holder", None)
    lod_preview.replace_source_display(empty, True)
    assert empty.display_type == 'TEXTURED' and lod_preview.SOURCE_DISPLAY_PROPERTY not in empty
    # One an older release drew as its bounds gets its own display back with the preview off.
    empty.display_type, empty[lod_preview.SOURCE_DISPLAY_PROPERTY] = 'BOUNDS', 'TEXTURED'
    lod_preview.replace_source_display(empty, False)
    assert empty.display_type == 'TEXTURED' and lod_preview.SOURCE_DISPLAY_PROPERTY not in empty
    bpy.data.objects.remove(empty)
