"""Hostile inputs (issue 12): every bad input exits 2 with one line on stderr naming the user's file
or argument, and nothing the user owns is lost.

- test_bad_input: the bad inputs the issue lists, one table, through cli.main in this process.
- test_*folder* / test_*file*: outputs the CLI and the Python API may and may not replace.
- test_generated_hostile_inputs: HOSTILE_COUNT seeded mutations per command of valid command lines
  and of their input files (HAIRLOD_HOSTILE_COUNT overrides the count, HAIRLOD_HOSTILE_SEED picks
  another sequence). They run through cli.main in a worker process (this file run as a script), so
  that a hang, a crash or an allocation the memory budget did not stop is reported as a failure of
  one input instead of ending the suite or exhausting the machine.
"""

import contextlib
import hashlib
import importlib.util
import io
import json
import os
import random
import re
import select
import shutil
import struct
import subprocess
import sys
import time
import traceback
import zipfile
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[2]
EXAMPLES = REPO / "examples" / "data"
HOSTILE_COUNT = int(os.environ.get("HAIRLOD_HOSTILE_COUNT", "60"))
HOSTILE_SEED = os.environ.get("HAIRLOD_HOSTILE_SEED", "0")
# The worker's memory budget: small, so that large requests are refused the same way on any machine.
WORKER_BUDGET = "256M"
# The worker's address space: an allocation that the budget should have refused fails (MemoryError,
# "out of memory") long before it could take the machine's memory.
WORKER_ADDRESS_SPACE = 4 << 30
CASE_TIMEOUT = 60.0


