"""Command line: python3 -m hairlod <command> ... [--json].

Contract (DESIGN.md): --json prints one JSON object on stdout; bad input exits with code 2 and one
line on stderr naming the file or parameter and the problem, never a traceback; no partial output
file is left behind.
"""

import argparse
import json
import os
import sys
import time

from . import __version__

EXIT_BAD_INPUT = 2


class UsageError(Exception):
    """A bad command line: reported as one line, exit code 2."""


class _Parser(argparse.ArgumentParser):
    def error(self, message):
        raise UsageError(message)


def strand_summary(strands):
    """Counts, points per strand, bounding box and total length of Strands, as plain Python."""
    import numpy as np

    counts = strands.counts()
    lower, upper = strands.bounding_box()
    has_curves = len(strands) > 0
    return {
        "strands": len(strands),
        "points": strands.point_count,
        "points_per_strand": {
            "min": int(counts.min()) if has_curves else 0,
            "mean": float(counts.mean()) if has_curves else 0.0,
            "max": int(counts.max()) if has_curves else 0,
        },
        "bounding_box": {"min": [float(v) for v in lower], "max": [float(v) for v in upper]},
        "total_length": float(np.sum(strands.curve_lengths())),
        "radius": {
            "min": float(strands.radius.min()) if has_curves else 0.0,
            "max": float(strands.radius.max()) if has_curves else 0.0,
        },
        "attributes": {name: strands.attribute_domain(name) for name in strands.attribute_names()},
    }


def _print_summary(path, summary):
    per_strand = summary["points_per_strand"]
    box = summary["bounding_box"]
    print(f"{path}")
    print(f"  strands            {summary['strands']}")
    print(f"  points             {summary['points']}")
    print(f"  points per strand  min {per_strand['min']}  mean {per_strand['mean']:.2f}  max {per_strand['max']}")
    print("  bounding box       min ({:.6g}, {:.6g}, {:.6g})  max ({:.6g}, {:.6g}, {:.6g})".format(*box["min"], *box["max"]))
    print(f"  total length       {summary['total_length']:.6g}")
    print(f"  radius             min {summary['radius']['min']:.6g}  max {summary['radius']['max']:.6g}")
    if summary["attributes"]:
        attributes = ", ".join(f"{name} ({domain})" for name, domain in summary["attributes"].items())
        print(f"  attributes         {attributes}")


def _read_timed(path):
    from . import io

    start = time.perf_counter()
    strands = io.read(path)
    return strands, time.perf_counter() - start


def command_info(args):
    strands, seconds = _read_timed(args.file)
    summary = strand_summary(strands)
    if args.json:
        print(json.dumps({"file": args.file, **summary, "read_seconds": seconds}))
    else:
        _print_summary(args.file, summary)
    return 0


def command_convert(args):
    from . import io

    extension = os.path.splitext(args.output)[1].lower()
    if extension not in io.WRITE_FORMATS:
        supported = ", ".join(io.WRITE_FORMATS)
        raise UsageError(f"{args.output}: cannot write '{extension or 'no extension'}' files (supported: {supported})")
    strands, read_seconds = _read_timed(args.input)
    start = time.perf_counter()
    io.write(args.output, strands)
    write_seconds = time.perf_counter() - start
    result = {
        "input": args.input,
        "output": args.output,
        "strands": len(strands),
        "points": strands.point_count,
        "read_seconds": read_seconds,
        "write_seconds": write_seconds,
    }
    if args.json:
        print(json.dumps(result))
    else:
        print(f"{args.input} -> {args.output}: {result['strands']} strands, {result['points']} points")
    return 0


def command_generate(args):
    from . import hairmesh

    if args.out is not None:
        from . import io

        extension = os.path.splitext(args.out)[1].lower()
        if extension not in io.WRITE_FORMATS:
            supported = ", ".join(io.WRITE_FORMATS)
            raise UsageError(f"{args.out}: cannot write '{extension or 'no extension'}' files (supported: {supported})")
    if args.count < 1 or args.seed < 0:
        raise UsageError(f"--count must be >= 1 and --seed >= 0, got {args.count} and {args.seed}")
    start = time.perf_counter()
    source = hairmesh.read(args.hairmesh)
    read_seconds = time.perf_counter() - start
    try:
        mesh, styling, radius = hairmesh.resolve_inputs(source, radius=args.radius)
        start = time.perf_counter()
        generator = hairmesh.strand_generator(mesh, args.count, args.seed, args.subdivision)
        prepare_seconds = time.perf_counter() - start
        start = time.perf_counter()
        strands = generator.generate(vertices=args.vertices, styling=styling, strand_lod=args.lod,
                                     vertex_lod=args.lod, radius=radius)
        generate_seconds = time.perf_counter() - start
    except ValueError as error:
        raise ValueError(f"{args.hairmesh}: {error}") from None
    write_seconds = None
    if args.out is not None:
        start = time.perf_counter()
        io.write(args.out, strands)
        write_seconds = time.perf_counter() - start
    result = {
        "input": args.hairmesh,
        "output": args.out,
        "bundles": source.mesh.face_count,
        "strands": len(strands),
        "points": strands.point_count,
        "points_per_strand": int(strands.counts()[0]) if len(strands) else 0,
        "styling": hairmesh.styling_to_dicts(source.styling),
        "read_seconds": read_seconds,
        "prepare_seconds": prepare_seconds,
        "generate_seconds": generate_seconds,
        "write_seconds": write_seconds,
    }
    if args.json:
        print(json.dumps(result))
    else:
        target = f" -> {args.out}" if args.out else ""
        print(f"{args.hairmesh}{target}: {result['strands']} strands of {result['points_per_strand']} points "
              f"generated in {generate_seconds:.3f} s (+ {prepare_seconds:.3f} s subdivision, frames, root samples)")
    return 0


