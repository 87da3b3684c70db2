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


def _read_params(path):
    if path is None:
        return {}
    try:
        with open(path) as f:
            params = json.load(f)
    except json.JSONDecodeError as error:
        raise UsageError(f"{path}: not valid JSON ({error.msg} at line {error.lineno})")
    if not isinstance(params, dict):
        raise UsageError(f"{path}: expected a JSON object of HairParams fields")
    return params


def command_bake(args):
    from . import bcsdf

    params = _read_params(args.params)
    try:
        params = bcsdf.as_params(params)
    except ValueError as error:
        raise UsageError(f"{args.params or 'params'}: {error}")
    start = time.perf_counter()
    manifest = bcsdf.bake(params, args.out, theta_samples=args.theta_samples,
                          hair_count_samples=args.hair_count_samples, max_hair_count=args.max_hair_count)
    seconds = time.perf_counter() - start
    tables = [{"name": t["name"], "file": t["file"], "resolution": t["resolution"], "channels": len(t["channels"]),
               "bytes": t["bytes"]} for t in manifest["tables"]]
    if args.json:
        print(json.dumps({"params": args.params, "out": args.out, "tables": tables,
                          "bytes": sum(t["bytes"] for t in tables), "bake_seconds": seconds}))
    else:
        for t in tables:
            print(f"{os.path.join(args.out, t['file'])}: {t['resolution'][0]} x {t['resolution'][1]}, "
                  f"{t['channels']} channels")
        print(f"baked {len(tables)} tables in {seconds:.3f} s")
    return 0


def command_bench(args):
    from . import bench

    if args.plot and not args.plot.lower().endswith(".png"):
        raise UsageError(f"{args.plot}: --plot writes a .png file")
    if args.plot and not os.path.isdir(os.path.dirname(os.path.abspath(args.plot))):
        raise UsageError(f"{args.plot}: folder does not exist")
    if args.repeats < 1:
        raise UsageError(f"--repeats must be >= 1, got {args.repeats}")
    result = bench.bench_bcsdf(repeats=args.repeats)
    if args.plot:
        staging = args.plot + ".tmp.png"
        try:
            bench.plot_bcsdf(result, staging)
            os.replace(staging, args.plot)
        finally:
            if os.path.exists(staging):
                os.remove(staging)
        result["plot"] = args.plot
    if args.json:
        print(json.dumps({"component": args.component, **result}))
    else:
        print(f"{'model':<11} {'tier':<26} {'ns/eval':>9} {'max rel':>9} {'mean rel':>9} {'|E-1|':>8} {'bytes':>8}")
        for r in result["rows"]:
            def cell(value, spec):
                return format(value, spec) if value is not None else format("-", spec.split(".")[0].rstrip("de"))
            print(f"{r['model']:<11} {r['tier']:<26} {r['ns_per_eval']:>9.0f} {cell(r['max_rel_error'], '>9.2e')} "
                  f"{cell(r['mean_rel_error'], '>9.2e')} {cell(r['energy_error'], '>8.3f')} {cell(r['bytes'], '>8')}")
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

    bake = commands.add_parser("bake", help="bake the aggregated BCSDF's lookup tables (OpenEXR + manifest.json)")
    bake.add_argument("--params", metavar="FILE.json", help="HairParams fields as a JSON object (default: defaults)")
    bake.add_argument("--out", required=True, metavar="DIR", help="output folder (replaced atomically)")
    bake.add_argument("--theta-samples", type=int, default=64, help="theta_d resolution (default 64)")
    bake.add_argument("--hair-count-samples", type=int, default=64, help="hair count n resolution (default 64)")
    bake.add_argument("--max-hair-count", type=float, default=64.0,
                      help="largest hair count n the tables cover (default 64; the densest cluster in use)")
    bake.add_argument("--json", action="store_true", help="print one JSON object")
    bake.set_defaults(run=command_bake)

    bench = commands.add_parser("bench", help="speed against error of a component (no assertions)")
    bench.add_argument("component", choices=["bcsdf"], help="what to benchmark")
    bench.add_argument("--repeats", type=int, default=5, help="timing repeats (median; default 5)")
    bench.add_argument("--plot", metavar="FILE.png", help="also plot ns per evaluation against error")
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
