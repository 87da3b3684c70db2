"""The command line as a user runs it: a subprocess of /usr/bin/python3 -m hairlod."""

import json
import os
import struct
import subprocess
import sys

import numpy as np
import pytest

from conftest import REPO
from hairlod import lod

BUNDLED = REPO / "examples" / "data" / "bob.hair"
BANGS = ["Bangs_100.hair", "Bangs_100.data", "Bangs_100.bin", "Bangs_100_ascii.ply", "Bangs_100_binary.ply"]


def run_cli(*args):
    env = dict(os.environ, PYTHONPATH=str(REPO / "addon"))
    return subprocess.run([sys.executable, "-m", "hairlod", *map(str, args)], capture_output=True, text=True,
                          env=env, cwd=REPO)


@pytest.mark.parametrize("name", BANGS)
def test_info_json_on_shared_files(shared_data, name):
    result = run_cli("info", shared_data / name, "--json")
    assert result.returncode == 0, result.stderr
    info = json.loads(result.stdout)
    assert info["strands"] == 100
    assert info["points"] == 1165
    assert info["points_per_strand"] == {"min": 5, "mean": 11.65, "max": 21}
    assert info["total_length"] > 0
    lower, upper = np.array(info["bounding_box"]["min"]), np.array(info["bounding_box"]["max"])
    assert np.all(lower < upper)
    assert info["read_seconds"] >= 0


def test_info_agrees_across_formats(shared_data):
    infos = [json.loads(run_cli("info", shared_data / name, "--json").stdout) for name in BANGS]
    for info in infos[1:]:
        assert info["bounding_box"] == infos[0]["bounding_box"]
        assert info["total_length"] == pytest.approx(infos[0]["total_length"], rel=1e-12)


def test_info_human_readable(shared_data):
    result = run_cli("info", shared_data / "Curly_100.ply")
    assert result.returncode == 0
    assert "strands            100" in result.stdout
    assert "points             2528" in result.stdout


def test_convert_round_trip(shared_data, tmp_path):
    out = tmp_path / "bangs.data"
    result = run_cli("convert", shared_data / "Bangs_100_binary.ply", out, "--json")
    assert result.returncode == 0, result.stderr
    summary = json.loads(result.stdout)
    assert summary["strands"] == 100 and summary["points"] == 1165
    again = json.loads(run_cli("info", out, "--json").stdout)
    original = json.loads(run_cli("info", shared_data / "Bangs_100.hair", "--json").stdout)
    assert again["bounding_box"] == original["bounding_box"]


def one_line_error(result):
    assert result.returncode == 2
    assert result.stdout == ""
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1, result.stderr
    assert "Traceback" not in result.stderr
    return lines[0]


def test_missing_file(tmp_path):
    line = one_line_error(run_cli("info", tmp_path / "nothing.hair"))
    assert "nothing.hair" in line


def test_unknown_extension(tmp_path):
    path = tmp_path / "hair.xyz"
    path.write_bytes(b"1234")
    line = one_line_error(run_cli("info", path))
    assert "hair.xyz" in line and ".hair" in line


def test_hostile_header_is_rejected_before_allocating(tmp_path):
    path = tmp_path / "hostile.hair"
    header = b"HAIR" + struct.pack("<IIIIff3f", 2**31, 2**31, 3, 0, 1.0, 0.0, 1.0, 1.0, 1.0)
    path.write_bytes(header.ljust(128, b"\0") + bytes(100))
    line = one_line_error(run_cli("info", path))
    assert "hostile.hair" in line


@pytest.mark.parametrize("length", [0, 3, 127, 128, 5000, 512127])
def test_truncated_file(tmp_path, length):
    path = tmp_path / "truncated.hair"
    path.write_bytes(BUNDLED.read_bytes()[:length])
    line = one_line_error(run_cli("info", path))
    assert "truncated.hair" in line


def test_a_message_quoting_bytes_that_are_not_utf8_keeps_its_text(tmp_path):
    path = tmp_path / "x.ply"
    path.write_bytes(b"ply\n\xef\n")
    line = one_line_error(run_cli("info", path))
    assert "x.ply: header line 2: unknown keyword" in line and "\\xef" in line


def test_info_on_bundled_input():
    info = json.loads(run_cli("info", BUNDLED, "--json").stdout)
    assert info["strands"] == 2000 and info["points"] == 32000


def test_convert_leaves_no_partial_output(tmp_path):
    out = tmp_path / "out.hair"
    bad = tmp_path / "bad.hair"
    bad.write_bytes(BUNDLED.read_bytes()[:1000])
    one_line_error(run_cli("convert", bad, out))
    assert list(tmp_path.iterdir()) == [bad]