def _strand_bytes(strands):
    """Bytes of the strand data the LoD asset is compared with: points, radius, offsets."""
    return strands.points.nbytes + strands.radius.nbytes + strands.offsets.nbytes


def _level_report(asset):
    return [{"level": level_id, "hairs": int(len(level.n_total)), "coverage": level.coverage, "mean_area": level.mean_area}
            for level_id, level in zip(asset.level_ids, asset.levels)]


def _positive(name, value, lowest=1):
    if value < lowest:
        raise UsageError(f"--{name} must be >= {lowest}, got {value}")


def command_lod(args):
    from . import lod

    for name in ("guides", "levels", "control_points"):
        _positive(name.replace("_", "-"), getattr(args, name), 2 if name != "guides" else 1)
    if not args.width_px > 0:
        raise UsageError(f"--width-px must be > 0, got {args.width_px}")
    cameras = lod.read_cameras(args.cameras) if args.cameras else None
    strands, read_seconds = _read_timed(args.input)
    start = time.perf_counter()
    asset = lod.build_lod(strands, guides=args.guides, levels=args.levels, control_points=args.control_points, seed=args.seed)
    build_seconds = time.perf_counter() - start
    finest = len(asset.levels)
    selected = list(range(finest + 1))
    if cameras:
        # Item 8: keep only the levels some camera selects; at least one thick level stays, as the
        # asset's hierarchy and the strands' skinning are defined through the thick levels.
        selected = lod.scene_levels(asset, cameras, args.width_px)
        kept = [level for level in selected if level < finest] or [finest - 1]
        asset = asset.with_levels(kept)
    options = {name: getattr(args, name) for name in ("guides", "levels", "control_points", "seed", "width_px")}
    start = time.perf_counter()
    manifest = lod.save(asset, args.out, extra={
        "input": os.path.abspath(args.input),
        "options": options,
        "cameras": len(cameras) if cameras else 0,
        "selected_levels": selected,
        "strands_selected": finest in selected,
    })
    write_seconds = time.perf_counter() - start
    result = {
        "input": args.input,
        "output": args.out,
        "strands": len(strands),
        "guides": asset.guide_count,
        "clusters": asset.cluster_count,
        "built_levels": finest + 1,
        "selected_levels": selected,
        "levels": _level_report(asset),
        "area_ratios": manifest["area_ratios"],
        "memory_ratio": asset.memory_bytes / _strand_bytes(strands),
        "timings": asset.timings,
        "read_seconds": read_seconds,
        "build_seconds": build_seconds,
        "write_seconds": write_seconds,
    }
    if args.json:
        print(json.dumps(result))
    else:
        print(f"{args.input} -> {args.out}: {len(strands)} strands, {asset.cluster_count} clusters, "
              f"thick levels {[level['hairs'] for level in result['levels']]}, build {build_seconds:.2f} s")
    return 0


def synthetic_hair(strands, points, seed=7):
    """Wavy strands hanging from a unit cylinder-capped head (the C++ benchmark's shape)."""
    import numpy as np

    from . import Strands

    rng = np.random.default_rng(seed)
    azimuth, height = rng.uniform(0, 2 * np.pi, strands), rng.uniform(0, 1, strands)
    roots = np.stack([np.cos(azimuth), np.sin(azimuth), height], axis=1)
    t = np.linspace(0, 1, points)
    wave = np.stack([0.05 * np.sin(12 * t[None, :] + azimuth[:, None]), np.zeros((strands, points)),
                     -np.broadcast_to(t, (strands, points))], axis=2)
    positions = (roots[:, None, :] * (1 + 0.3 * t[None, :, None]) + wave).astype(np.float32).reshape(-1, 3)
    return Strands.from_counts(positions, np.full(strands, points), np.full(strands * points, 0.001, np.float32))


