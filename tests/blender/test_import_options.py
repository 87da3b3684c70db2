"""File > Import > Hair Strands options: Forward / Up / Scale, the Source presets, remembered values,
the side panel and the menu name (hairlod.blender.operators)."""

import math
import os
import re

import bpy
import numpy as np
import pytest

# TressFX's Ratboy mohawk: Y up, in metres (bundled, see examples/data/tressfx/LICENSE).
REPO_ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), os.pardir, os.pardir))
RATBOY = os.path.join(REPO_ROOT, "examples", "data", "tressfx", "Ratboy_mohawk.tfx")
OPTIONS = ("source", "axis_forward", "axis_up", "global_scale", "default_radius")


def import_hair(path, *call_args, **options):
    """Imports `path` with bpy.ops (call_args: the operator's context and undo flag) and returns the
    new object's points and radii."""
    assert bpy.ops.hairlod.import_hair(*call_args, filepath=str(path), **options) == {'FINISHED'}
    curves = bpy.context.active_object.data
    points = np.empty((len(curves.points), 3), np.float32)
    curves.attributes["position"].data.foreach_get("vector", points.ravel())
    radius = np.empty(len(curves.points), np.float32)
    curves.attributes["radius"].data.foreach_get("value", radius)
    return points, radius


def y_up_to_z_up(points):
    """Blender's own conversion of a Y-up file (-Z Forward, Y Up): (x, y, z) -> (x, -z, y)."""
    return np.stack([points[:, 0], -points[:, 2], points[:, 1]], axis=1)


def operator_property(name):
    return bpy.ops.hairlod.import_hair.get_rna_type().properties[name]


def last_used():
    """The values the next import from the user interface starts with."""
    return bpy.context.window_manager.operator_properties_last("hairlod.import_hair")


@pytest.fixture
def ratboy():
    import hairlod.io

    return hairlod.io.read(RATBOY)


@pytest.fixture
def centimetre_file(ratboy, tmp_path):
    """Ratboy in centimetres, with radii that differ per point, as a .hair file (which stores them)."""
    import hairlod.io

    strands = ratboy.copy()
    strands.points[:] *= 100
    strands.radius[:] = np.linspace(0.005, 0.02, strands.point_count, dtype=np.float32)
    path = tmp_path / "ratboy_cm.hair"
    hairlod.io.write(path, strands)
    return path, hairlod.io.read(path)


def test_defaults_leave_the_points_unchanged(empty_scene, addon, ratboy):
    assert (operator_property("axis_forward").default, operator_property("axis_up").default) == ('Y', 'Z')
    assert operator_property("global_scale").default == 1.0
    assert operator_property("source").default == 'BLENDER'
    points, radius = import_hair(RATBOY)
    np.testing.assert_array_equal(points, ratboy.points)
    np.testing.assert_array_equal(radius, ratboy.radius)


def test_y_up_preset_stands_the_hair_upright(empty_scene, addon, ratboy):
    points, radius = import_hair(RATBOY, source='Y_UP')
    lower, upper = ratboy.bounding_box()
    # The file's height (y) becomes the height in Blender (z), exactly: the conversion only swaps axes.
    assert (points[:, 2].min(), points[:, 2].max()) == (lower[1], upper[1])
    # The mohawk is taller than deep: on its side in the file read as Z up, upright now.
    assert np.ptp(ratboy.points[:, 2]) < np.ptp(ratboy.points[:, 1])
    assert np.ptp(points[:, 2]) > np.ptp(points[:, 1])
    np.testing.assert_array_equal(points, y_up_to_z_up(ratboy.points))
    np.testing.assert_array_equal(radius, ratboy.radius)
    # The preset is -Z Forward, Y Up, as Blender's own importers call a Y-up file.
    explicit, _ = import_hair(RATBOY, axis_forward='-Z', axis_up='Y')
    np.testing.assert_array_equal(explicit, points)