def test_convert_to_read_only_format_is_a_usage_error(tmp_path):
    line = one_line_error(run_cli("convert", BUNDLED, tmp_path / "x.ply"))
    assert "x.ply" in line
    assert not (tmp_path / "x.ply").exists()


def test_bad_arguments_are_one_line():
    line = one_line_error(run_cli("frobnicate"))
    assert "frobnicate" in line
    assert run_cli("--help").returncode == 0


def _lod_input(tmp_path):
    from hairlod import io
    from test_lod import hanging_hair

    path = tmp_path / "in.hair"
    io.write(path, hanging_hair(curves=1200, points=10))
    return path


def test_lod_exports_a_folder_that_loads_back(tmp_path):

    source = _lod_input(tmp_path)
    result = run_cli("lod", source, "--out", tmp_path / "asset", "--guides", 12, "--levels", 5, "--control-points", 8,
                     "--json")
    assert result.returncode == 0, result.stderr
    report = json.loads(result.stdout)
    assert report["strands"] == 1200 and report["selected_levels"] == list(range(report["built_levels"]))
    assert all(level["coverage"] >= 0.95 for level in report["levels"])
    assert report["timings"]["kmeans"] > 0
    manifest = json.loads((tmp_path / "asset" / "manifest.json").read_text())
    assert [level["hairs"] for level in manifest["thick_levels"]] == [level["hairs"] for level in report["levels"]]
    for level in manifest["thick_levels"]:
        assert (tmp_path / "asset" / level["hair_file"]).is_file()
    loaded = lod.load(tmp_path / "asset")
    assert sum(int(n) for n in loaded.levels[0].n_total) == 1200


def test_lod_with_a_far_camera_drops_fine_levels(tmp_path):
    from test_lod import look_at, perspective

    source = _lod_input(tmp_path)
    far = {"view": look_at((300, 30, 20), (0, 0, -0.3)).tolist(),
           "projection": perspective(0.8, 4 / 3, 0.01, 1000).tolist(), "viewport": [800, 600]}
    (tmp_path / "cameras.json").write_text(json.dumps([far]))
    result = run_cli("lod", source, "--out", tmp_path / "asset", "--guides", 12, "--levels", 5, "--control-points", 8,
                     "--cameras", tmp_path / "cameras.json", "--json")
    assert result.returncode == 0, result.stderr
    report = json.loads(result.stdout)
    assert report["selected_levels"] and max(report["selected_levels"]) < report["built_levels"] - 1
    assert [level["level"] for level in report["levels"]] == [level for level in report["selected_levels"]]


@pytest.mark.parametrize("arguments", [["--guides", "0"], ["--width-px", "0"], ["--cameras", "missing.json"],
                                       ["--cameras", "bad.json"]])
def test_lod_bad_input_exits_2_without_output(tmp_path, arguments):
    source = _lod_input(tmp_path)
    (tmp_path / "bad.json").write_text(json.dumps([{"view": [[1, 0], [0, 1]]}]))
    arguments = [str(tmp_path / a) if a.endswith(".json") else a for a in arguments]
    result = run_cli("lod", source, "--out", tmp_path / "asset", *arguments)
    one_line_error(result)
    assert not (tmp_path / "asset").exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(["in.hair", "bad.json"])


def test_lod_stores_the_guides_of_per_frame_files(tmp_path):
    from hairlod import Strands, io, lod
    from hairlod.temporal import turn

    source = _lod_input(tmp_path)
    hair = io.read(source)
    frames = []
    for index, angle in enumerate((0.0, 0.3)):
        frames.append(tmp_path / f"frame{index}.hair")
        io.write(frames[-1], Strands(turn(hair.points, angle), hair.offsets, hair.radius))
    result = run_cli("lod", source, "--out", tmp_path / "asset", "--guides", 12, "--levels", 4, "--control-points", 8,
                     "--animation", *frames, "--first-frame", 7, "--json")
    assert result.returncode == 0, result.stderr
    assert json.loads(result.stdout)["animation_frames"] == 2
    asset = lod.load(tmp_path / "asset")
    numbers, guides = lod.load_animation(tmp_path / "asset", asset)
    assert numbers.tolist() == [7, 8]
    size = float(np.ptp(asset.rest_guides.reshape(-1, 3), axis=0).max())
    assert np.abs(guides[0] - asset.rest_guides).max() <= 1e-5 * size
    assert np.abs(guides[1] - turn(asset.rest_guides, 0.3)).max() <= 1e-5 * size

    # A frame of another hair (fewer curves) is refused, and nothing is written.
    io.write(tmp_path / "other.hair", Strands.from_counts(hair.points[:40], np.full(4, 10), hair.radius[:40]))
    result = run_cli("lod", source, "--out", tmp_path / "asset2", "--animation", frames[0], tmp_path / "other.hair")
    assert "other.hair has 4 curves, the LoD asset 1200" in one_line_error(result)
    assert not (tmp_path / "asset2").exists()


