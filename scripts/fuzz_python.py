#!/usr/bin/python3
"""Mutation fuzzer for hairlod's Python-side readers (issue 12), pure Python: atheris is on PyPI,
which these machines cannot reach.

    scripts/fuzz_python.py TARGET SECONDS [--seed N] [--timeout S]

Targets and the call each input goes through:

    hairmesh  hairlod.hairmesh.read(file)
    manifest  hairlod.lod.load(folder) on an LoD folder of bob.hair whose manifest.json is the input
    cameras   hairlod.lod.read_cameras(file)
    params    hairlod.hair_params.as_params(hairlod.cli._read_params(file))
    unpack    hairlod.lod.unpack(bytes), from mutations of hairlod.lod.pack(asset)

Every reader promises ValueError for any bad input (params may also raise cli.UsageError, the
CLI's own bad-input error). A finding is any other exception, an input that runs longer than
--timeout seconds, or a crash of the process running it. Inputs run in a child process (fork),
restarted when it dies or hangs; the parent never imports hairlod, so each child starts the C++
core (and its thread pool) itself instead of inheriting one across fork.

Inputs are mutations of seeds (examples/data, files built at start-up, earlier findings): byte
flips, insertions, deletions, splices, and JSON-aware ones (a value replaced by a huge integer,
1e400, deep nesting, another type). An input that draws a rejection message not seen before joins
the pool of inputs to mutate, a cheap stand-in for coverage feedback. Each distinct finding
(exception type and where it was raised) is saved once, its smallest input, under
fuzz-corpus/python/TARGET/ (git-ignored) as NAME.EXT and NAME.txt (the traceback and the command
that reruns it).
Prints executions, executions/s and findings; exits 1 when there are findings.
"""

import argparse
import copy
import hashlib
import io
import json
import math
import multiprocessing
import os
import random
import re
import resource
import shutil
import signal
import struct
import subprocess
import sys
import tempfile
import time
import traceback
import zipfile

REPO_ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), os.pardir))
EXAMPLES = os.path.join(REPO_ROOT, "examples", "data")
CORPUS = os.path.join(REPO_ROOT, "fuzz-corpus", "python")
TARGETS = ("hairmesh", "manifest", "cameras", "params", "unpack")
EXTENSIONS = {"hairmesh": ".hairmesh.json", "manifest": ".json", "cameras": ".json", "params": ".json",
              "unpack": ".npz"}
# Address space of a child: a runaway allocation becomes a MemoryError (a finding where a reader
# lets it through) instead of taking the machine's memory.
CHILD_ADDRESS_SPACE = 4 << 30
POOL_LIMIT = 400

# ---------------------------------------------------------------------------------------------
# Mutations (also used by tests/python/test_hostile_inputs.py). Pure functions of an rng.

# Values a JSON reader must refuse or handle: out-of-range numbers, non-JSON constants, wrong types.
HOSTILE_JSON_VALUES = (
    "100000000000000000000", "-100000000000000000000", "-1", "0", "-0.0", "1", "2147483648", "4294967298",
    "9223372036854775808", "18446744073709551616", "1e400", "-1e400", "1e308", "-1e308", "4e-320", "3.5e38",
    "0.5", "NaN", "Infinity", "-Infinity", '""', '"abc"', '"16"', '"1e400"', '"\\u0000"', '"\\ud800"', "true",
    "false", "null", "[]", "{}", "[[]]", "[null]", '{"": 0}',
)
INTERESTING_BYTES = (0x00, 0x01, 0x7F, 0x80, 0xFF, 0x20, 0x22, 0x2C, 0x2D, 0x2E, 0x30, 0x39, 0x3A, 0x5B, 0x5D,
                     0x7B, 0x7D, 0x65, 0x5C)