def test_scale_shrinks_points_and_radii(empty_scene, addon, centimetre_file):
    path, in_file = centimetre_file
    points, radius = import_hair(path, global_scale=0.01)
    np.testing.assert_allclose(points, in_file.points * np.float32(0.01), rtol=1e-6)
    np.testing.assert_allclose(radius, in_file.radius * np.float32(0.01), rtol=1e-6)
    assert np.ptp(in_file.points, axis=0) == pytest.approx(100 * np.ptp(points, axis=0), rel=1e-5)


def test_centimetre_preset_gives_the_hair_in_metres_upright(empty_scene, addon, centimetre_file, ratboy):
    path, in_file = centimetre_file
    points, radius = import_hair(path, source='Y_UP_CM')
    np.testing.assert_allclose(points, y_up_to_z_up(ratboy.points), rtol=1e-6, atol=1e-7)
    np.testing.assert_allclose(radius, in_file.radius / 100, rtol=1e-6)


def test_default_radius_is_in_the_scene_whatever_the_scale(empty_scene, addon, ratboy, tmp_path):
    import hairlod.io

    strands = ratboy.copy()
    strands.points[:] *= 100
    path = tmp_path / "ratboy_cm.data"  # .data stores no thickness
    hairlod.io.write(path, strands)
    _, radius = import_hair(path, global_scale=0.01, default_radius=0.0002)
    np.testing.assert_allclose(radius, 0.0002, rtol=1e-6)
    # Automatic (0): 1/10000 of the diagonal, of the file's hair and so of the scaled hair alike.
    _, automatic = import_hair(path, global_scale=0.01)
    np.testing.assert_allclose(automatic, hairlod.io.read(path).radius * 0.01, rtol=1e-6)


def test_scale_of_zero_or_less_is_refused_by_its_range(empty_scene, addon, ratboy):
    smallest = operator_property("global_scale").hard_min
    assert 0 < smallest <= 1e-4
    for bad in (0.0, -1.0, -0.01):
        points, radius = import_hair(RATBOY, global_scale=bad)  # clamped: not flattened, not mirrored
        np.testing.assert_allclose(points, ratboy.points * np.float32(smallest), rtol=1e-6)
        np.testing.assert_allclose(radius, ratboy.radius * np.float32(smallest), rtol=1e-6)
    objects = len(bpy.data.objects)
    # NaN passes any range: the operator refuses it.
    with pytest.raises(RuntimeError, match="Cannot import .*Scale must be a positive number, got nan"):
        bpy.ops.hairlod.import_hair(filepath=RATBOY, global_scale=math.nan)
    assert len(bpy.data.objects) == objects


def test_values_passed_with_a_source_replace_the_presets(empty_scene, addon, ratboy):
    points, _ = import_hair(RATBOY, source='Y_UP_CM', global_scale=0.5)
    np.testing.assert_allclose(points, y_up_to_z_up(ratboy.points) * np.float32(0.5), rtol=1e-6)


def test_last_used_options_are_remembered(empty_scene, addon, ratboy):
    assert not any(operator_property(name).is_skip_save for name in OPTIONS)
    # bpy.ops(..., 'EXEC_DEFAULT', True): a call made as the user interface makes it, which stores
    # the values it used and starts from the stored ones.
    first, _ = import_hair(RATBOY, 'EXEC_DEFAULT', True, source='Y_UP_CM', default_radius=0.001)
    remembered = last_used()
    assert (remembered.source, remembered.axis_forward, remembered.axis_up) == ('Y_UP_CM', '-Z', 'Y')
    assert remembered.global_scale == pytest.approx(0.01)
    assert remembered.default_radius == pytest.approx(0.001)
    again, _ = import_hair(RATBOY, 'EXEC_DEFAULT', True)
    np.testing.assert_array_equal(again, first)
    # A script's call uses neither: it gets the defaults.
    plain, _ = import_hair(RATBOY)
    np.testing.assert_array_equal(plain, ratboy.points)
    # Back to the Blender preset from Y up: its axes land exactly (each axis update moves the other).
    back, _ = import_hair(RATBOY, 'EXEC_DEFAULT', True, source='BLENDER')
    np.testing.assert_array_equal(back, ratboy.points)
    assert (last_used().axis_forward, last_used().axis_up, last_used().global_scale) == ('Y', 'Z', 1.0)


