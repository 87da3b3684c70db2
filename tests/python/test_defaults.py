"""Every default and range is defined once: the screen-width threshold comes from C++ (lod/selection.h,
hairlod._core) and the CLI, the Python API and the benchmarks all read it (the Blender properties:
tests/blender/test_lod_operator.py)."""

import inspect
import re

import pytest

from hairlod import _core, bench, cli, lod, quality, render


def test_width_threshold_comes_from_cpp():
    assert lod.DEFAULT_WIDTH_PX == pytest.approx(_core.DEFAULT_WIDTH_PX)
    assert lod.MIN_WIDTH_PX == pytest.approx(_core.MIN_WIDTH_PX)
    assert 0 < lod.MIN_WIDTH_PX < lod.DEFAULT_WIDTH_PX


@pytest.mark.parametrize("function", [lod.LodAsset.select, lod.scene_levels, lod.keep_scene_levels, render.render,
                                      render.coverage, render.lod_geometry, quality.bench_quality, bench.bench_lod])
def test_python_api_defaults_to_it(function):
    assert inspect.signature(function).parameters["width_px"].default == lod.DEFAULT_WIDTH_PX


def binding_default(function, name):
    """The default of argument `name` that pybind11 writes into the signature line of a binding's
    docstring. Its annotation varies with the pybind11 release (2.x `float`, 3.x `typing.SupportsFloat |
    typing.SupportsIndex`), and 3.x prints a float default through double (0.1f as 0.10000000149011612)."""
    found = re.search(rf"\b{name}: [^=]+? = ([-+0-9.eE]+)[,)]", function.__doc__)
    assert found, f"{name} has no default in {function.__doc__.splitlines()[0]}"
    return float(found.group(1))


@pytest.mark.parametrize("function", [_core.ViewSelection.update, _core.LodAsset.select, _core.LodAsset.time_selection])
def test_bindings_default_to_it(function):
    assert binding_default(function, "width_px") == pytest.approx(lod.DEFAULT_WIDTH_PX, rel=1e-6)


@pytest.mark.parametrize("command", [["lod", "hair.hair", "--out", "out"], ["bench", "lod"]])
def test_cli_defaults_to_it_and_refuses_less_than_the_minimum(command):
    parser = cli.build_parser()
    assert parser.parse_args(command).width_px == lod.DEFAULT_WIDTH_PX
    assert parser.parse_args(command + ["--width-px", str(lod.MIN_WIDTH_PX)]).width_px == lod.MIN_WIDTH_PX
    with pytest.raises(cli.UsageError, match=f"--width-px.*>= {lod.MIN_WIDTH_PX}"):
        parser.parse_args(command + ["--width-px", str(lod.MIN_WIDTH_PX / 2)])


def test_build_defaults_and_ranges_come_from_cpp():
    assert lod.LOD_DEFAULTS == {"guides": 0, "levels": _core.LOD_DEFAULTS["levels"],
                                "control_points": _core.LOD_DEFAULTS["control_points"], "seed": 0,
                                "ellipse_coverage": pytest.approx(_core.LOD_DEFAULTS["ellipse_coverage"])}
    parameters = inspect.signature(lod.build_lod).parameters
    for name in ("levels", "control_points", "seed", "ellipse_coverage"):
        assert parameters[name].default == lod.LOD_DEFAULTS[name]
    for command in (["lod", "hair.hair", "--out", "out"], ["bench", "lod"]):
        parsed = cli.build_parser().parse_args(command)
        assert (parsed.levels, parsed.control_points) == (lod.LOD_DEFAULTS["levels"], lod.LOD_DEFAULTS["control_points"])
    with pytest.raises(cli.UsageError, match="--levels"):
        cli.build_parser().parse_args(["lod", "hair.hair", "--out", "out", "--levels", str(lod.MAX_LEVELS + 1)])


def test_vertex_tolerance_comes_from_cpp():
    assert lod.DEFAULT_VERTEX_TOLERANCE_PX == pytest.approx(_core.DEFAULT_VERTEX_TOLERANCE_PX)
    assert lod.DEFAULT_VERTEX_TOLERANCE_PX > 0
    for function in (render.render, render.coverage, render.lod_geometry, quality.bench_quality):
        assert inspect.signature(function).parameters["vertex_tolerance_px"].default == lod.DEFAULT_VERTEX_TOLERANCE_PX
    assert binding_default(_core.vertex_lod_keep, "tolerance_px") == pytest.approx(lod.DEFAULT_VERTEX_TOLERANCE_PX, rel=1e-6)
    for command in (["render", "hair.hair", "--out", "x.png"], ["bench", "quality", "hair.hair"]):
        assert cli.build_parser().parse_args(command).vertex_tolerance_px == lod.DEFAULT_VERTEX_TOLERANCE_PX