INTERESTING_WORDS = (
    struct.pack("<I", 0), struct.pack("<I", 0xFFFFFFFF), struct.pack("<I", 0x7FFFFFFF), struct.pack("<I", 0x80000000),
    struct.pack("<I", 0x10000), struct.pack("<H", 0xFFFF), struct.pack("<f", float("nan")),
    struct.pack("<f", float("inf")), struct.pack("<f", 1e30), struct.pack("<f", 1e-30), struct.pack("<f", -0.0),
    struct.pack("<Q", 2**63), struct.pack("<q", -1),
)


def deep_json(rng):
    """Text nested just past, at or far past strict_json's depth limit (64)."""
    depth = rng.choice((63, 64, 65, 200, 5000, 100000))
    if rng.random() < 0.5:
        return "[" * depth + "]" * depth
    return '{"a":' * depth + "0" + "}" * depth


def mutate_bytes(rng, data, others=()):
    """1-4 byte-level mutations of `data`; `others` are inputs to splice with."""
    data = bytearray(data)
    for _ in range(rng.randint(1, 4)):
        kind = rng.randrange(9)
        at = rng.randrange(len(data) + 1)
        if kind == 0 and data:  # flip bits
            for _ in range(rng.randint(1, 8)):
                data[rng.randrange(len(data))] ^= 1 << rng.randrange(8)
        elif kind == 1 and data:
            data[min(at, len(data) - 1)] = rng.choice(INTERESTING_BYTES)
        elif kind == 2:
            word = rng.choice(INTERESTING_WORDS)
            data[at:at + len(word)] = word
        elif kind == 3:
            data[at:at] = bytes(rng.randrange(256) for _ in range(rng.randint(1, 16)))
        elif kind == 4:  # delete a range
            del data[at:at + rng.randint(1, max(1, len(data) // 8))]
        elif kind == 5 and data:  # repeat a range
            start = rng.randrange(len(data))
            chunk = data[start:start + rng.randint(1, 64)]
            data[at:at] = chunk * rng.randint(1, 16)
        elif kind == 6 and others:  # splice: a prefix of this, a suffix of another input
            other = rng.choice(others)
            data = data[:at] + other[rng.randrange(len(other) + 1):]
        elif kind == 7:
            del data[at:]
        elif kind == 8:
            data[at:at] = rng.choice(HOSTILE_JSON_VALUES).encode()
    return bytes(data)


def _nodes(value):
    """(container, key) of every value inside a parsed JSON document (iterative: deep input is fine)."""
    found, stack = [], [value]
    while stack:
        container = stack.pop()
        keys = container.keys() if isinstance(container, dict) else range(len(container))
        for key in keys:
            found.append((container, key))
            if isinstance(container[key], (dict, list)):
                stack.append(container[key])
    return found


def mutate_json(rng, data):
    """1-3 structure-aware mutations of JSON bytes: a value replaced by a hostile one (as raw text, so
    it can be what Python's json would not write: 1e400, NaN, a duplicate key), by deep nesting or by
    a copy of another value; a value wrapped in a list, retyped or deleted; a key or list item added.
    Falls back to mutate_bytes when `data` is not JSON Python can parse."""
    try:
        document = json.loads(data)
    except (ValueError, RecursionError):
        return mutate_bytes(rng, data)
    raw = {}

    def placeholder(raw_text):
        name = f"@@hostile{len(raw)}@@"
        raw[name] = raw_text
        return name

    root = [document]
    for _ in range(rng.randint(1, 3)):
        nodes = _nodes(root)
        container, key = rng.choice(nodes)
        value = container[key]
        kind = rng.randrange(8)
        if kind == 0:
            container[key] = placeholder(deep_json(rng))
        elif kind == 1:  # a value of the right shape in the wrong place
            source, source_key = rng.choice(nodes)
            container[key] = copy.deepcopy(source[source_key])
        elif kind == 2:
            container[key] = [value]
        elif kind == 3 and isinstance(value, (int, float)) and not isinstance(value, bool):
            container[key] = rng.choice((str(value), float(value), -value, value * 1e30))
        elif kind == 4 and container is not root:
            del container[key]
        elif kind == 5 and isinstance(value, dict):
            if value and rng.random() < 0.5:  # the same key twice: the reader sees only the last
                duplicate = rng.choice(list(value))
                value[placeholder(json.dumps(duplicate))] = placeholder(rng.choice(HOSTILE_JSON_VALUES))
            else:
                value["unknown_key"] = placeholder(rng.choice(HOSTILE_JSON_VALUES))
        elif kind == 6 and isinstance(value, list) and value:
            if rng.random() < 0.5:
                value.append(copy.deepcopy(value[rng.randrange(len(value))]))
            else:
                value.pop(rng.randrange(len(value)))
        else:
            container[key] = placeholder(rng.choice(HOSTILE_JSON_VALUES))
    try:
        text = json.dumps(root[0])
    except RecursionError:  # parsed just below Python's own nesting limit, and nested deeper since
        return mutate_bytes(rng, data)
    for name, raw_text in raw.items():
        text = text.replace(json.dumps(name), raw_text)
    return text.encode("utf-8", "surrogatepass")


def _npy_parts(member):
    """(header, data) of .npy bytes (format versions 1 to 3), None when they are not .npy."""
    if member[:6] != b"\x93NUMPY" or len(member) < 12:
        return None
    size, start = (struct.unpack("<H", member[8:10])[0], 10) if member[6] == 1 else \
        (struct.unpack("<I", member[8:12])[0], 12)
    return member[:start + size], member[start + size:]


def _npy_bytes(data):
    """A version 1.0 .npy of a uint8 array holding `data` (as lod.pack stores the header)."""
    header = "{'descr': '|u1', 'fortran_order': False, 'shape': (%d,), }" % len(data)
    header += " " * (63 - (10 + len(header)) % 64) + "\n"
    return b"\x93NUMPY\x01\x00" + struct.pack("<H", len(header)) + header.encode("latin-1") + data


def mutate_pack(rng, data, others=()):
    """Mutations of lod.pack() bytes. Half of them inside a valid archive, which byte mutations of
    compressed data rarely reach: the header JSON, or one array's .npy header or data, re-compressed;
    a member dropped or renamed. The other half byte-level."""
    try:
        with zipfile.ZipFile(io.BytesIO(data)) as archive:
            members = {name: archive.read(name) for name in archive.namelist()}
    except Exception:  # noqa: BLE001 (a damaged zip fails in many ways; then mutate its bytes)
        members = None
    if not members or rng.random() < 0.5:
        return mutate_bytes(rng, data, others)
    name = "header.npy" if "header.npy" in members and rng.random() < 0.5 else rng.choice(sorted(members))
    parts = _npy_parts(members[name])
    kind = rng.randrange(6)
    if kind == 0:
        del members[name]
    elif kind == 1:
        members[rng.choice(sorted(members))] = members.pop(name)
    elif name == "header.npy" and parts:
        members[name] = _npy_bytes(mutate_json(rng, parts[1]))
    elif parts and kind < 4:  # the .npy header: shape, dtype, order
        header = mutate_bytes(rng, parts[0][10:]) if rng.random() < 0.5 else \
            re.sub(rb"\d+", lambda _: rng.choice((b"0", b"1", b"2147483648", b"99999999999", b"-1")), parts[0][10:], 1)
        members[name] = parts[0][:8] + struct.pack("<H", len(header) % 65536) + header + parts[1]
    else:
        members[name] = mutate_bytes(rng, members[name])
    buffer = io.BytesIO()
    with zipfile.ZipFile(buffer, "w", zipfile.ZIP_DEFLATED) as archive:
        for member, content in members.items():
            archive.writestr(member, content)
    return buffer.getvalue()


def mutate(rng, target, data, others=()):
    """One fuzz input of `target` from `data`: JSON-aware, pack-aware or byte-level mutations."""
    if target == "unpack":
        return mutate_pack(rng, data, others)
    return mutate_json(rng, data) if rng.random() < 0.6 else mutate_bytes(rng, data, others)


# ---------------------------------------------------------------------------------------------
# Seeds, built in a child process (the parent stays free of the C++ core).

def cameras_seed():
    """Two cameras in lod.read_cameras' format: looking at the origin from +z and from +x."""
    near, far, focal = 0.1, 1000.0, 1.0 / math.tan(0.4)
    projection = [[focal / (4 / 3), 0, 0, 0], [0, focal, 0, 0],
                  [0, 0, (far + near) / (near - far), 2 * far * near / (near - far)], [0, 0, -1, 0]]
    front = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, -400], [0, 0, 0, 1]]
    side = [[0, 0, -1, 0], [0, 1, 0, 0], [1, 0, 0, -400], [0, 0, 0, 1]]
    return [{"view": front, "projection": projection, "viewport": [800, 600]},
            {"view": side, "projection": projection, "viewport": [64, 64]}]


def hair_mesh_seed():
    """A 2 x 1 quad cage of three layers with uv, w and every styling operation."""
    root = [[0, 0, 0], [1, 0, 0], [2, 0, 0], [0, 1, 0], [1, 1, 0], [2, 1, 0]]
    layers = [[[x, y, z + 0.1 * x] for x, y, _ in root] for z in (0.0, 1.0, 2.0)]
    return {"format": "hairlod.hairmesh", "version": 1, "layers": layers, "faces": [[0, 1, 4, 3], [1, 2, 5, 4]],
            "uv": [[[0, 0], [0.5, 0], [0.5, 1], [0, 1]], [[0.5, 0], [1, 0], [1, 1], [0.5, 1]]],
            "w": [[0.0] * 6, [1.0] * 6, [2.0] * 6], "strand_radius": 0.01,
            "styling": [{"op": "curl", "radius": 0.1, "frequency": 2, "randomness": 0.2},
                        {"op": "wave", "amplitude": 0.1, "frequency": 1, "randomness": 0.5},
                        {"op": "twist", "rate": 0.1}, {"op": "clump", "amount": 0.5, "profile": 1},
                        {"op": "frizz", "amplitude": 0.01, "frequency": 3}, {"op": "trim", "amount": 0.2}]}


def _build_seeds(target, workdir, connection):
    """Child: sends the seeds of `target`; the manifest and unpack seeds come from the LoD folder it
    leaves in workdir/lod (the manifest target's inputs replace its manifest.json)."""
    sys.path.insert(0, os.path.join(REPO_ROOT, "addon"))
    from hairlod import hair_params, lod

    def text(value):
        return json.dumps(value).encode()

    seeds = []
    if target == "hairmesh":
        seeds = [open(os.path.join(EXAMPLES, name), "rb").read() for name in sorted(os.listdir(EXAMPLES))
                 if name.endswith(".hairmesh.json")] + [text(hair_mesh_seed())]
    elif target == "cameras":
        seeds = [text(cameras_seed()), text(cameras_seed()[:1])]
    elif target == "params":
        seeds = [text({}), text(hair_params.params_to_dict(None)), text({"beta_m": 0.2, "sigma_a": [0.1, 0.2, 0.3]})]
    else:
        folder = os.path.join(workdir, "lod")
        environment = dict(os.environ, PYTHONPATH=os.path.join(REPO_ROOT, "addon"))
        subprocess.run([sys.executable, "-m", "hairlod", "lod", os.path.join(EXAMPLES, "bob.hair"), "--out", folder,
                        "--guides", "16"], check=True, env=environment, stdout=subprocess.DEVNULL)
        if target == "manifest":
            seeds = [open(os.path.join(folder, "manifest.json"), "rb").read()]
        else:
            seeds = [lod.pack(lod.load(folder))]
    connection.send(seeds)


# ---------------------------------------------------------------------------------------------
# Running inputs: in a child process that the parent restarts after a crash or a hang.

def _target_call(target, workdir):
    """(call(data), the exceptions that are the reader's promised rejections) for `target`."""
    sys.path.insert(0, os.path.join(REPO_ROOT, "addon"))
    from hairlod import cli, hair_params, hairmesh, lod

    if target == "unpack":
        return lod.unpack, ValueError
    if target == "manifest":
        folder = os.path.join(tempfile.mkdtemp(dir=workdir), "lod")
        shutil.copytree(os.path.join(workdir, "lod"), folder)
        path, read = os.path.join(folder, "manifest.json"), lambda _: lod.load(folder)
    else:
        path = os.path.join(tempfile.mkdtemp(dir=workdir), "input" + EXTENSIONS[target])
        read = {"hairmesh": hairmesh.read, "cameras": lod.read_cameras,
                "params": lambda file: hair_params.as_params(cli._read_params(file))}[target]

    def call(data):
        with open(path, "wb") as stream:
            stream.write(data)
        read(path)

    return call, (ValueError, cli.UsageError) if target == "params" else ValueError


def _signature(error):
    """The exception type and the innermost hairlod line it passed: one per distinct bug."""
    frames = traceback.extract_tb(error.__traceback__)
    package = os.path.join(REPO_ROOT, "addon")
    frame = ([f for f in frames if f.filename.startswith(package)] or frames or [None])[-1]
    where = f"{os.path.relpath(frame.filename, REPO_ROOT)}:{frame.lineno}" if frame else "?"
    return f"{type(error).__name__} at {where}"


def _outcome(call, accepted, data):
    """("ok", ""), ("rejected", message) or ("finding", (signature, traceback)) for one input."""
    try:
        call(data)
    except accepted as error:
        return "rejected", str(error)[:300]
    except BaseException as error:  # noqa: BLE001 (anything else is what the fuzzer looks for)
        return "finding", (_signature(error), traceback.format_exc())
    return "ok", ""


def _serve(target, workdir, connection):
    # Ctrl-C stops the parent, which reports; a KeyboardInterrupt here would read as a finding.
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    resource.setrlimit(resource.RLIMIT_AS, (CHILD_ADDRESS_SPACE, CHILD_ADDRESS_SPACE))
    call, accepted = _target_call(target, workdir)
    while True:
        try:
            data = connection.recv_bytes()
        except EOFError:
            return
        connection.send(_outcome(call, accepted, data))


class Worker:
    """A child process that runs the inputs of one target."""

    def __init__(self, target, workdir):
        self.target, self.workdir = target, workdir
        self._start()

    def _start(self):
        self.connection, child_end = _FORK.Pipe()
        self.process = _FORK.Process(target=_serve, args=(self.target, self.workdir, child_end), daemon=True)
        self.process.start()
        child_end.close()

    def stop(self):
        self.connection.close()
        self.process.kill()
        self.process.join()

    def run(self, data, timeout):
        """_outcome() of one input; a hang or a death of the child is a finding, after which the
        child is replaced."""
        try:
            self.connection.send_bytes(data)
            if self.connection.poll(timeout):
                return self.connection.recv()
            finding = ("hang", f"no result within {timeout} s")
        except (EOFError, OSError):
            self.process.join(5)
            code = self.process.exitcode
            how = f"signal {-code}" if code is not None and code < 0 else f"exit code {code}"
            finding = (f"crash ({how})", f"the process running the input died ({how})")
        self.stop()
        self._start()
        return "finding", finding


_FORK = multiprocessing.get_context("fork")


def _rejection_class(message):
    """A rejection message without the paths, numbers, strings and lists it quotes: a new one means
    the input reached a reader branch not seen before."""
    message = re.sub(r"/\S+", "PATH", message)
    message = re.sub(r"'[^']*'|\"[^\"]*\"", "S", message)
    for _ in range(100):  # innermost lists first, then the lists holding them
        message, collapsed = re.subn(r"\[[^\[\]]*\]|\{[^{}]*\}", "L", message)
        if not collapsed:
            break
    message = re.sub(r"[\[{]+", "L", message)  # a quote cut off by the reader's own truncation
    return re.sub(r"[-+]?[\d.]+(e[-+]?\d+)?", "#", message)[:100]


def _save(folder, name, extension, data, text):
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, name + extension), "wb") as stream:
        stream.write(data)
    with open(os.path.join(folder, name + ".txt"), "w") as stream:
        stream.write(text)