@pytest.mark.parametrize("values, source", [
    (dict(axis_forward='-Z', axis_up='Y'), 'Y_UP'),
    (dict(axis_forward='-Z', axis_up='Y', global_scale=0.01), 'Y_UP_CM'),
    (dict(axis_forward='-Z', axis_up='Y', global_scale=0.5), 'CUSTOM'),
    (dict(axis_forward='X', axis_up='Z'), 'CUSTOM'),
    (dict(source='CUSTOM', axis_forward='Y', axis_up='Z', global_scale=1.0), 'BLENDER'),
])
def test_source_shows_the_preset_the_values_match(empty_scene, addon, values, source):
    import_hair(RATBOY, 'EXEC_DEFAULT', True, **values)
    assert last_used().source == source


def test_check_keeps_axes_apart_and_source_up_to_date(empty_scene, addon):
    from hairlod.blender.operators import HAIRLOD_OT_import_hair

    import_hair(RATBOY, 'EXEC_DEFAULT', True)
    properties = last_used()  # real operator properties, with their update callbacks
    properties.source = 'Y_UP_CM'
    assert (properties.axis_forward, properties.axis_up, properties.global_scale) == ('-Z', 'Y', pytest.approx(0.01))
    assert not HAIRLOD_OT_import_hair.check(properties, bpy.context)
    properties.global_scale = 0.1  # edited by hand: the preset no longer applies
    assert HAIRLOD_OT_import_hair.check(properties, bpy.context)
    assert properties.source == 'CUSTOM' and properties.global_scale == pytest.approx(0.1)
    properties.axis_up = 'Z'  # same axis as Forward: Forward moves off it
    HAIRLOD_OT_import_hair.check(properties, bpy.context)
    assert properties.axis_forward[-1] != properties.axis_up[-1] == 'Z'


class RecordingLayout:
    """Stands in for a UILayout: records the properties and operator texts drawn through it."""

    def __init__(self):
        self.props, self.operators = [], []

    def prop(self, data, name, **_):
        self.props.append(name)

    def operator(self, idname, text="", **_):
        self.operators.append((idname, text))

    def column(self, **_):
        return self

    row = box = column


def test_side_panel_draws_every_option_with_a_tooltip(addon):
    from types import SimpleNamespace

    from hairlod.blender.operators import HAIRLOD_OT_import_hair

    layout = RecordingLayout()
    HAIRLOD_OT_import_hair.draw(SimpleNamespace(layout=layout), bpy.context)
    assert sorted(layout.props) == sorted(OPTIONS)
    for name in OPTIONS:
        assert operator_property(name).name and operator_property(name).description, name
    shown = {identifier for identifier, prop in operator_property("source").enum_items.items()}
    assert shown == {'BLENDER', 'Y_UP', 'Y_UP_CM', 'CUSTOM'}
    assert all(item.description for item in operator_property("source").enum_items)


def test_menus_and_readme_use_one_name(addon):
    import hairlod.io
    from types import SimpleNamespace

    from hairlod.blender.operators import menu_func_export, menu_func_import

    with open(os.path.join(REPO_ROOT, "README.md"), encoding="utf-8") as readme:
        text = readme.read()
    for menu_func, menu, formats in ((menu_func_import, "Import", hairlod.io.READ_FORMATS),
                                     (menu_func_export, "Export", hairlod.io.WRITE_FORMATS)):
        layout = RecordingLayout()
        menu_func(SimpleNamespace(layout=layout), bpy.context)
        [(_, menu_text)] = layout.operators
        assert menu_text == f"Hair Strands ({', '.join(formats)})"
        assert re.findall(rf"\*\*File > {menu} > ([^*]+)\*\*", text) == ["Hair Strands"], menu
    layout = RecordingLayout()
    menu_func_import(SimpleNamespace(layout=layout), bpy.context)
    assert layout.operators == [("hairlod.import_hair", "Hair Strands (.hair, .data, .bin, .ply, .tfx)")]
    assert bpy.types.HAIRLOD_OT_import_hair.bl_label == "Import Hair Strands"
