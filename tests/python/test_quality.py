"""bench quality (hairlod.quality and the CLI) on a tiny input: JSON structure and invariants; never times."""

import json
import math
import os
import subprocess
import sys

import pytest

from conftest import REPO

from hairlod import bench, io, quality, render


def run_cli(*args):
    env = dict(os.environ, PYTHONPATH=str(REPO / "addon"))
    return subprocess.run([sys.executable, "-m", "hairlod", *map(str, args)], capture_output=True, text=True, env=env,
                          timeout=600)


@pytest.fixture(scope="module")
def tiny_hair(tmp_path_factory):
    path = tmp_path_factory.mktemp("quality") / "tiny.hair"
    io.write(str(path), bench.synthetic_hair(300, 12))
    return path


def test_default_guides():
    assert quality.default_guides(100_000) == 256
    assert quality.default_guides(300) == 75
    assert quality.default_guides(2) == 1


def test_bench_quality_cli_json_and_plot(tiny_hair, tmp_path):
    plot = tmp_path / "q.png"
    run = run_cli("bench", "quality", tiny_hair, "--json", "--width", 32, "--spp", 2, "--reference-spp", 4,
                  "--eps-w", "1,4", "--plot", plot)
    assert run.returncode == 0, run.stderr
    result = json.loads(run.stdout, parse_constant=lambda name: pytest.fail(f"{name} in the JSON"))
    assert result["component"] == "quality" and result["strands"] == 300
    assert result["lod_build"]["guides"] == result["guides"] == 75
    assert set(result["views"]) == set(render.VIEWS)
    for view, entry in result["views"].items():
        # The reference is not compared with itself: it has no error fields, and no row repeats it.
        assert "flip" not in entry["reference"]
        assert set(entry["rows"]) == set(render.METHODS)
        for method, row in entry["rows"].items():
            assert 0.0 <= row["flip"] <= 1.0, (view, method)
            # PSNR is null (not Infinity, which is not JSON) when the 8-bit images are identical.
            assert -1.0 <= row["ssim"] <= 1.0 and (row["psnr"] is None or 0 < row["psnr"] < math.inf)
            assert row["segments"] == row["strand_segments"] + row["thick_segments"] > 0
            assert row["rays"] > 0 and row["rays_per_second"] > 0
        full = entry["rows"]["pt"]["segments"]
        assert entry["rows"]["ds"]["segments"] == full == entry["reference"]["segments"]
        assert entry["rows"]["pt"]["thick_segments"] == 0
    far = result["views"]["far"]["rows"]
    assert far["lod"]["segments"] <= far["pt"]["segments"]
    assert far["lod"]["segments"] == far["lod-single"]["segments"] == far["lod-no-s"]["segments"]
    assert result["summary"]["far"]["segment_reduction"] >= 1.0
    sweep = result["sweep"]
    assert sweep["view"] == "mid" and [r["eps_w"] for r in sweep["rows"]] == [1.0, 4.0]
    # A coarser threshold never draws more segments.
    assert sweep["rows"][1]["segments"] <= sweep["rows"][0]["segments"] <= sweep["full_segments"]
    assert all(0.0 <= r["flip"] <= 1.0 for r in sweep["rows"])
    assert result["plot"] == str(plot) and plot.stat().st_size > 1000
    assert sorted(os.listdir(tmp_path)) == ["q.png"]


@pytest.mark.parametrize("args, needle", [
    ((), "input hair file"),
    (("{hair}", "--spp", "0"), "--spp"),
    (("{hair}", "--eps-w", "1,x"), "--eps-w"),
    (("{hair}", "--plot", "out.jpg"), "out.jpg"),
    (("missing.hair",), "missing.hair"),
])
def test_bench_quality_bad_input(tiny_hair, args, needle):
    run = run_cli("bench", "quality", *[str(a).format(hair=tiny_hair) for a in args], "--json")
    assert run.returncode == 2 and needle in run.stderr and run.stdout == ""
    assert len(run.stderr.strip().splitlines()) == 1 and "Traceback" not in run.stderr
