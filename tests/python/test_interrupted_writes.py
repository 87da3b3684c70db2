"""Issue 12, item 5: interrupted and concurrent writes leave one complete result and no temporaries.

The commands that write (`lod`, `bake`, `convert`) run as a user runs them, a subprocess of
`python3 -m hairlod`, and are

- SIGKILLed at points spread over the run, some timed (a fraction of an unkilled run's wall time)
  and some during the final write (as soon as a temporary of the target appears): the target must
  then be absent or the complete previous or new result, and the next, unkilled run of the same
  command must succeed and remove the temporaries the killed one left;
- sent SIGTERM / SIGINT: the process must clean up by itself (exit 128 + signal, one stderr line,
  no temporaries);
- run four at a time on one target (and lod.save from four threads): one complete result of one of
  the writers, nothing else beside it.

HAIRLOD_KILL_RUNS sets the number of kill points per command (default 3; the whole module then takes
about a minute and a half on two cores), HAIRLOD_CONCURRENT_ROUNDS the rounds of each concurrency
test (default 6). HAIRLOD_KILL_LOG names a file to which every kill and signal run appends one JSON
line (what the kill left, the target's state, the exit latency), for the long runs of the issue's
target ("no stale temporaries after 100 killed runs": HAIRLOD_KILL_RUNS=34).
"""

import hashlib
import json
import os
import shutil
import signal
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

from hairlod.atomic_output import files_named

from conftest import REPO

KILL_RUNS = int(os.environ.get("HAIRLOD_KILL_RUNS", "3"))
CONCURRENT_ROUNDS = int(os.environ.get("HAIRLOD_CONCURRENT_ROUNDS", "6"))
KILL_LOG = os.environ.get("HAIRLOD_KILL_LOG")

# Delays after the target's first temporary appears, cycled over the write kill points: 0 hits the
# very start of the write, the longer ones its middle and end (the lod and bake writes take tens of
# milliseconds, convert's a few hundred).
WRITE_OFFSETS = (0.0, 0.002, 0.005, 0.010, 0.020, 0.040)
SIGNAL_EXIT_TIMEOUT = 10.0  # a hang detector, not a speed test
SIGNAL_ATTEMPTS = 5  # runs to catch one before it ends (see test_signal_cleans_up_before_exiting)
TEMPORARY_MARK = ".hairlod-"

# Sizes that make each command run one to two seconds on two cores, so that timed kill points land
# in its different stages (start-up, read, compute, write).
LOD_STRANDS, CONVERT_STRANDS, POINTS = 30_000, 300_000, 17
LOD_GUIDES = "128"
BAKE_SIZES = ["--theta-samples", "384", "--hair-count-samples", "384", "--table-samples", "385"]
NEW_SEED, PREVIOUS_SEED = 0, 7


def kill_points(count):
    """`count` kill points: every third during the final write (seconds after the first temporary
    appears), the others timed at fractions spread evenly over an unkilled run's wall time."""
    writes = count // 3
    timed = count - writes
    points = [("after", round(0.95 * (j + 0.5) / timed, 3)) for j in range(timed)]
    for j in range(writes):
        points.insert(3 * j + 2, ("writing", WRITE_OFFSETS[j % len(WRITE_OFFSETS)]))
    return points


def _point_id(point):
    kind, value = point
    return f"at{value:.2f}" if kind == "after" else f"writing+{value * 1000:g}ms"


COMMANDS = ("lod", "bake", "convert")
KILL_CASES = [(name, index) for name in COMMANDS for index in range(KILL_RUNS)]


def _log(record):
    if KILL_LOG:
        with open(KILL_LOG, "a", encoding="utf-8") as log:
            log.write(json.dumps(record) + "\n")


def _environment():
    return dict(os.environ, PYTHONPATH=str(REPO / "addon"))


def _start(argv):
    return subprocess.Popen([sys.executable, "-m", "hairlod", *map(str, argv)], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, env=_environment(), cwd=REPO)