def _seeds(target, workdir):
    receiver, sender = _FORK.Pipe(duplex=False)
    builder = _FORK.Process(target=_build_seeds, args=(target, workdir, sender))
    builder.start()
    seeds = receiver.recv()
    builder.join()
    return seeds


def fuzz(target, seconds, seed, timeout):
    """Runs the fuzzer; returns the number of distinct findings."""
    rng = random.Random(seed)
    findings_folder = os.path.join(CORPUS, target)
    extension = EXTENSIONS[target]
    with tempfile.TemporaryDirectory(prefix="hairlod-fuzz-") as workdir:
        seeds = _seeds(target, workdir)
        if os.path.isdir(findings_folder):  # earlier findings: check they stay fixed
            seeds += [open(os.path.join(findings_folder, name), "rb").read()
                      for name in sorted(os.listdir(findings_folder)) if name.endswith(extension)]
        pool, seen = list(seeds), set()
        distinct, finding_inputs, executions = {}, 0, 0
        worker = Worker(target, workdir)
        start = time.monotonic()
        try:
            while time.monotonic() - start < seconds:
                data = mutate(rng, target, rng.choice(pool), pool)
                status, detail = worker.run(data, timeout)
                executions += 1
                if status == "rejected" and _rejection_class(detail) not in seen:
                    seen.add(_rejection_class(detail))
                    if len(pool) < POOL_LIMIT:
                        pool.append(data)
                    else:
                        pool[rng.randrange(len(seeds), POOL_LIMIT)] = data
                elif status == "finding":
                    finding_inputs += 1
                    signature, text = detail
                    if signature not in distinct or len(data) < len(distinct[signature][0]):
                        distinct[signature] = (data, text)
        except KeyboardInterrupt:
            pass
        elapsed = time.monotonic() - start
        for signature, (data, text) in sorted(distinct.items()):
            name = re.sub(r"[^a-z0-9]+", "-", signature.lower()).strip("-")[:60] + "-" + \
                hashlib.sha1(signature.encode()).hexdigest()[:8]
            path = os.path.relpath(os.path.join(findings_folder, name + extension), REPO_ROOT)
            _save(findings_folder, name, extension, data,
                  f"{signature}\nreproduce: scripts/fuzz_python.py {target} --run {path}\n\n{text}")
            print(f"finding: {signature}: {path}")
        worker.stop()
    print(f"{target}: {executions} executions in {elapsed:.1f} s ({executions / max(elapsed, 1e-9):.1f}/s), "
          f"{finding_inputs} finding inputs, {len(distinct)} distinct findings, {len(seen)} rejection kinds, "
          f"pool {len(pool)}")
    return len(distinct)


