"""The command line as a user runs it: a subprocess of /usr/bin/python3 -m hairlod."""

import json
import os
import struct
import subprocess
import sys

import numpy as np
import pytest

from conftest import REPO

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