def _run(argv, timeout=600):
    return subprocess.run([sys.executable, "-m", "hairlod", *map(str, argv)], capture_output=True, text=True,
                          env=_environment(), cwd=REPO, timeout=timeout)


def _temporaries_of(folder, name):
    """Hidden entries named after `name` in `folder`: the temporaries of target `name`, whichever
    naming scheme made them (the one of atomic_output, or an older one)."""
    return sorted(entry for entry in os.listdir(folder) if entry.startswith(f".{name}."))


def _marked_anywhere(folder):
    """Every path under `folder` whose name carries hairlod's temporary mark."""
    found = []
    for parent, folders, files in os.walk(folder):
        found += [os.path.join(parent, entry) for entry in folders + files if TEMPORARY_MARK in entry]
    return sorted(found)


def _assert_only_target(out, target):
    """`out` holds the target and nothing else: no temporary of any naming scheme, no `.old`."""
    left = sorted(set(os.listdir(out)) - {target.name})
    assert not left, f"left beside {target.name}: {left}"
    assert not _marked_anywhere(out), f"temporaries under {out}: {_marked_anywhere(out)}"


def _sha256(path):
    digest = hashlib.sha256()
    with open(path, "rb") as file:
        for block in iter(lambda: file.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def _read_manifest(folder):
    with open(os.path.join(folder, "manifest.json"), encoding="utf-8") as file:
        return json.load(file)


def _assert_holds_what_manifest_names(folder, manifest):
    # A mixture of two writes, or a temporary inside the folder, shows as a file the manifest does
    # not name or a named one missing.
    assert set(os.listdir(folder)) == files_named(manifest) | {"manifest.json"}, f"{folder}: {sorted(os.listdir(folder))}"


def _synthetic_strands(count, points, seed):
    """Strands hanging from a cap, with per-strand direction and phase: clusterable like hair."""
    import hairlod

    rng = np.random.default_rng(seed)
    theta, phi = rng.uniform(0, 2 * np.pi, count), rng.uniform(0, 0.45 * np.pi, count)
    roots = np.stack([np.sin(phi) * np.cos(theta), np.sin(phi) * np.sin(theta), np.cos(phi)], 1)
    t = np.linspace(0, 1, points)[None, :, None]
    directions = roots + 0.3 * rng.normal(size=(count, 3))
    curves = (roots[:, None] + 0.5 * t * directions[:, None] + 1.5 * t**2 * np.array([0, 0, -1.0])
              + 0.02 * np.sin(8 * t + rng.uniform(0, 6, (count, 1, 1))))
    return hairlod.Strands.from_counts(np.ascontiguousarray(curves.reshape(-1, 3), dtype=np.float32),
                                       np.full(count, points, np.int64), np.full(count * points, 1e-3, np.float32))


@pytest.fixture(scope="session")
def data(tmp_path_factory):
    """Inputs written once per session: hair files for lod and convert, parameters for bake."""
    from hairlod import io

    folder = tmp_path_factory.mktemp("interrupted_inputs")
    io.write(folder / "lod.hair", _synthetic_strands(LOD_STRANDS, POINTS, seed=1))
    io.write(folder / "convert.hair", _synthetic_strands(CONVERT_STRANDS, POINTS, seed=2))
    io.write(folder / "small.hair", _synthetic_strands(2_000, 9, seed=3))
    for index, sigma_a in enumerate([(0.2, 0.5, 1.2), (0.3, 0.6, 1.1), (0.4, 0.7, 1.0), (0.5, 0.8, 0.9), (1.0, 1.0, 1.0)]):
        (folder / f"params{index}.json").write_text(json.dumps({"sigma_a": list(sigma_a)}))
    return folder


class _Case:
    """One writing command: how to run its new and its previous version into a target, and which
    of the two complete results a target holds (AssertionError when it holds neither)."""

    target_name = None

    def __init__(self, data, scratch):
        self.data = data
        self.references = {}
        for version in ("previous", "new"):
            folder = scratch / version
            folder.mkdir()
            target = folder / self.target_name
            start = time.monotonic()
            run = _run(self.argv(target, version))
            assert run.returncode == 0, run.stderr
            if version == "new":
                self.duration = time.monotonic() - start
            self.references[version] = target

    def argv(self, target, version="new"):
        raise NotImplementedError

    def install_previous(self, target):
        """Put the previous complete result at target, replacing what an earlier attempt left there."""
        if target.is_dir():
            shutil.rmtree(target)
        elif target.exists():
            target.unlink()
        copy = shutil.copytree if self.references["previous"].is_dir() else shutil.copy2
        copy(self.references["previous"], target)

    def identify(self, target):
        raise NotImplementedError


class _Lod(_Case):
    target_name = "asset"

    def argv(self, target, version="new"):
        seed = NEW_SEED if version == "new" else PREVIOUS_SEED
        return ["lod", self.data / "lod.hair", "--out", target, "--guides", LOD_GUIDES, "--seed", seed]

    def identify(self, target):
        from hairlod import lod

        try:
            lod.load(target)
        except ValueError as error:
            raise AssertionError(f"{target} does not load: {error}") from None
        manifest = _read_manifest(target)
        _assert_holds_what_manifest_names(target, manifest)
        version = {NEW_SEED: "new", PREVIOUS_SEED: "previous"}[manifest["extra"]["options"]["seed"]]
        # The build is deterministic: every stored file equals the reference run's byte for byte.
        reference = self.references[version]
        for name in files_named(manifest):
            assert _sha256(target / name) == _sha256(reference / name), f"{target}/{name} differs from the {version} result"
        return version


class _Bake(_Case):
    target_name = "tables"

    def argv(self, target, version="new"):
        if version == "new":
            return ["bake", "--out", target, "--params", self.data / "params0.json", *BAKE_SIZES]
        return ["bake", "--out", target, "--params", self.data / "params4.json"]

    def identify(self, target):
        manifest = _read_manifest(target)
        assert manifest["format"] == "hairlod-bcsdf-lut"
        _assert_holds_what_manifest_names(target, manifest)
        version = next((v for v, folder in self.references.items() if _read_manifest(folder) == manifest), None)
        assert version is not None, f"{target}: the manifest is neither the previous nor the new one"
        for table in manifest["tables"]:
            path = target / table["file"]
            assert _sha256(path) == _sha256(self.references[version] / table["file"]), f"{path} is not complete"
        return version


class _Convert(_Case):
    target_name = "out.hair"

    def argv(self, target, version="new"):
        source = "convert.hair" if version == "new" else "small.hair"
        return ["convert", self.data / source, target]

    def identify(self, target):
        from hairlod import io

        try:
            strands = io.read(target)
        except ValueError as error:
            raise AssertionError(f"{target} does not read: {error}") from None
        digest = _sha256(target)
        version = next((v for v, path in self.references.items() if _sha256(path) == digest), None)
        assert version is not None, f"{target} ({len(strands)} strands) is neither the previous nor the new file"
        return version


@pytest.fixture(scope="session")
def cases(data, tmp_path_factory):
    """Each command calibrated once: its reference results and an unkilled run's wall time."""
    made = {}

    def case(name):
        if name not in made:
            kind = {"lod": _Lod, "bake": _Bake, "convert": _Convert}[name]
            made[name] = kind(data, tmp_path_factory.mktemp(f"reference_{name}"))
        return made[name]

    return case


def _state(case, target):
    """"absent", "previous", "new", or "broken (why)": what a run left at `target`."""
    if not os.path.lexists(target):
        return "absent"
    try:
        return case.identify(target)
    except (AssertionError, OSError, ValueError, KeyError) as error:
        return f"broken ({error})"


def _catches(pid, numbers):
    """Whether process `pid` has handlers for every signal of `numbers` (Linux: SigCgt in
    /proc/PID/status); True where that cannot be read, so that callers then only wait."""
    try:
        with open(f"/proc/{pid}/status", encoding="ascii") as status:
            caught = next(int(line.split()[1], 16) for line in status if line.startswith("SigCgt:"))
    except (OSError, StopIteration, ValueError, IndexError):
        return True
    return all(caught >> (number - 1) & 1 for number in numbers)


def _wait_for(process, point, duration, out, name, handled=()):
    """Returns when kill point `point` is reached, or when the process has ended before it. With
    `handled` (signal numbers), an "after" point is not before the process handles them: a signal
    that comes while Python is still starting (on a loaded machine, past the usual fraction of the
    run) kills it before it has anything to clean up, which is not what the point stands for."""
    kind, value = point
    started = time.monotonic()
    if kind == "after":
        while handled and process.poll() is None and not _catches(process.pid, handled) and \
                time.monotonic() - started < 10 * duration + 60:
            time.sleep(0.001)
        try:
            process.wait(timeout=max(0.0, value * duration - (time.monotonic() - started)))
        except subprocess.TimeoutExpired:
            pass
        return
    # Poll for the first temporary: the write has begun. The cap only guards a run that never
    # writes (it then fails in the checks that follow, not here).
    while process.poll() is None and time.monotonic() - started < 10 * duration + 60:
        if _temporaries_of(out, name):
            time.sleep(value)
            return
        time.sleep(0.0005)


@pytest.mark.parametrize("name,index", KILL_CASES,
                         ids=[f"{name}-{index}-{_point_id(kill_points(KILL_RUNS)[index])}" for name, index in KILL_CASES])
def test_killed_run_leaves_a_complete_target_and_the_next_run_cleans_up(cases, tmp_path, name, index):
    case = cases(name)
    point = kill_points(KILL_RUNS)[index]
    out = tmp_path / "out"
    out.mkdir()
    target = out / case.target_name
    # Every other kill point has a previous result in place, which the killed run must not lose.
    had_previous = index % 2 == 0
    if had_previous:
        case.install_previous(target)

    process = _start(case.argv(target))
    _wait_for(process, point, case.duration, out, case.target_name)
    process.kill()
    process.communicate()
    left_by_kill = _temporaries_of(out, case.target_name)
    state = _state(case, target)
    allowed = {"previous", "new"} if had_previous else {"absent", "new"}
    _log({"test": "kill", "command": name, "point": _point_id(point), "killed": process.returncode == -signal.SIGKILL,
          "had_previous": had_previous, "state": state, "left_by_kill": left_by_kill})
    assert state in allowed, f"after SIGKILL {_point_id(point)}: the target is {state}"

    again = _run(case.argv(target))
    left_after = sorted(set(os.listdir(out)) - {case.target_name})
    if left_after:
        _log({"test": "stale", "command": name, "point": _point_id(point), "left_after_next_run": left_after})
    assert again.returncode == 0, again.stderr
    assert case.identify(target) == "new"
    _assert_only_target(out, target)


# "computing": past start-up (the signal handlers are in place after about a sixth of a run), inside
# the read or the C++ build; "writing": temporaries exist, at the start of the write and 20 ms into
# it (lod is then writing its per-level files into the staging folder).
SIGNAL_POINTS = {"computing": ("after", 0.45), "writing+0ms": ("writing", 0.0), "writing+20ms": ("writing", 0.020)}


@pytest.mark.parametrize("trigger", list(SIGNAL_POINTS))
@pytest.mark.parametrize("number", [signal.SIGTERM, signal.SIGINT], ids=["SIGTERM", "SIGINT"])
@pytest.mark.parametrize("name", COMMANDS)
def test_signal_cleans_up_before_exiting(cases, tmp_path, name, number, trigger):
    case = cases(name)
    out = tmp_path / "out"
    out.mkdir()
    target = out / case.target_name
    writing = trigger.startswith("writing")

    # On a loaded machine a run can end before its signal comes: then there was nothing to interrupt,
    # so run again (the signal point is reached again) rather than judge a run that was not signalled.
    for attempt in range(SIGNAL_ATTEMPTS):
        if writing:
            case.install_previous(target)
        process = _start(case.argv(target))
        kind, value = SIGNAL_POINTS[trigger]
        # A fast machine can finish the whole write within the delay: each retry halves it, so that the
        # signal still comes inside the write (20, 10, 5, 2.5, 1.25 ms into it).
        _wait_for(process, (kind, value / 2 ** attempt if kind == "writing" else value), case.duration, out,
                  case.target_name, handled=(signal.SIGINT, signal.SIGTERM))
        sent = time.monotonic()
        process.send_signal(number)
        try:
            _, stderr = process.communicate(timeout=SIGNAL_EXIT_TIMEOUT)
        except subprocess.TimeoutExpired:
            process.kill()
            process.communicate()
            pytest.fail(f"{name} did not exit within {SIGNAL_EXIT_TIMEOUT} s of {number.name}")
        latency = time.monotonic() - sent
        state = _state(case, target)
        left = sorted(set(os.listdir(out)) - {case.target_name})
        _log({"test": "signal", "command": name, "signal": number.name, "trigger": trigger,
              "returncode": process.returncode, "latency_s": round(latency, 3), "state": state, "left": left,
              "stderr": stderr, "attempt": attempt})
        if process.returncode != 0:
            break
        # Not signalled in time, so it must have succeeded completely.
        assert state == "new" and not left, f"{name} exited 0 leaving the target {state} and {left}"
    else:
        pytest.fail(f"{name} finished before {number.name} at the {trigger} point in {SIGNAL_ATTEMPTS} runs")
    assert process.returncode == 128 + number, stderr
    lines = stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("hairlod:"), stderr
    # "new": the signal came as the write ended; the process still reports the interruption.
    assert state in ({"previous", "new"} if writing else {"absent", "new"}), f"after {number.name}: the target is {state}"
    _assert_only_target(out, target)


def _dead_pid():
    child = subprocess.Popen([sys.executable, "-c", "pass"])
    child.wait()
    return child.pid


@pytest.mark.parametrize("name", COMMANDS)
def test_next_run_removes_only_stale_temporaries(data, tmp_path, name):
    """Stale: the process is gone, or it started after the temporary was last changed (its id was
    reused). Kept: a live writer's temporary, and hidden files that are not hairlod temporaries."""
    out = tmp_path / "out"
    out.mkdir()
    target_name = {"lod": "asset", "bake": "tables", "convert": "out.hair"}[name]
    argv = {"lod": ["lod", data / "small.hair", "--out", out / target_name, "--guides", "16"],
            "bake": ["bake", "--out", out / target_name, "--theta-samples", "8", "--hair-count-samples", "8"],
            "convert": ["convert", data / "small.hair", out / target_name]}[name]
    live = subprocess.Popen(["sleep", "120"])
    try:
        time.sleep(0.1)  # the temporaries below are changed after `live` started
        dead, prefix = _dead_pid(), f".{target_name}.hairlod-"
        stale = [f"{prefix}{dead}-00ff00ff00ff00ff.tmp", f"{prefix}{dead}-0123456789abcdef.tmp", f"{prefix}{live.pid}-aa.tmp"]
        kept = [f"{prefix}{live.pid}-bb.tmp", f"{prefix}{os.getpid()}-cc.tmp", f"{prefix}notes.tmp", f".{target_name}.tmp",
                f".{target_name}.hairlod-{dead}-xyz.tmp"]
        (out / stale[0]).write_bytes(b"partial")
        (out / stale[1]).mkdir()
        (out / stale[1] / "level0.npy").write_bytes(b"partial")
        (out / stale[2]).write_bytes(b"partial")
        an_hour_before = time.time() - 3600
        os.utime(out / stale[2], (an_hour_before, an_hour_before))  # older than the live process: its id was reused
        for entry in kept:
            (out / entry).write_bytes(b"user data")
        run = _run(argv)
    finally:
        live.kill()
        live.wait()
    assert run.returncode == 0, run.stderr
    assert sorted(os.listdir(out)) == sorted(kept + [target_name])


def _assert_lod_result_of_one(target, results):
    """`target` is the complete result of one of `results` ({seed: the --json report})."""
    from hairlod import lod

    lod.load(target)
    manifest = _read_manifest(target)
    _assert_holds_what_manifest_names(target, manifest)
    seed = manifest["extra"]["options"]["seed"]
    assert seed in results
    report = results[seed]
    assert manifest["clusters"] == report["clusters"]
    assert [level["hairs"] for level in manifest["thick_levels"]] == [level["hairs"] for level in report["levels"]]


def test_concurrent_lod_runs_end_with_one_complete_result(data, tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    target = out / "asset"
    seeds = [11, 12, 13, 14]
    # Round 0 races to create the target, the others to replace it. A small input, so that the
    # four writes overlap and the rounds are many.
    for _ in range(CONCURRENT_ROUNDS):
        processes = {seed: _start(["lod", data / "small.hair", "--out", target, "--guides", "16", "--seed", seed, "--json"])
                     for seed in seeds}
        reports = {}
        for seed, process in processes.items():
            stdout, stderr = process.communicate(timeout=600)
            assert process.returncode == 0, stderr
            reports[seed] = json.loads(stdout)
        _assert_lod_result_of_one(target, reports)
        _assert_only_target(out, target)


def test_concurrent_bakes_end_with_one_complete_result(data, tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    target = out / "tables"
    for _ in range(CONCURRENT_ROUNDS):
        processes = [_start(["bake", "--out", target, "--params", data / f"params{index}.json", "--theta-samples", "32",
                             "--hair-count-samples", "32", "--json"]) for index in range(4)]
        reports = []
        for process in processes:
            stdout, stderr = process.communicate(timeout=600)
            assert process.returncode == 0, stderr
            reports.append(json.loads(stdout))
        manifest = _read_manifest(target)
        _assert_holds_what_manifest_names(target, manifest)
        writer = [report for report in reports if report["hair_params"] == manifest["params"]]
        assert len(writer) == 1, "the tables are not those of exactly one writer"
        assert [(t["name"], t["file"], t["bytes"]) for t in manifest["tables"]] == \
            [(t["name"], t["file"], t["bytes"]) for t in writer[0]["tables"]]
        for table in manifest["tables"]:
            assert os.path.getsize(target / table["file"]) > 0
        _assert_only_target(out, target)


def _arrays_equal(left, right):
    if isinstance(left, dict):
        return left.keys() == right.keys() and all(_arrays_equal(left[key], right[key]) for key in left)
    if isinstance(left, (list, tuple)):
        return len(left) == len(right) and all(_arrays_equal(a, b) for a, b in zip(left, right))
    return np.array_equal(left, right)


def test_concurrent_saves_from_threads_end_with_one_complete_result(data, tmp_path):
    from hairlod import io, lod

    strands = io.read(data / "small.hair")
    assets = {seed: lod.build_lod(strands, guides=16, seed=seed) for seed in range(4)}
    out = tmp_path / "out"
    out.mkdir()
    target = out / "asset"
    # A round costs a tenth of a second: more of them than of the subprocess rounds.
    for _ in range(5 * CONCURRENT_ROUNDS):
        start, failures = threading.Barrier(len(assets)), []

        def save(seed):
            start.wait()  # all threads reach save() together
            try:
                lod.save(assets[seed], target, extra={"seed": seed})
            except BaseException as error:  # reported by the main thread
                failures.append(error)

        threads = [threading.Thread(target=save, args=(seed,)) for seed in assets]
        for thread in threads:
            thread.start()
        for thread in threads:
            thread.join()
        assert not failures, failures
        loaded = lod.load(target)
        manifest = _read_manifest(target)
        _assert_holds_what_manifest_names(target, manifest)
        assert _arrays_equal(loaded.arrays(), assets[manifest["extra"]["seed"]].arrays())
        _assert_only_target(out, target)