def command_bench(args):
    import numpy as np

    from . import lod
    from .camera import look_at, perspective

    _positive("strands", args.strands)
    _positive("points", args.points, 2)
    _positive("frames", args.frames)
    strands = synthetic_hair(args.strands, args.points)
    start = time.perf_counter()
    asset = lod.build_lod(strands, guides=args.guides, levels=args.levels, control_points=args.control_points)
    build_seconds = time.perf_counter() - start
    projection = perspective(np.radians(40), 16 / 9, 0.05, 100)
    selection = {}
    for distance in (3.0, 6.0, 30.0):
        view = look_at((distance, 0, 0), (0, 0, -0.5))
        seconds = asset._core.time_selection(view.astype(np.float32), projection.astype(np.float32), (1920.0, 1080.0),
                                             args.width_px, args.frames)
        levels = asset.select(view, projection, (1920, 1080), args.width_px).levels
        selection[f"distance_{distance:g}"] = {"seconds_per_frame": seconds, "mean_level": float(levels.mean())}
    result = {
        "component": "lod",
        "strands": args.strands,
        "points_per_strand": args.points,
        "guides": asset.guide_count,
        "clusters": asset.cluster_count,
        "control_points": args.control_points,
        "built_levels": len(asset.levels) + 1,
        "build_seconds": build_seconds,
        "stages": asset.timings,
        "selection": selection,
        "memory_ratio": asset.memory_bytes / _strand_bytes(strands),
        "levels": _level_report(asset),
        "area_ratios": asset.area_ratios,
    }
    if args.json:
        print(json.dumps(result))
    else:
        print(json.dumps(result, indent=1))
    return 0


def build_parser():
    parser = _Parser(prog="python3 -m hairlod", description="Strand hair to real-time LoD assets.")
    parser.add_argument("--version", action="version", version=f"hairlod {__version__}")
    commands = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    commands.required = True

    info = commands.add_parser("info", help="summarise a hair file")
    info.add_argument("file", help="hair file (.hair .data .bin .ply .tfx)")
    info.add_argument("--json", action="store_true", help="print one JSON object")
    info.set_defaults(run=command_info)

    convert = commands.add_parser("convert", help="convert between hair file formats")
    convert.add_argument("input", help="hair file to read (.hair .data .bin .ply .tfx)")
    convert.add_argument("output", help="hair file to write (.hair .data)")
    convert.add_argument("--json", action="store_true", help="print one JSON object")
    convert.set_defaults(run=command_convert)

    generate = commands.add_parser("generate", help="generate strands from a hair mesh (.json)")
    generate.add_argument("hairmesh", help="hair mesh file (JSON, docs/hairmesh-format.md)")
    generate.add_argument("--count", type=int, default=10000, help="strands at full LoD (default 10000)")
    generate.add_argument("--vertices", type=int, default=17, help="vertices per strand, 2^e + 1 (default 17)")
    generate.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    generate.add_argument("--lod", type=float, default=1.0, help="level of detail in (0, 1] (default 1)")
    generate.add_argument("--subdivision", type=int, default=0, help="OpenSubdiv level 0-3 (default 0)")
    generate.add_argument("--radius", type=float, default=None, help="strand radius (default: the file's)")
    generate.add_argument("--out", default=None, help="hair file to write (.hair .data); omitted: generate only")
    generate.add_argument("--json", action="store_true", help="print one JSON object")
    generate.set_defaults(run=command_generate)

    lod = commands.add_parser("lod", help="build an LoD asset and export it to a folder")
    lod.add_argument("input", help="hair file to read (.hair .data .bin .ply .tfx)")
    lod.add_argument("--out", required=True, help="folder to write (replaced atomically)")
    lod.add_argument("--guides", type=int, default=256, help="k of the guide k-means (default 256)")
    lod.add_argument("--levels", type=int, default=6, help="levels including the strands (default 6)")
    lod.add_argument("--control-points", type=int, default=16, help="control points per hair (default 16)")
    lod.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    lod.add_argument("--width-px", type=float, default=2.0, help="screen width threshold in pixels (default 2)")
    lod.add_argument("--cameras", help="JSON list of {view, projection, viewport}: export only the levels they select")
    lod.add_argument("--json", action="store_true", help="print one JSON object")
    lod.set_defaults(run=command_lod)

    bench = commands.add_parser("bench", help="benchmark a component (timings and accuracy, no assertions)")
    bench.add_argument("component", choices=["lod"], help="component to benchmark")
    bench.add_argument("--strands", type=int, default=100_000, help="synthetic strands (default 100000)")
    bench.add_argument("--points", type=int, default=32, help="points per synthetic strand (default 32)")
    bench.add_argument("--guides", type=int, default=256, help="guides (default 256)")
    bench.add_argument("--levels", type=int, default=6, help="levels including the strands (default 6)")
    bench.add_argument("--control-points", type=int, default=16, help="control points (default 16)")
    bench.add_argument("--width-px", type=float, default=2.0, help="width threshold (default 2)")
    bench.add_argument("--frames", type=int, default=200, help="selection frames timed per camera (default 200)")
    bench.add_argument("--json", action="store_true", help="print one JSON object")
    bench.set_defaults(run=command_bench)
    return parser


def main(argv=None):
    try:
        args = build_parser().parse_args(argv)
        return args.run(args)
    except UsageError as error:
        print(f"hairlod: error: {error}", file=sys.stderr)
    except (ValueError, OSError) as error:
        print(f"hairlod: error: {error}", file=sys.stderr)
    return EXIT_BAD_INPUT