def run_one(target, path):
    """Runs one saved input in this process (a reproducer): prints the outcome, returns 1 for a finding."""
    with tempfile.TemporaryDirectory(prefix="hairlod-fuzz-") as workdir:
        if target == "manifest":
            _seeds(target, workdir)  # the LoD folder the input is the manifest of
        call, accepted = _target_call(target, workdir)
        with open(path, "rb") as stream:
            status, detail = _outcome(call, accepted, stream.read())
    print(status if status == "ok" else f"{status}: {detail if status == 'rejected' else detail[1]}")
    return 1 if status == "finding" else 0


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("target", choices=TARGETS)
    parser.add_argument("seconds", type=float, nargs="?", help="how long to fuzz")
    parser.add_argument("--seed", type=int, default=0, help="random seed of the mutations (default 0)")
    parser.add_argument("--timeout", type=float, default=10.0, help="seconds an input may run (default 10)")
    parser.add_argument("--run", metavar="FILE", help="run one input in this process and print the outcome")
    args = parser.parse_args(argv)
    if args.run:
        return run_one(args.target, args.run)
    if args.seconds is None:
        parser.error("give SECONDS to fuzz, or --run FILE")
    return 1 if fuzz(args.target, args.seconds, args.seed, args.timeout) else 0


if __name__ == "__main__":
    sys.exit(main())