def _script(name):
    spec = importlib.util.spec_from_file_location(name, REPO / "scripts" / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


fuzz_python = _script("fuzz_python")  # the mutators
fuzz_seeds = _script("make_fuzz_seeds")  # small files of every hair format


def cli_run(argv):
    """(exit code, stdout, stderr) of cli.main(argv) in this process."""
    from hairlod import cli

    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = cli.main([str(a) for a in argv])
    return code, out.getvalue(), err.getvalue()


def error_line(code, out, err):
    """The one stderr line of a bad-input failure (after checking it is one)."""
    assert code == 2, f"exit code {code}, stderr {err!r}"
    assert out == "", "nothing on stdout after a failure"
    assert "Traceback" not in err
    lines = err.splitlines()
    assert len(lines) == 1, f"one line on stderr, got {err!r}"
    assert lines[0].startswith("hairlod: error: ")
    assert ".hairlod-" not in lines[0], f"names a hidden temporary instead of the user's path: {lines[0]}"
    return lines[0]


def snapshot(*folders):
    """sha256 of every file under `folders` (and the folders themselves), to compare before/after."""
    state = {}
    for folder in folders:
        for root, dirs, files in os.walk(folder):
            state[root] = "folder"
            for name in files:
                path = os.path.join(root, name)
                with open(path, "rb") as stream:
                    state[path] = hashlib.sha256(stream.read()).hexdigest()
    return state


# ---------------------------------------------------------------------------------------------
# Inputs shared by the tests: small, so that every command on them takes a fraction of a second.

def _scaled(strands, factor):
    from hairlod import Strands

    return Strands.from_counts((strands.points.astype(np.float64) * factor).astype(np.float32), strands.counts(),
                               (strands.radius.astype(np.float64) * factor).astype(np.float32))


def _with_nan(hair_bytes):
    """A .hair file with one NaN coordinate (the writer refuses to write one)."""
    strands, flags = struct.unpack("<I", hair_bytes[4:8])[0], struct.unpack("<I", hair_bytes[12:16])[0]
    offset = 128 + (2 * strands if flags & 1 else 0)
    return hair_bytes[:offset] + struct.pack("<f", float("nan")) + hair_bytes[offset + 4:]


class Data:
    """Paths of the valid inputs the tests start from."""

    def __init__(self, folder):
        from hairlod import hairmesh, io as hair_io

        self.folder = folder
        strands = hairmesh.generate_strands(hairmesh.read(EXAMPLES / "scalp_patch.hairmesh.json"), count=100,
                                            vertices=5, seed=1)
        self.hair = folder / "small.hair"
        hair_io.write(self.hair, strands)
        self.few = folder / "few.hair"  # 4 strands
        hair_io.write(self.few, hairmesh.generate_strands(hairmesh.read(EXAMPLES / "scalp_patch.hairmesh.json"),
                                                          count=4, vertices=5, seed=1))
        self.huge = folder / "huge.hair"
        hair_io.write(self.huge, _scaled(strands, 1e30))
        self.tiny = folder / "tiny.hair"
        hair_io.write(self.tiny, _scaled(strands, 1e-30))
        self.nan = folder / "nan.hair"
        self.nan.write_bytes(_with_nan(self.hair.read_bytes()))
        self.data = folder / "small.data"
        hair_io.write(self.data, strands)
        self.formats = {"seed.ply": fuzz_seeds.ply("ascii"), "seed_le.ply": fuzz_seeds.ply("binary_little_endian"),
                        "seed.tfx": fuzz_seeds.tfx(2, 3), "seed.bin": fuzz_seeds.strand_list([3, 1, 2], 7),
                        "seed.hair": fuzz_seeds.cyhair([2, 3, 4])}
        for name, content in self.formats.items():
            (folder / name).write_bytes(content)
        self.mesh = EXAMPLES / "scalp_patch.hairmesh.json"
        self.seed_mesh = folder / "seed.hairmesh.json"
        self.seed_mesh.write_text(json.dumps(fuzz_python.hair_mesh_seed()))
        self.cameras = folder / "cameras.json"
        self.cameras.write_text(json.dumps(fuzz_python.cameras_seed()))
        self.params = folder / "params.json"
        self.params.write_text(json.dumps({"beta_m": 0.25, "sigma_a": [0.2, 0.3, 0.5]}))
        self.lod = folder / "lod"
        assert cli_run(["lod", self.hair, "--out", self.lod, "--guides", 4, "--levels", 3,
                        "--control-points", 4])[0] == 0
        self.tables = folder / "tables"
        assert cli_run(["bake", "--out", self.tables, "--theta-samples", 4, "--hair-count-samples", 4,
                        "--table-samples", 5])[0] == 0


@pytest.fixture(scope="module")
def data(tmp_path_factory):
    return Data(tmp_path_factory.mktemp("hostile-data"))


# ---------------------------------------------------------------------------------------------
# (a) The bad inputs issue 12 lists: exit 2, one line naming the user's file or argument, at once.

DEEP = "[" * 100000 + "]" * 100000


def _lod_copy(data, tmp, name, change):
    folder = tmp / name
    shutil.copytree(data.lod, folder)
    change(folder)
    return folder


def _edit_manifest(edit):
    def change(folder):
        manifest = json.loads((folder / "manifest.json").read_text())
        edit(manifest)
        (folder / "manifest.json").write_text(json.dumps(manifest))
    return change


def _mesh_with(**changes):
    def make(data, tmp, name):
        mesh = json.loads(data.mesh.read_text())
        mesh.update(changes)
        path = tmp / name
        path.write_text(json.dumps(mesh))
        return path
    return make


def _huge_face(data, tmp, name):
    mesh = json.loads(data.mesh.read_text())
    mesh["faces"][0][0] = 10**20
    path = tmp / name
    path.write_text(json.dumps(mesh))
    return path


def _text(content):
    """A maker of a file holding `content` (str or bytes)."""
    def make(data, tmp, name):
        path = tmp / name
        path.write_bytes(content.encode() if isinstance(content, str) else content)
        return path
    return make


def _nan_offset_box(folder):
    boxes = np.load(folder / "offset_boxes.npy")
    boxes.flat[0] = np.nan
    np.save(folder / "offset_boxes.npy", boxes)


# Files a row's argv names as {placeholder}: made in the row's folder on first use.
MAKERS = {
    "deep.hairmesh.json": _text('{"format": "hairlod.hairmesh", "version": 1, "layers": ' + DEEP + "}"),
    "deep_cameras.json": _text(DEEP),
    "deep_params.json": _text('{"beta_m": ' + DEEP + "}"),
    "huge_face.hairmesh.json": _huge_face,
    "params_1e400.json": _text('{"beta_m": 1e400}'),
    "params_big_integer.json": _text('{"beta_m": ' + "9" * 400 + "}"),
    "overflow.hairmesh.json": _mesh_with(styling=[{"op": "wave", "amplitude": 3e38, "frequency": 3e38}]),
    "bad_cameras.json": _text(json.dumps([{"view": [[1, 0], [0, 1]], "projection": [], "viewport": [8, 8]}])),
    "truncated.hair": _text((EXAMPLES / "bob.hair").read_bytes()[:5000]),
    "deep_manifest": lambda data, tmp, name: _lod_copy(data, tmp, name,
                                                       lambda f: (f / "manifest.json").write_text(DEEP)),
    "string_coverage": lambda data, tmp, name: _lod_copy(
        data, tmp, name, _edit_manifest(lambda m: m["thick_levels"][0].update(coverage="abc"))),
    "string_control_points": lambda data, tmp, name: _lod_copy(
        data, tmp, name, _edit_manifest(lambda m: m.update(control_points="many"))),
    "nan_offset_box": lambda data, tmp, name: _lod_copy(data, tmp, name, _nan_offset_box),
    "truncated_array": lambda data, tmp, name: _lod_copy(
        data, tmp, name, lambda f: (f / "rest_guides.npy").write_bytes((f / "rest_guides.npy").read_bytes()[:90])),
}

RENDER = ["--out", "{tmp}/image.png", "--width", 4, "--spp", 1]
BAKE = ["--out", "{tmp}/tables", "--theta-samples", 4, "--hair-count-samples", 4, "--table-samples", 5]

# id, argv ({hair} {few} {huge} {tiny} {nan} {mesh} {lod}: data's inputs; {tmp}: the row's folder;
# other {names}: MAKERS), a regular expression the line must match (the file or argument it
# names), the memory budget (None: the default).
BAD_INPUTS = [
    ("lod --seed -1", ["lod", "{hair}", "--out", "{tmp}/out", "--seed", -1], "--seed", None),
    ("lod --guides 2^31", ["lod", "{hair}", "--out", "{tmp}/out", "--guides", 2**31], "--guides", None),
    ("lod --levels 2^32+2", ["lod", "{hair}", "--out", "{tmp}/out", "--levels", 2**32 + 2], "--levels", None),
    ("lod --control-points -3", ["lod", "{hair}", "--out", "{tmp}/out", "--control-points", -3], "--control-points",
     None),
    ("generate --seed 10^20", ["generate", "{mesh}", "--seed", "99999999999999999999"], "--seed", None),
    ("generate --count 0", ["generate", "{mesh}", "--count", 0], "--count", None),
    ("generate --lod nan", ["generate", "{mesh}", "--lod", "nan"], "--lod", None),
    ("lod --width-px inf", ["lod", "{hair}", "--out", "{tmp}/out", "--width-px", "inf"], "--width-px", None),
    ("lod --width-px nan", ["lod", "{hair}", "--out", "{tmp}/out", "--width-px", "nan"], "--width-px", None),
    ("lod --width-px 1e39", ["lod", "{hair}", "--out", "{tmp}/out", "--width-px", "1e39"], "--width-px", None),
    ("render --width abc", ["render", "{hair}", "--out", "{tmp}/image.png", "--width", "abc"], "--width", None),
    ("deep hair mesh", ["generate", "{deep.hairmesh.json}"], "deep.hairmesh.json", None),
    ("deep manifest (render)", ["render", "{hair}", "--lod", "{deep_manifest}", "--method", "lod", *RENDER],
     "deep_manifest", None),
    ("deep manifest (bake)", ["bake", "--lod", "{deep_manifest}", *BAKE], "deep_manifest", None),
    ("deep cameras", ["lod", "{hair}", "--out", "{tmp}/out", "--cameras", "{deep_cameras.json}"], "deep_cameras.json",
     None),
    ("deep params (bake)", ["bake", "--params", "{deep_params.json}", *BAKE], "deep_params.json", None),
    ("deep params (render)", ["render", "{hair}", "--params", "{deep_params.json}", *RENDER], "deep_params.json", None),
    ("face index 10^20", ["generate", "{huge_face.hairmesh.json}"], "huge_face.hairmesh.json", None),
    ("params 1e400 (bake)", ["bake", "--params", "{params_1e400.json}", *BAKE], "params_1e400.json", None),
    ("params 1e400 (render)", ["render", "{hair}", "--params", "{params_1e400.json}", *RENDER], "params_1e400.json",
     None),
    ("params 10^400 integer", ["bake", "--params", "{params_big_integer.json}", *BAKE], "params_big_integer.json",
     None),
    ("cameras of the wrong shape", ["lod", "{hair}", "--out", "{tmp}/out", "--cameras", "{bad_cameras.json}"],
     "bad_cameras.json", None),
    ("manifest: a string for a float (bake)", ["bake", "--lod", "{string_coverage}", *BAKE], "string_coverage", None),
    ("manifest: a string for a float (render)",
     ["render", "{hair}", "--lod", "{string_coverage}", "--method", "lod", *RENDER], "string_coverage", None),
    ("manifest: a string for an integer", ["bake", "--lod", "{string_control_points}", *BAKE],
     "string_control_points", None),
    ("asset: NaN in an offset box", ["render", "{hair}", "--lod", "{nan_offset_box}", "--method", "lod", *RENDER],
     "nan_offset_box", None),
    ("asset: truncated array", ["bake", "--lod", "{truncated_array}", *BAKE], "truncated_array", None),
    ("truncated hair file", ["info", "{truncated.hair}"], "truncated.hair", None),
    ("NaN coordinate (lod)", ["lod", "{nan}", "--out", "{tmp}/out"], "nan.hair", None),
    ("NaN coordinate (render)", ["render", "{nan}", *RENDER], "nan.hair", None),
    ("coordinates 1e30 (lod)", ["lod", "{huge}", "--out", "{tmp}/out"], "huge.hair", None),
    ("coordinates 1e30 (render)", ["render", "{huge}", *RENDER], "huge.hair", None),
    ("coordinates 1e-30 (lod)", ["lod", "{tiny}", "--out", "{tmp}/out"], "tiny.hair", None),
    ("coordinates 1e-30 (render)", ["render", "{tiny}", *RENDER], "tiny.hair", None),
    ("styling overflows float32", ["generate", "{overflow.hairmesh.json}", "--count", 10, "--out",
                                   "{tmp}/generated.hair"], "overflow.hairmesh.json", None),
    ("generate --count 10^8 refused at once", ["generate", "{mesh}", "--count", 10**8], "--count", "16G"),
    ("lod --control-points 10^5 (budget)", ["lod", "{hair}", "--out", "{tmp}/out", "--control-points", 10**5],
     "control.points", "1G"),
    ("lod --control-points 10^6 (budget)", ["lod", "{hair}", "--out", "{tmp}/out", "--control-points", 10**6],
     "control.points", "1G"),
    # More control points than a .hair curve holds (65536) can never be written: refused before the
    # build, not after it (a large budget, as on a large machine).
    ("lod --control-points 65537", ["lod", "{few}", "--out", "{tmp}/out", "--control-points", 65537],
     "control.points", "64G"),
    ("render --width 2^31-1 (budget)", ["render", "{hair}", "--out", "{tmp}/image.png", "--width", 2**31 - 1],
     "width", None),
    ("bake --theta-samples 2^31-1 (budget)", ["bake", "--out", "{tmp}/tables", "--theta-samples", 2**31 - 1],
     "theta.samples", None),
]


def _fill(argv, data, tmp):
    """argv with its {placeholders} replaced by paths (making the MAKERS files it names)."""
    known = {name: getattr(data, name) for name in ("hair", "few", "huge", "tiny", "nan", "mesh", "lod")}
    known["tmp"] = tmp

    def path(match):
        name = match.group(1)
        if name not in known:
            known[name] = MAKERS[name](data, tmp, name)
        return str(known[name])

    return [re.sub(r"\{([^}]+)\}", path, str(token)) for token in argv]


@pytest.mark.parametrize("argv, names, budget", [row[1:] for row in BAD_INPUTS], ids=[row[0] for row in BAD_INPUTS])
def test_bad_input(data, tmp_path, monkeypatch, argv, names, budget):
    if budget:
        monkeypatch.setenv("HAIRLOD_MEMORY_BUDGET", budget)
    else:
        monkeypatch.delenv("HAIRLOD_MEMORY_BUDGET", raising=False)
    argv = _fill(argv, data, tmp_path)
    inputs = snapshot(data.folder)
    start = time.perf_counter()
    line = error_line(*cli_run(argv))
    seconds = time.perf_counter() - start
    assert re.search(names, line), f"the line should name {names!r}: {line}"
    assert seconds < 10, f"refused after {seconds:.1f} s: a refusal comes before the work"
    assert snapshot(data.folder) == inputs
    for name in ("out", "tables", "image.png", "generated.hair"):
        assert not (tmp_path / name).exists(), f"no output after a failure: {name}"
    assert not [p for p in tmp_path.rglob("*") if ".hairlod-" in p.name], "no temporaries left"


def test_manifests_stay_strict_json_at_the_largest_width(data, tmp_path):
    # --width-px inf once wrote Infinity into manifest.json; the largest accepted value must not either.
    assert cli_run(["lod", data.hair, "--out", tmp_path / "out", "--guides", 4, "--width-px", "3.4e38"])[0] == 0
    json.loads((tmp_path / "out" / "manifest.json").read_text(),
               parse_constant=lambda constant: pytest.fail(f"manifest.json holds {constant}"))


def test_bench_lod_sizes_are_checked_against_the_budget(tmp_path):
    # bench lod --strands 2^31-1 (or --points) must be refused at once like the other commands' sizes;
    # run in a child with a bounded address space, so that an unchecked allocation fails fast there.
    code = ("import resource, sys; resource.setrlimit(resource.RLIMIT_AS, (%d, %d)); from hairlod import cli; "
            "sys.exit(cli.main(sys.argv[1:]))" % (WORKER_ADDRESS_SPACE, WORKER_ADDRESS_SPACE))
    environment = dict(os.environ, PYTHONPATH=str(REPO / "addon"), HAIRLOD_MEMORY_BUDGET="1G")
    for option in ("--strands", "--points"):
        sizes = {"--strands": 20, "--points": 4, option: 2**31 - 1}
        start = time.perf_counter()
        argv = ["bench", "lod", "--guides", 4, "--levels", 2, "--frames", 1, *[v for item in sizes.items() for v in item]]
        run = subprocess.run([sys.executable, "-c", code, *map(str, argv)], capture_output=True, text=True,
                             timeout=120, env=environment, cwd=tmp_path)
        line = error_line(run.returncode, run.stdout, run.stderr)
        assert "out of memory" not in line, f"allocated before checking the budget: {line}"
        assert option in line or option[2:] in line, line
        assert time.perf_counter() - start < 10


# ---------------------------------------------------------------------------------------------
# (b) Nothing the user owns is lost: what --out may replace.

def _lod_argv(data, out, *extra):
    return ["lod", data.hair, "--out", out, "--guides", 4, "--levels", 3, "--control-points", 4, *extra]


def _bake_argv(out, *extra):
    return ["bake", "--out", out, "--theta-samples", 4, "--hair-count-samples", 4, "--table-samples", 5, *extra]


@pytest.mark.parametrize("force", [[], ["--force"]], ids=["plain", "force"])
def test_lod_out_dot_keeps_the_current_folder(data, tmp_path, monkeypatch, force):
    work = tmp_path / "work"
    work.mkdir()
    shutil.copy(data.hair, work / "hair.hair")
    (work / "notes.txt").write_text("mine")
    monkeypatch.chdir(work)
    before = snapshot(work)
    error_line(*cli_run(["lod", "hair.hair", "--out", ".", "--guides", 4, *force]))
    assert snapshot(work) == before


@pytest.mark.parametrize("force", [[], ["--force"]], ids=["plain", "force"])
def test_an_existing_file_is_never_replaced_by_a_folder(data, tmp_path, force):
    notes = tmp_path / "notes.txt"
    notes.write_text("mine")
    line = error_line(*cli_run(_lod_argv(data, notes, *force)))
    assert "notes.txt" in line
    error_line(*cli_run(_bake_argv(notes, *force)))
    assert notes.read_text() == "mine"


def test_a_folder_of_other_files_is_refused(data, tmp_path):
    folder = tmp_path / "mine"
    folder.mkdir()
    (folder / "notes.txt").write_text("mine")
    (folder / "sub").mkdir()
    (folder / "sub" / "more.txt").write_text("more")
    before = snapshot(folder)
    assert "mine" in error_line(*cli_run(_lod_argv(data, folder)))
    assert "mine" in error_line(*cli_run(_bake_argv(folder)))
    assert snapshot(folder) == before


@pytest.mark.parametrize("force", [[], ["--force"]], ids=["plain", "force"])
def test_bake_never_replaces_the_lod_folder_it_reads(data, tmp_path, force):
    from hairlod import lod

    asset = tmp_path / "asset"
    shutil.copytree(data.lod, asset)
    before = snapshot(asset)
    error_line(*cli_run(_bake_argv(asset, "--lod", asset, *force)))
    assert snapshot(asset) == before
    lod.load(asset)


def test_a_folder_of_the_other_kind_is_refused(data, tmp_path):
    lod_folder, tables = tmp_path / "lod", tmp_path / "tables"
    shutil.copytree(data.lod, lod_folder)
    shutil.copytree(data.tables, tables)
    before = snapshot(lod_folder, tables)
    error_line(*cli_run(_bake_argv(lod_folder)))
    error_line(*cli_run(_lod_argv(data, tables)))
    assert snapshot(lod_folder, tables) == before


def test_a_folder_hairlod_wrote_is_replaced(data, tmp_path):
    from hairlod import lod

    out, tables = tmp_path / "asset", tmp_path / "tables"
    assert cli_run(_lod_argv(data, out))[0] == 0
    assert cli_run(["lod", data.hair, "--out", out, "--guides", 2, "--levels", 2, "--control-points", 3])[0] == 0
    manifest = json.loads((out / "manifest.json").read_text())
    assert manifest["extra"]["options"]["guides"] == 2 and lod.load(out).control_points == 3
    assert cli_run(_bake_argv(tables))[0] == 0
    assert cli_run(["bake", "--out", tables, "--theta-samples", 3, "--hair-count-samples", 3, "--table-samples", 3])[0] == 0
    assert json.loads((tables / "manifest.json").read_text())["tables"][0]["resolution"][0] == 3
    assert sorted(p.name for p in tmp_path.iterdir()) == ["asset", "tables"], "no temporaries left beside"


def test_force_replaces_a_foreign_folder(data, tmp_path):
    from hairlod import lod

    foreign = tmp_path / "foreign"
    foreign.mkdir()
    (foreign / "notes.txt").write_text("mine")
    assert cli_run(_lod_argv(data, foreign, "--force"))[0] == 0
    lod.load(foreign)
    assert not (foreign / "notes.txt").exists()


def test_force_still_refuses_the_current_home_and_input_folders(data, tmp_path, monkeypatch):
    home, work, inputs = tmp_path / "home", tmp_path / "home" / "work", tmp_path / "inputs"
    work.mkdir(parents=True)
    inputs.mkdir()
    for folder in (home, work, inputs):
        (folder / "notes.txt").write_text("mine")
    shutil.copy(data.hair, inputs / "hair.hair")
    monkeypatch.setenv("HOME", str(home))
    monkeypatch.chdir(work)
    before = snapshot(tmp_path)
    for out in (".", work, home, inputs, inputs / "hair.hair", tmp_path):
        line = error_line(*cli_run(["lod", inputs / "hair.hair", "--out", out, "--guides", 4, "--force"]))
        assert str(out) in line
    for out in (".", work, home, tmp_path):  # bake reads no hair: the inputs folder is just a folder to it
        error_line(*cli_run(_bake_argv(out, "--force")))
    assert snapshot(tmp_path) == before


def test_a_failed_write_leaves_an_existing_output_file(data, tmp_path):
    bad_hair, bad_mesh = tmp_path / "bad.hair", tmp_path / "bad.hairmesh.json"
    bad_hair.write_bytes(data.hair.read_bytes()[:200])
    bad_mesh.write_text("{}")
    for name, argv in [("out.hair", ["convert", bad_hair]), ("out.hair", ["generate", bad_mesh, "--out"]),
                       ("out.png", ["render", bad_hair, "--width", 4, "--out"])]:
        (tmp_path / name).write_text("mine")
        error_line(*cli_run([*argv, tmp_path / name]))
        assert (tmp_path / name).read_text() == "mine"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.hair", "bad.hairmesh.json", "out.hair", "out.png"]


def test_the_python_api_refuses_a_foreign_folder(data, tmp_path):
    from hairlod import bcsdf_bake, lod

    asset = lod.load(data.lod)
    foreign = tmp_path / "foreign"
    foreign.mkdir()
    (foreign / "notes.txt").write_text("mine")
    (tmp_path / "notes.txt").write_text("mine")
    before = snapshot(tmp_path)
    for target in (foreign, tmp_path / "notes.txt"):
        with pytest.raises(ValueError, match="notes.txt|foreign"):
            lod.save(asset, target)
        with pytest.raises(ValueError, match="notes.txt|foreign"):
            bcsdf_bake.bake(None, target, theta_samples=4, hair_count_samples=4, table_samples=5)
    with pytest.raises(ValueError, match="would replace the input"):
        lod.save(asset, foreign, force=True, inputs=[foreign / "notes.txt"])
    assert snapshot(tmp_path) == before
    lod.save(asset, foreign, force=True)
    lod.load(foreign)


# ---------------------------------------------------------------------------------------------
# The API's promise: ValueError for any damaged asset (packs live in .blend files).

def _pack_members(data):
    from hairlod import lod

    with np.load(io.BytesIO(lod.pack(lod.load(data.lod)))) as archive:
        return {name: archive[name] for name in archive.files}


def _repack(members):
    buffer = io.BytesIO()
    np.savez_compressed(buffer, **members)
    return buffer.getvalue()


def _deep_header(data):
    return _repack(dict(_pack_members(data), header=np.frombuffer(DEEP.encode(), np.uint8)))


def _unparsable_npy_header(data):
    # A .npy header numpy's tokenizer cannot parse (an unclosed bracket) inside a valid zip.
    buffer = io.BytesIO()
    with zipfile.ZipFile(buffer, "w") as archive:
        archive.writestr("header.npy", b"\x93NUMPY\x01\x00\x10\x00{'descr': '|u1'\n")
    return buffer.getvalue()


@pytest.mark.parametrize("damage", [_deep_header, _unparsable_npy_header], ids=["deep header", "unparsable .npy header"])
def test_unpack_refuses_a_damaged_pack_with_value_error(data, damage):
    from hairlod import lod

    with pytest.raises(ValueError, match="packed LoD asset"):
        lod.unpack(damage(data))


def test_unpack_refuses_bit_flipped_packs_with_value_error(data):
    from hairlod import lod

    packed, rng = lod.pack(lod.load(data.lod)), random.Random(12)
    for _ in range(200):
        damaged = bytearray(packed)
        for _ in range(rng.randint(1, 4)):
            damaged[rng.randrange(len(damaged))] ^= 1 << rng.randrange(8)
        try:
            lod.unpack(bytes(damaged))
        except ValueError:
            pass


@pytest.mark.parametrize("edit", [
    lambda m: m["thick_levels"][0].update(per_hair="not an object"),
    lambda m: next(iter(m["thick_levels"][0]["per_hair"].values())).update(shape=5),
    lambda m: m["arrays"]["rest_guides"].update(shape=7),
    lambda m: m.update(thick_levels={"not": "a list"}),
], ids=["per_hair a string", "per_hair shape an integer", "array shape an integer", "thick_levels an object"])
def test_load_refuses_a_damaged_manifest_with_value_error(data, tmp_path, edit):
    from hairlod import lod

    folder = _lod_copy(data, tmp_path, "asset", _edit_manifest(edit))
    with pytest.raises(ValueError, match="asset"):
        lod.load(folder)


def test_load_refuses_an_unparsable_array_header_with_value_error(data, tmp_path):
    from hairlod import lod

    folder = _lod_copy(data, tmp_path, "asset", lambda f: (f / "rest_guides.npy").write_bytes(
        b"\x93NUMPY\x01\x00\x10\x00{'descr': '<f4'\n"))
    with pytest.raises(ValueError, match="asset"):
        lod.load(folder)


TRIANGLE_CAGE = {"format": "hairlod.hairmesh", "version": 1, "faces": [[0, 1, 2]],
                 "layers": [[[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 0, 1], [1, 0, 1], [0, 1, 1]]]}


# Found by scripts/fuzz_python.py hairmesh (TypeError once).
@pytest.mark.parametrize("changes", [{"uv": [[[0, 0], [1, 0], [0, 1]], 7]}, {"styling": [{"op": []}]}],
                         ids=["uv entry not a list", "styling op a list"])
def test_hairmesh_read_refuses_a_malformed_file_with_value_error(tmp_path, changes):
    from hairlod import hairmesh

    path = tmp_path / "cage.hairmesh.json"
    path.write_text(json.dumps(dict(TRIANGLE_CAGE, **changes)))
    with pytest.raises(ValueError, match="cage.hairmesh.json"):
        hairmesh.read(path)


def test_io_read_refuses_a_path_with_a_nul_byte_with_value_error():
    from hairlod import io as hair_io

    with pytest.raises(ValueError):
        hair_io.read("a\x00b.hair")


# ---------------------------------------------------------------------------------------------
# (c) Generated hostile inputs: mutations of valid command lines and of their input files.

# Invalid as any number argument of the CLI (or valid but harmless: "-0", "٣" is 3, "1e3").
HOSTILE_NUMBERS = ["-1", "-0", "0", "", " ", "abc", "1e400", "-1e400", "inf", "-inf", "nan", "0x10", "1_0", "٣",
                   "1.5", "2147483648", "4294967298", "9223372036854775808", "99999999999999999999",
                   "-99999999999999999999", "18446744073709551616", "1e-400", "5e-324", "3.5e38", "1e39", "1e3"]
# Valid sizes the memory budget must refuse at once (only for "size" arguments: a huge --spp is a
# legitimately long render, not a bad input).
HUGE_SIZES = ["2147483647", "100000000"]
HOSTILE_FLOATS = ["1e308", "-1e308", "3.4e38", "1e-308", "1e-30", "1e30"]
# Valid spellings a parser may still get wrong.
ODD_NUMBERS = ["+1", " 2 ", "٣", "0003", "1E0", ".5", "2.", "1e0"]
HOSTILE_WORDS = ["", "PT", "lod,", "xu,xu", "aggregated,,xu", "none", "-", "--json", "é", "a\x00b"]
JUNK_TOKENS = ["--unknown", "-", "--", "", "a\x00b", "--out", "-x", "--json=1", "--guides=3", "é"]

# Per command: the words before the options, then its arguments as (option or None for a
# positional, kind, valid values, required, cheap default). Kinds: a number ("size": huge values
# must be refused by the budget; "time": they would be long runs; "seed"; "float"), "choice",
# "flag", an input ("hair", "mesh", "cameras", "params", "lod") or an output ("out-file",
# "out-folder", "out-image"). An argument without a cheap default is never dropped.
COMMANDS = {
    "info": (["info"], [(None, "hair", None, True, True), ("--json", "flag", None, False, True)]),
    "convert": (["convert"], [(None, "hair", None, True, True), (None, "out-file", [".hair", ".data"], True, True),
                              ("--json", "flag", None, False, True)]),
    "generate": (["generate"], [
        (None, "mesh", None, True, True), ("--count", "size", ["1", "10", "40"], True, True),
        ("--vertices", "size", ["2", "3", "5", "9"], False, True), ("--seed", "seed", None, False, True),
        ("--lod", "float", ["0.1", "0.5", "1"], False, True), ("--subdivision", "size", ["0", "1", "2"], False, True),
        ("--radius", "float", ["0", "0.01", "1"], False, True), ("--out", "out-file", [".hair", ".data"], False, True),
        ("--json", "flag", None, False, True)]),
    "lod": (["lod"], [
        (None, "hair", None, True, True), ("--out", "out-folder", None, True, True),
        ("--guides", "size", ["1", "4", "16"], False, True), ("--levels", "size", ["2", "3", "6"], False, True),
        ("--control-points", "size", ["2", "4", "16"], False, True), ("--seed", "seed", None, False, True),
        ("--width-px", "float", ["0.5", "2", "8"], False, True), ("--cameras", "cameras", None, False, True),
        ("--force", "flag", None, False, True), ("--json", "flag", None, False, True)]),
    "bake": (["bake"], [
        ("--out", "out-folder", None, True, True), ("--theta-samples", "size", ["2", "4", "8"], True, True),
        ("--hair-count-samples", "size", ["2", "4", "8"], True, True),
        ("--table-samples", "size", ["3", "5", "9"], True, True), ("--params", "params", None, False, True),
        ("--lod", "lod", None, False, True), ("--max-hair-count", "float", ["1", "16", "64"], False, True),
        ("--tables", "choice", ["aggregated", "xu", "aggregated,xu"], False, True),
        ("--force", "flag", None, False, True), ("--json", "flag", None, False, True)]),
    "render": (["render"], [
        (None, "hair", None, True, True), ("--out", "out-image", [".png", ".exr"], True, True),
        ("--width", "size", ["1", "4", "8"], True, True), ("--spp", "time", ["1", "2"], True, True),
        ("--lod", "lod", None, True, True), ("--method", "choice", ["pt", "ds", "lod", "lod-single", "lod-no-s"],
                                             False, True),
        ("--view", "choice", ["near", "mid", "far"], False, True), ("--seed", "seed", None, False, True),
        ("--params", "params", None, False, True), ("--json", "flag", None, False, True)]),
    "bench-lod": (["bench", "lod"], [
        ("--strands", "size", ["1", "20", "50"], True, False), ("--points", "size", ["2", "4", "8"], True, False),
        ("--frames", "time", ["1", "2"], True, True), ("--guides", "size", ["1", "4"], True, True),
        ("--levels", "size", ["2", "3"], False, True), ("--control-points", "size", ["2", "4"], False, True),
        ("--width-px", "float", ["0.5", "2"], False, True), ("--json", "flag", None, False, True)]),
}
INPUT_KINDS = ("hair", "mesh", "cameras", "params", "lod")
OUTPUT_KINDS = ("out-file", "out-folder", "out-image")


class Case:
    """One generated command line and the folder it runs in:

    case/in      the inputs it reads (copies, mutated or not)
    case/cwd     its current folder (a file of the user's in it)
    case/foreign a folder of the user's files; case/notes.txt a file of the user's
    case/out     where its outputs go (the only place it may change, with the foreign folder under
                 --force and an existing file it names as its output file)
    """

    def __init__(self, command, index, data, root, home):
        self.rng = random.Random(f"{HOSTILE_SEED}-{command}-{index}")
        self.folder = root / f"{command}-{index:05d}"
        self.home, self.data = home, data
        for name in ("in", "cwd", "foreign", "out"):
            (self.folder / name).mkdir(parents=True)
        (self.folder / "cwd" / "keep.txt").write_text("the user's")
        (self.folder / "foreign" / "keep.txt").write_text("the user's")
        (self.folder / "notes.txt").write_text("the user's")
        words, arguments = COMMANDS[command]
        self.slots = []
        for option, kind, values, required, cheap in arguments:
            if required or self.rng.random() < 0.5:
                self.slots.append([option, kind, self._valid(kind, values), cheap])
        for _ in range(self.rng.choices((1, 2, 3), (7, 2, 1))[0]):
            self._mutate()
        self.argv = list(words)
        for option, kind, value, _ in self.slots:
            self.argv += ([option] if option else []) + ([] if kind == "flag" or value is None else [value])

    def _copy(self, source, name=None):
        """A copy of `source` in case/in (under a fresh name when a copy is there already)."""
        name = name or Path(source).name
        target = self.folder / "in" / name
        while target.exists():
            target = target.with_name("copy-" + target.name)
        (shutil.copytree if Path(source).is_dir() else shutil.copy)(source, target)
        return str(target)

    def _valid(self, kind, values):
        data, rng = self.data, self.rng
        if kind == "hair":
            return self._copy(rng.choice([data.hair, data.hair, data.few, data.data, EXAMPLES / "bob.hair"]))
        if kind == "mesh":
            return self._copy(rng.choice([data.mesh, data.seed_mesh, EXAMPLES / "wavy_cap.hairmesh.json"]))
        if kind in ("cameras", "params", "lod"):
            return self._copy(getattr(data, kind))
        if kind == "seed":
            return str(rng.choice([0, 1, 2**64 - 1, rng.randrange(2**64)]))
        if kind == "out-folder":
            return str(self.folder / "out" / "result")
        if kind in ("out-file", "out-image"):
            return str(self.folder / "out" / ("result" + rng.choice(values)))
        return rng.choice(values) if values else None

    def _mutate(self):
        rng = self.rng
        if not self.slots:  # the last argument was dropped: something else in its place
            self.slots.append([rng.choice(JUNK_TOKENS), "flag", None, True])
            return
        slot = rng.choice(self.slots)
        option, kind, value, cheap = slot
        what = rng.randrange(10)
        if what == 0 and cheap and not (option is None and kind in INPUT_KINDS):
            self.slots.remove(slot)
        elif what == 1:  # a stray token
            self.slots.insert(rng.randrange(len(self.slots) + 1), [rng.choice(JUNK_TOKENS), "flag", None, True])
        elif what == 2 and value is not None and kind != "flag":
            slot[2] = None  # an option without its value (positionals: the argument missing)
            if option is None:
                self.slots.remove(slot)
        elif what == 3 and kind == "out-folder" and "--force" not in [s[0] for s in self.slots]:
            self.slots.append(["--force", "flag", None, True])
        elif kind in ("size", "time", "seed", "float"):
            extra = {"size": HUGE_SIZES, "seed": ["18446744073709551615"], "float": HOSTILE_FLOATS}.get(kind, [])
            slot[2] = rng.choice(ODD_NUMBERS if rng.random() < 0.25 else HOSTILE_NUMBERS + extra)
        elif kind == "choice":
            slot[2] = rng.choice(HOSTILE_WORDS)
        elif kind in INPUT_KINDS:
            slot[2] = self._hostile_input(kind, value)
        elif kind in OUTPUT_KINDS:
            slot[2] = self._hostile_output(kind, value)
        else:
            self.slots.append([rng.choice(JUNK_TOKENS), "flag", None, True])

    def _write(self, name, content):
        path = self.folder / "in" / name
        path.write_bytes(content)
        return str(path)

    def _hostile_input(self, kind, valid):
        rng, data = self.rng, self.data
        if kind == "lod":
            return self._hostile_lod(valid)
        extension = ".hairmesh.json" if kind == "mesh" else ".json" if kind in ("cameras", "params") else \
            rng.choice([".hair", ".data", ".ply", ".tfx", ".bin"])
        content = Path(valid).read_bytes() if valid and os.path.isfile(valid) else data.hair.read_bytes()
        what = rng.randrange(12)
        if what == 0:
            return str(self.folder / "in" / ("missing" + extension))
        if what == 1:
            os.makedirs(self.folder / "in" / ("folder" + extension), exist_ok=True)
            return str(self.folder / "in" / ("folder" + extension))
        if what == 2:
            return self._write("empty" + extension, b"")
        if what == 3:
            return self._write("truncated" + extension, content[:rng.randrange(len(content) + 1)])
        if what == 4:  # another kind's content under this name
            other = rng.choice([data.hair.read_bytes(), data.mesh.read_bytes(), data.cameras.read_bytes(),
                                *data.formats.values(), b"\x00" * 64])
            return self._write("other" + extension, other)
        if what == 5:
            return self._write("named" + rng.choice([".xyz", "", ".HAIR", ".json", ".ply"]), content)
        if what == 6:
            return rng.choice(["", ".", str(self.folder / "in"), "-", "-x" + extension])
        if what == 7 and kind == "hair":
            return self._copy(rng.choice([data.huge, data.tiny, data.nan]))
        if what == 8 and kind == "hair":
            name = rng.choice(list(data.formats))
            return self._write("fuzz-" + name, fuzz_python.mutate_bytes(rng, data.formats[name]))
        mutated = content
        for _ in range(rng.randint(1, 3)):  # truncated, bit-flipped, JSON-mutated copies
            mutated = fuzz_python.mutate(rng, kind, mutated, [data.hair.read_bytes()])
        return self._write("mutated" + (extension if kind != "hair" else Path(valid or "x.hair").suffix), mutated)

    def _hostile_lod(self, valid):
        rng, data = self.rng, self.data
        folder = Path(valid) if valid and os.path.isdir(valid) else Path(self._copy(data.lod))
        what = rng.randrange(9)
        files = sorted(folder.iterdir()) if folder.is_dir() else []
        if what <= 2 and (folder / "manifest.json").is_file():
            manifest = (folder / "manifest.json").read_bytes()
            for _ in range(rng.randint(1, 3)):
                manifest = fuzz_python.mutate(rng, "manifest", manifest)
            (folder / "manifest.json").write_bytes(manifest)
        elif what == 3 and files:
            victim = rng.choice(files)
            victim.write_bytes(fuzz_python.mutate_bytes(rng, victim.read_bytes()))
        elif what == 4 and files:
            rng.choice(files).unlink()
        elif what == 5 and (folder / "offset_boxes.npy").is_file():
            _nan_offset_box(folder)
        elif what == 6:
            return self._copy(data.tables, "tables")
        elif what == 7:
            return rng.choice([self._copy(data.hair), str(self.folder / "in" / "missing"), str(self.folder / "cwd")])
        return str(folder)

    def _hostile_output(self, kind, valid):
        rng = self.rng
        inputs = [s[2] for s in self.slots if s[1] in INPUT_KINDS and s[2] and os.path.exists(s[2])]
        choices = [".", str(self.home), str(self.home / ".."), str(self.folder / "foreign"),
                   str(self.folder / "notes.txt"), str(self.folder / "in"), str(self.folder), "",
                   str(self.folder / "out" / "missing" / "deeper" / Path(valid or "result").name), *inputs]
        if kind != "out-folder":  # an existing output file: replaced only by a successful write
            existing = self.folder / "existing" / ("result" + rng.choice([".hair", ".data", ".png", ".exr", ".ply", ""]))
            existing.parent.mkdir(exist_ok=True)
            existing.write_text("the user's")
            choices += [str(existing), str(existing)]
        return rng.choice(choices)

    def output(self):
        """The output argument it names, when it writes a file (which a success may replace)."""
        for option, kind, value, _ in self.slots:
            if kind in ("out-file", "out-image") and value:
                return os.path.abspath(os.path.join(self.folder / "cwd", value))
        return None

    def protected(self):
        """Everything of the user's that the case's run must leave as it was."""
        state = snapshot(self.folder, self.home)
        return {path: digest for path, digest in state.items()
                if not path.startswith(str(self.folder / "out"))}


def _names_the_input(line, argv):
    """Heuristic: the error line quotes one of the user's paths or options, or says 'argument', or
    starts with one of the arguments (a path too short to search for: "", ".")."""
    words = set()
    for token in argv[1:]:
        if token.startswith("--"):
            name = token[2:].split("=")[0]
            words |= {name, name.replace("-", "_"), name.replace("-", " ")}
        elif token and not re.fullmatch(r"[-+.\d\s]*", token):
            words |= {token, os.path.basename(token.rstrip("/")), os.path.abspath(token)}
    message = line.removeprefix("hairlod: error: ")
    return "argument" in line or any(len(word) >= 2 and word in line for word in words) or \
        any(message.startswith(token + ":") for token in argv[1:])


def check(case, outcome, before):
    """The reasons a run broke the contract (empty when it kept it)."""
    reasons = []
    if outcome.get("failure"):
        return [outcome["failure"]]
    code, out, err = outcome["code"], outcome["stdout"], outcome["stderr"]
    if code not in (0, 2):
        reasons.append(f"exit code {code}")
    if code == 2:
        lines = err.splitlines()
        if len(lines) != 1 or not lines[0].startswith("hairlod: error: ") or "Traceback" in err:
            reasons.append("not one error line")
        elif ".hairlod-" in lines[0]:
            reasons.append("names a hidden temporary")
        elif "out of memory" in lines[0]:
            reasons.append("allocated past the memory budget (no check before allocating)")
        elif not _names_the_input(lines[0], case.argv):
            reasons.append("names neither a file nor an argument of the user's")
        if out:
            reasons.append("stdout after a failure")
    elif code == 0 and err:
        reasons.append("stderr on success")
    after = case.protected()
    replaceable = case.output() if code == 0 else None
    forced = code == 0 and "--force" in case.argv
    for path, digest in before.items():
        if after.get(path) == digest or path == replaceable:
            continue
        if forced and path.startswith(str(case.folder / "foreign")):
            continue
        reasons.append(f"changed or removed the user's {os.path.relpath(path, case.folder.parent)}")
        break
    leftovers = [path for path in snapshot(case.folder, case.home) if ".hairlod-" in os.path.basename(path)]
    if leftovers:
        reasons.append(f"left temporaries ({os.path.basename(leftovers[0])})")
    return reasons


class Worker:
    """This file run as a script (--serve): cli.main for each case it is sent. A hang or a death is
    the case's failure, after which a fresh worker takes over."""

    def __init__(self, home):
        self.environment = dict(os.environ, PYTHONPATH=str(REPO / "addon"), HOME=str(home),
                                HAIRLOD_MEMORY_BUDGET=WORKER_BUDGET)
        self.process = None

    def _start(self):
        self.process = subprocess.Popen([sys.executable, __file__, "--serve"], stdin=subprocess.PIPE,
                                        stdout=subprocess.PIPE, env=self.environment, text=True)

    def stop(self):
        if self.process is not None:
            self.process.kill()
            self.process.wait()
            self.process = None

    def run(self, argv, cwd, timeout=CASE_TIMEOUT):
        if self.process is None:
            self._start()
        try:
            self.process.stdin.write(json.dumps({"argv": argv, "cwd": cwd}) + "\n")
            self.process.stdin.flush()
            ready, _, _ = select.select([self.process.stdout], [], [], timeout)
            line = self.process.stdout.readline() if ready else None
        except BrokenPipeError:
            line = ""
        if line:
            return json.loads(line)
        failure = f"hang (no result within {timeout:.0f} s)" if line is None else \
            f"crash (the worker died: exit code {self.process.poll()})"
        self.stop()
        return {"failure": failure}


def _serve():
    """Worker mode: one JSON case per line on stdin, one JSON outcome per line on stdout. Output is
    captured at the file descriptors, so a C++ write to stderr counts as much as a Python one."""
    import resource
    import tempfile

    resource.setrlimit(resource.RLIMIT_AS, (WORKER_ADDRESS_SPACE, WORKER_ADDRESS_SPACE))
    from hairlod import cli

    requests = os.fdopen(os.dup(0), "r")
    replies = os.fdopen(os.dup(1), "w")
    os.dup2(os.open(os.devnull, os.O_RDONLY), 0)  # a command reading stdin must not eat the requests
    for request in requests:
        case = json.loads(request)
        captured = {fd: tempfile.TemporaryFile() for fd in (1, 2)}
        saved = {fd: os.dup(fd) for fd in (1, 2)}
        sys.stdout.flush()
        sys.stderr.flush()
        for fd, file in captured.items():
            os.dup2(file.fileno(), fd)
        outcome = {}
        try:
            os.chdir(case["cwd"])
            outcome["code"] = cli.main(case["argv"])
        except BaseException:  # noqa: BLE001 (an exception escaping cli.main is the failure looked for)
            outcome["failure"] = "exception escaped cli.main: " + traceback.format_exc()
        finally:
            sys.stdout.flush()
            sys.stderr.flush()
            for fd in (1, 2):
                os.dup2(saved[fd], fd)
                os.close(saved[fd])
        for fd, name in ((1, "stdout"), (2, "stderr")):
            captured[fd].seek(0)
            outcome[name] = captured[fd].read().decode("utf-8", "replace")
            captured[fd].close()
        replies.write(json.dumps(outcome) + "\n")
        replies.flush()


@pytest.mark.parametrize("command", list(COMMANDS))
def test_generated_hostile_inputs(data, tmp_path, command):
    home = tmp_path / "home"
    home.mkdir()
    (home / "keep.txt").write_text("the user's")
    worker, failures, codes, unexpected = Worker(home), [], {0: 0, 2: 0}, set()
    start = time.perf_counter()
    try:
        for index in range(HOSTILE_COUNT):
            case = Case(command, index, data, tmp_path / "cases", home)
            before = case.protected()
            outcome = worker.run(case.argv, str(case.folder / "cwd"))
            reasons = check(case, outcome, before)
            codes[outcome.get("code")] = codes.get(outcome.get("code"), 0) + 1
            # cli's catch-all names the exception type: one the code did not expect (a reader broke
            # its ValueError promise), within the CLI contract but worth a look.
            unexpected.update(re.findall(r"^hairlod: error: \S+ .*?: (\w+(?:Error|Exception)): ",
                                         outcome.get("stderr", "")))
            if reasons:
                failures.append(f"#{index} {reasons}: {case.argv!r} -> {outcome.get('stderr', '').strip()[:300]!r}")
            else:
                shutil.rmtree(case.folder)
    finally:
        worker.stop()
    seconds = time.perf_counter() - start
    print(f"\n{command}: {HOSTILE_COUNT} hostile inputs in {seconds:.1f} s, exit codes {codes}, "
          f"{len(failures)} failures; unexpected exception types reported: {sorted(unexpected) or 'none'}")
    for failure in failures:
        print("  " + failure)
    assert not failures, f"{len(failures)} of {HOSTILE_COUNT} broke the contract:\n" + "\n".join(failures[:20])


if __name__ == "__main__" and sys.argv[1:] == ["--serve"]:
    _serve()