def test_bench_lod_json():
    result = run_cli("bench", "lod", "--strands", 3000, "--guides", 16, "--frames", 20, "--json")
    assert result.returncode == 0, result.stderr
    report = json.loads(result.stdout)
    assert set(report["stages"]) == {"resample", "kmeans", "clusters", "levels", "fitting", "weights"}
    assert all(entry["seconds_per_frame"] > 0 for entry in report["selection"].values())
    assert report["memory_ratio"] > report["stored_ratio"] > 0 and len(report["area_ratios"]) == len(report["levels"]) - 1


def test_bench_skinning_json():
    result = run_cli("bench", "skinning", "--strands", 2000, "--guides", 16, "--control-points", 8, "--frames", 3,
                     "--json")
    assert result.returncode == 0, result.stderr
    report = json.loads(result.stdout)
    assert set(report["per_frame_ms"]) == {"skin_maps", "maps_copy", "select_moved", "select_static"}
    assert report["maps_bytes"] == report["clusters"] * 8 * lod.SKIN_MAP_TEXELS * 4 * 4
    # The rigid turn is exact to float precision; the GPU path is the CPU skin.
    assert report["rigid_turn_30deg"]["max_of_size"] < 1e-5
    assert report["gpu_path_vs_cpu_skin_max_of_size"] < 1e-5
    assert 0.0 < report["bend"]["mean_of_size"] < report["bend"]["p99_of_size"]
    assert len(report["coverage_bent"]) == len(report["coverage_rest"]) == report["built_levels"] - 1
    assert len(report["coverage_of_bent_strands"]) == len(report["coverage_rest"])


def test_render_own_hair_scatter_is_for_lod_single(tmp_path):
    source = _lod_input(tmp_path)
    assert run_cli("lod", source, "--out", tmp_path / "asset", "--guides", 12, "--levels", 4,
                   "--control-points", 8).returncode == 0
    images = {}
    for own_hair in ("attenuate", "scatter"):
        out = tmp_path / f"{own_hair}.exr"
        result = run_cli("render", source, "--method", "lod-single", "--lod", tmp_path / "asset", "--own-hair", own_hair,
                         "--spp", 2, "--width", 24, "--view", "near", "--out", out)
        assert result.returncode == 0, result.stderr
        images[own_hair] = out.read_bytes()
    assert images["attenuate"] != images["scatter"]  # the paths inside the thick hairs differ
    line = one_line_error(run_cli("render", source, "--method", "lod", "--lod", tmp_path / "asset", "--own-hair", "scatter",
                                  "--out", tmp_path / "x.png"))
    assert "--own-hair scatter: applies to --method lod-single only" in line
    assert not (tmp_path / "x.png").exists()


def test_render_and_bench_animation_take_frames(tmp_path):
    from hairlod import Strands, io
    from hairlod.temporal import bend

    source = _lod_input(tmp_path)
    hair = io.read(source)
    bent = tmp_path / "bent.hair"
    io.write(bent, Strands(bend(hair.points, 0.4), hair.offsets, hair.radius))
    assert run_cli("lod", source, "--out", tmp_path / "asset", "--guides", 12, "--levels", 4, "--control-points", 8,
                   "--animation", source, bent).returncode == 0
    result = run_cli("render", bent, "--method", "lod", "--lod", tmp_path / "asset", "--frame", 2, "--spp", 2,
                     "--width", 32, "--out", tmp_path / "frame2.png", "--json")
    assert result.returncode == 0, result.stderr
    assert json.loads(result.stdout)["frame"] == 2 and (tmp_path / "frame2.png").is_file()
    assert "stores frames 1 to 2" in one_line_error(run_cli("render", bent, "--method", "lod", "--lod", tmp_path / "asset",
                                                            "--frame", 5, "--out", tmp_path / "x.png"))
    assert "only the lod methods" in one_line_error(run_cli("render", bent, "--frame", 1, "--out", tmp_path / "x.png"))
    assert not (tmp_path / "x.png").exists()

    result = run_cli("bench", "animation", "--animation", source, bent, "--lod", tmp_path / "asset", "--spp", 2,
                     "--width", 32, "--json")
    assert result.returncode == 0, result.stderr
    report = json.loads(result.stdout)
    assert report["frames"] == 2 and np.isfinite(report["adjacent_psnr_gap_db"])
    assert "2 or more frames" in one_line_error(run_cli("bench", "animation", "--animation", source))
