"""Command line: python3 -m hairlod <command> ... [--json].

Contract (docs/ARCHITECTURE.md, "Command line" and "Errors"): --json prints one JSON object on stdout; bad input exits with code 2 and one
line on stderr naming the file or parameter and the problem, never a traceback; no partial output
file is left behind.
"""

import argparse
import os
import signal
import sys
import threading
import time
import warnings

from . import __version__, atomic_output, strict_json
from .lod import (DEFAULT_VERTEX_TOLERANCE_PX, DEFAULT_WIDTH_PX, LOD_DEFAULTS, MAX_CONTROL_POINTS, MAX_LEVELS, MIN_CONTROL_POINTS, MIN_LEVELS,
                  MIN_WIDTH_PX)

EXIT_BAD_INPUT = 2
INT32_MAX = 2**31 - 1
SEED_MAX = 2**64 - 1
FLOAT32_MAX = 3.4028234663852886e38  # numbers the C++ core holds as float


class UsageError(Exception):
    """A bad command line: reported as one line, exit code 2."""


class _Parser(argparse.ArgumentParser):
    def error(self, message):
        raise UsageError(message)


def _integer(lowest, highest=INT32_MAX):
    """argparse type: a decimal integer in [lowest, highest] (the bindings' C++ types hold it)."""
    def parse(text):
        try:
            value = int(text, 10)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected an integer, got {text[:40]!r}") from None
        if not lowest <= value <= highest:
            raise argparse.ArgumentTypeError(f"must be between {lowest} and {highest}, got {text[:40]}")
        return value
    return parse


def _width_px():
    """argparse type: a screen-width threshold in the range every tool accepts (lod.MIN_WIDTH_PX up)."""
    return _number(at_least=MIN_WIDTH_PX, at_most=FLOAT32_MAX)


def _vertex_tolerance():
    """argparse type: a vertex LoD tolerance in pixels (0 up)."""
    return _number(at_least=0.0, at_most=FLOAT32_MAX)


def _number(above=None, at_least=None, at_most=None):
    """argparse type: a finite number, > above / >= at_least / <= at_most where given."""
    def parse(text):
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected a number, got {text[:40]!r}") from None
        if value != value or value in (float("inf"), float("-inf")):
            raise argparse.ArgumentTypeError(f"must be a finite number, got {text[:40]}")
        if above is not None and not value > above:
            raise argparse.ArgumentTypeError(f"must be > {above}, got {text[:40]}")
        if at_least is not None and not value >= at_least:
            raise argparse.ArgumentTypeError(f"must be >= {at_least}, got {text[:40]}")
        if at_most is not None and not value <= at_most:
            raise argparse.ArgumentTypeError(f"must be <= {at_most}, got {text[:40]}")
        return value
    return parse


def _path(text):
    """argparse type: a non-empty path (an empty one names nothing a message could point at)."""
    if not text:
        raise argparse.ArgumentTypeError("expected a path, got an empty string")
    return text


def _print_json(value):
    print(strict_json.dumps(value))


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
        _print_json({"file": args.file, **summary, "read_seconds": seconds})
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
        _print_json(result)
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
    hairmesh.check_generate_budget(args.count, args.vertices)
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
        hairmesh.require_finite(strands)
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
        _print_json(result)
    else:
        target = f" -> {args.out}" if args.out else ""
        print(f"{args.hairmesh}{target}: {result['strands']} strands of {result['points_per_strand']} points "
              f"generated in {generate_seconds:.3f} s (+ {prepare_seconds:.3f} s subdivision, frames, root samples)")
    return 0


def command_lod(args):
    import numpy as np

    from . import lod

    inputs = [args.input, args.cameras, *(args.animation or ())]
    # Refused before the build, so a refusal costs nothing (lod.save checks again when it writes).
    atomic_output.check_folder_target(args.out, lod.FORMAT_KIND, args.force, inputs, lod.WHAT)
    cameras = lod.read_cameras(args.cameras) if args.cameras else None
    strands, read_seconds = _read_timed(args.input)
    start = time.perf_counter()
    asset = lod.build_lod(strands, guides=args.guides, levels=args.levels, control_points=args.control_points, seed=args.seed)
    build_seconds = time.perf_counter() - start
    finest = len(asset.levels)
    selected = list(range(finest + 1))
    if cameras:
        asset, selected = lod.keep_scene_levels(asset, cameras, args.width_px)
    options = {name: getattr(args, name) for name in ("levels", "control_points", "seed", "width_px")}
    options["guides"] = asset.guide_count
    animation = None
    if args.animation:
        # Each frame's guides, from its file (the same curves, moved): the asset's skinning turns
        # them into every strand and thick hair of that frame.
        poses = [lod.frame_guides(asset, _read_timed(path)[0], path) for path in args.animation]
        animation = (list(range(args.first_frame, args.first_frame + len(poses))), np.stack(poses))
    start = time.perf_counter()
    manifest = lod.save(asset, args.out, animation=animation, extra={
        "input": os.path.abspath(args.input),
        "options": options,
        "cameras": len(cameras) if cameras else 0,
        "selected_levels": selected,
        "strands_selected": finest in selected,
        "animation_files": [os.path.abspath(path) for path in args.animation or ()],
    }, force=args.force, inputs=inputs)
    write_seconds = time.perf_counter() - start
    result = {
        "input": args.input,
        "output": args.out,
        "strands": len(strands),
        "guides": asset.guide_count,
        "clusters": asset.cluster_count,
        "built_levels": finest + 1,
        "selected_levels": selected,
        "levels": lod.level_report(asset),
        "area_ratios": manifest["area_ratios"],
        "memory_ratio": asset.memory_bytes / lod.strand_bytes(strands),  # held in memory
        "stored_ratio": asset.stored_bytes / lod.strand_bytes(strands),  # in the folder's arrays / a pack
        "timings": asset.timings,
        "read_seconds": read_seconds,
        "build_seconds": build_seconds,
        "write_seconds": write_seconds,
        "animation_frames": len(args.animation or ()),
    }
    if args.json:
        _print_json(result)
    else:
        print(f"{args.input} -> {args.out}: {len(strands)} strands, {asset.cluster_count} clusters, "
              f"thick levels {[level['hairs'] for level in result['levels']]}, build {build_seconds:.2f} s")
    return 0


def command_render(args):
    from . import lod, render

    if not args.out.lower().endswith((".exr", ".png")):
        raise UsageError(f"--out {args.out}: must end in .exr or .png")
    if args.method.startswith("lod") and not args.lod:
        raise UsageError(f"--method {args.method} needs --lod DIR (an LoD asset from 'hairlod lod')")
    if args.frame is not None and not args.method.startswith("lod"):
        raise UsageError(f"--frame {args.frame}: only the lod methods skin to a frame (the strands are IN as it is)")
    if args.own_hair is not None and args.method != "lod-single":
        raise UsageError(f"--own-hair {args.own_hair}: applies to --method lod-single only")
    strands, read_seconds = _read_timed(args.input)
    asset = lod.load(args.lod) if args.lod else None
    guides = _animation_frame(args.lod, asset, args.frame) if args.frame is not None else None
    bar = None
    if sys.stderr.isatty() or args.progress:
        def bar(fraction):
            done = int(30 * fraction)
            print(f"\rrender [{'#' * done}{'.' * (30 - done)}] {100 * fraction:5.1f}%", end="" if fraction < 1 else "\n",
                  file=sys.stderr, flush=True)
    result = render.render(strands, method=args.method, view=args.view, width=args.width, spp=args.spp, asset=asset,
                           seed=args.seed, params=_read_params(args.params), progress=bar, guides=guides,
                           own_hair=args.own_hair, vertex_tolerance_px=args.vertex_tolerance_px)
    render.write_image(args.out, result["image"])
    summary = {key: result[key] for key in ("seconds", "setup_seconds", "rays", "rays_per_second", "segments",
                                            "strand_segments", "thick_segments", "camera")}
    summary.update(input=args.input, lod=args.lod, output=args.out, method=args.method, view=args.view, spp=args.spp,
                   width=args.width, read_seconds=read_seconds, frame=args.frame)
    if args.json:
        _print_json(summary)
    else:
        print(f"{args.input} -> {args.out}: {args.method}, {args.view} view, {summary['segments']} segments, "
              f"{result['seconds']:.2f} s, {result['rays_per_second'] / 1e6:.2f} M rays/s")
    return 0


def _animation_frame(folder, asset, frame):
    """The guides of `frame` in the guide animation stored in the LoD folder (lod --animation)."""
    import numpy as np

    from . import lod

    animation = lod.load_animation(folder, asset)
    if animation is None:
        raise UsageError(f"--frame {frame}: {folder} holds no guide animation (lod --animation, or Export Hair LoD "
                         "with Guide Animation)")
    frames, guides = animation
    if frame not in frames:
        raise UsageError(f"--frame {frame}: {folder} stores frames {int(frames[0])} to {int(frames[-1])}"
                         + ("" if len(frames) == frames[-1] - frames[0] + 1 else " (not every one)"))
    return guides[int(np.flatnonzero(frames == frame)[0])]


def _read_params(path):
    if path is None:
        return {}
    params = strict_json.load(path, "--params, BCSDF parameters")
    if not isinstance(params, dict):
        raise UsageError(f"{path}: expected a JSON object of HairParams fields")
    return params


def _principled_hair_from_blend(path, material):
    # Blender reads the node (addon/hairlod/blender/principled_hair.py) and prints one marked line.
    import shutil
    import subprocess

    if not os.path.isfile(path):
        raise UsageError(f"{path}: no such .blend file")
    blender = os.environ.get("HAIRLOD_BLENDER") or shutil.which("blender")
    if blender is None:
        raise UsageError("--from-blend: blender not found on PATH (or set HAIRLOD_BLENDER)")
    script = os.path.join(os.path.dirname(os.path.abspath(__file__)), "blender", "principled_hair.py")
    run = subprocess.run([blender, "-b", "--factory-startup", path, "--python", script, "--", "--material", material],
                         capture_output=True, text=True)
    for line in run.stdout.splitlines():
        if line.startswith("HAIRLOD_JSON "):
            return strict_json.loads(line[len("HAIRLOD_JSON "):], f"{path}: the material blender read")
        if line.startswith("HAIRLOD_ERROR "):
            raise UsageError(f"{path}: {line[len('HAIRLOD_ERROR '):]}")
    last = (run.stderr.strip().splitlines() or run.stdout.strip().splitlines() or ["no output"])[-1]
    raise UsageError(f"{path}: blender could not read the file ({last})")


def command_bake(args):
    from . import bcsdf, bcsdf_bake, hair_params

    if args.from_blend and args.params:
        raise UsageError("--params and --from-blend are exclusive")
    atomic_output.check_folder_target(args.out, bcsdf_bake.BAKE_FORMAT, args.force, [args.lod, args.params, args.from_blend],
                                      bcsdf_bake.BAKE_WHAT)
    if bool(args.from_blend) != bool(args.material):
        raise UsageError("--from-blend and --material go together")
    source = args.params or (f"{args.from_blend}:{args.material}" if args.from_blend else "params")
    try:
        if args.from_blend:
            node = _principled_hair_from_blend(args.from_blend, args.material)
            params = hair_params.from_principled_hair(**node)
        else:
            node = None
            params = hair_params.as_params(_read_params(args.params))
    except ValueError as error:
        raise UsageError(str(error) if source in str(error) else f"{source}: {error}")
    max_hair_count, densest = args.max_hair_count, None
    if args.lod:
        from . import lod

        try:
            asset = lod.load(args.lod)
        except ValueError as error:
            raise UsageError(str(error))
        crossed, densest = bcsdf.lod_hair_count_range(asset)
        if max_hair_count is None:
            max_hair_count = crossed
    if max_hair_count is None:
        max_hair_count = 64.0
    sets = [t for t in args.tables.split(",") if t]
    for t in sets:
        if t not in ("aggregated", "xu"):
            raise UsageError(f"--tables: unknown table set '{t}' (aggregated, xu)")
    start = time.perf_counter()
    manifest = bcsdf_bake.bake(params, args.out, theta_samples=args.theta_samples,
                          hair_count_samples=args.hair_count_samples, max_hair_count=max_hair_count,
                          table_samples=args.table_samples, tables=sets, force=args.force,
                          inputs=[args.lod, args.params, args.from_blend])
    seconds = time.perf_counter() - start
    tables = [{"name": t["name"], "file": t["file"], "resolution": t["resolution"], "channels": len(t["channels"]),
               "bytes": t["bytes"]} for t in manifest["tables"]]
    if args.json:
        _print_json({"params": args.params, "from_blend": args.from_blend, "material": args.material,
                     "principled_hair": node, "hair_params": manifest["params"], "lod": args.lod,
                     "densest_cluster_strands": densest, "max_hair_count": max_hair_count, "out": args.out,
                     "tables": tables, "bytes": sum(t["bytes"] for t in tables), "bake_seconds": seconds})
    else:
        for t in tables:
            print(f"{os.path.join(args.out, t['file'])}: {t['resolution'][0]} x {t['resolution'][1]}, "
                  f"{t['channels']} channels")
        print(f"baked {len(tables)} tables in {seconds:.3f} s")
    return 0


def _check_plot_path(path):
    """--plot: a .png in an existing folder (checked before a long benchmark runs)."""
    if path and not path.lower().endswith(".png"):
        raise UsageError(f"{path}: --plot writes a .png file")
    if path and not os.path.isdir(os.path.dirname(os.path.abspath(path))):
        raise UsageError(f"{path}: folder does not exist")


def _write_plot(path, draw):
    """Calls draw(file) on a temporary name and renames it to `path`: no partial plot is left."""
    with atomic_output.replacing_file(path) as staging:
        draw(staging)


def _bench_bcsdf(args):
    from . import bench

    _check_plot_path(args.plot)
    result = bench.bench_bcsdf(repeats=args.repeats)
    if args.plot:
        _write_plot(args.plot, lambda file: bench.plot_bcsdf(result, file))
        result["plot"] = args.plot
    if args.json:
        _print_json({"component": args.component, **result})
    else:
        print(f"{'model':<11} {'tier':<26} {'ns/eval':>9} {'max rel':>9} {'mean rel':>9} {'|E-1|':>8} {'bytes':>8}")
        for r in result["rows"]:
            def cell(value, spec):
                return format(value, spec) if value is not None else format("-", spec.split(".")[0].rstrip("de"))
            print(f"{r['model']:<11} {r['tier']:<26} {r['ns_per_eval']:>9.0f} {cell(r['max_rel_error'], '>9.2e')} "
                  f"{cell(r['mean_rel_error'], '>9.2e')} {cell(r['energy_error'], '>8.3f')} {cell(r['bytes'], '>8')}")
    return 0


def _bench_lod(args):
    from . import bench

    result = bench.bench_lod(strands=args.strands, points=args.points, guides=args.guides, levels=args.levels,
                             control_points=args.control_points, width_px=args.width_px, frames=args.frames)
    print(strict_json.dumps(result, indent=None if args.json else 1))
    return 0


def _bench_skinning(args):
    from . import bench

    result = bench.bench_skinning(strands=args.strands, points=args.points, guides=args.guides, levels=args.levels,
                                  control_points=args.control_points, frames=args.frames)
    print(strict_json.dumps(result, indent=None if args.json else 1))
    return 0


def _bench_generate(args):
    from . import bench

    segments = args.vertices - 1
    if segments < 1 or segments & (segments - 1):
        raise UsageError(f"--vertices must be 2^e + 1 (2, 3, 5, 9, 17, 33, ...), got {args.vertices}")
    _check_plot_path(args.plot)
    result = bench.bench_generate(strands=args.strands, vertices=args.vertices, repeats=args.repeats)
    if args.plot:
        _write_plot(args.plot, lambda file: bench.plot_generate(result, file))
        result["plot"] = args.plot
    print(strict_json.dumps({"component": args.component, **result}, indent=None if args.json else 1))
    return 0


def _check_images_folder(path, views):
    """--images DIR: a folder, or a path where one can be made, whose <view>.png are not folders
    (checked before a long benchmark runs)."""
    existing = os.path.abspath(path)
    while not os.path.lexists(existing):
        existing = os.path.dirname(existing)
    if not os.path.isdir(existing):
        raise UsageError(f"--images {path}: {existing} exists and is not a folder")
    for view in views:
        image = os.path.join(path, f"{view}.png")
        if os.path.isdir(image):
            raise UsageError(f"--images {path}: {image} is a folder")


def _bench_quality(args):
    from . import lod, quality, render

    if not args.input:
        raise UsageError("bench quality needs an input hair file: bench quality IN")
    _check_plot_path(args.plot)
    if args.images:
        _check_images_folder(args.images, render.VIEWS)
    try:
        eps_w = [float(v) for v in args.eps_w.split(",") if v]
    except ValueError:
        raise UsageError(f"--eps-w {args.eps_w}: expected comma-separated pixel widths")
    strands, read_seconds = _read_timed(args.input)
    asset = lod.load(args.lod) if args.lod else None
    say = None if args.json else (lambda message: print(f"bench quality: {message}", file=sys.stderr, flush=True))
    start = time.perf_counter()
    result = quality.bench_quality(strands, asset=asset, **_given(spp=args.spp), width=args.width,
                                   reference_spp=args.reference_spp, equal_time_spp=args.equal_time_spp, eps_w=eps_w,
                                   width_px=args.width_px, guides=args.guides,
                                   params=_read_params(args.params), keep_images=bool(args.images), progress=say,
                                   max_bounces=args.max_bounces, own_hair=args.own_hair,
                                   vertex_tolerance_px=args.vertex_tolerance_px, max_view_spp_scale=args.max_view_spp_scale)
    result.update(component="quality", input=args.input, lod=args.lod, read_seconds=read_seconds,
                  bench_seconds=time.perf_counter() - start)
    if args.images:
        result["images"] = quality.write_view_images(result, result.pop("images"), args.images)
    if args.plot:
        _write_plot(args.plot, lambda file: quality.plot_quality(result, file, titles=[os.path.basename(args.input)]))
        result["plot"] = args.plot
    print(strict_json.dumps(result) if args.json else quality.format_tables(result))
    return 0


def _given(**options):
    """The options given on the command line (not None), so that the library's defaults apply to the rest."""
    return {name: value for name, value in options.items() if value is not None}


def _bench_thick_hairs(args):
    from . import lod, thick_hair_check

    if not args.input:
        raise UsageError("bench thick-hairs needs an input hair file: bench thick-hairs IN")
    strands, read_seconds = _read_timed(args.input)
    asset = lod.load(args.lod) if args.lod else None
    say = None if args.json else (lambda message: print(f"bench thick-hairs: {message}", file=sys.stderr, flush=True))
    result = thick_hair_check.bench_thick_hairs(strands, asset=asset, guides=args.guides, params=_read_params(args.params),
                                                progress=say, **_given(spp=args.spp, hairs=args.hairs))
    result.update(component="thick-hairs", input=args.input, lod=args.lod, read_seconds=read_seconds)
    print(strict_json.dumps(result) if args.json else thick_hair_check.format_tables(result))
    return 0


def _bench_animation(args):
    from . import lod, temporal

    if not args.animation or len(args.animation) < 2:
        raise UsageError("bench animation needs the hair at 2 or more frames: --animation FRAME_FILE FRAME_FILE ...")
    frames = [_read_timed(path)[0] for path in args.animation]
    asset = lod.load(args.lod) if args.lod else None
    say = None if args.json else (lambda message: print(f"bench animation: {message}", file=sys.stderr, flush=True))
    result = temporal.bench_animation(frames, asset=asset, view=args.view, width=args.width, **_given(spp=args.spp),
                                      width_px=args.width_px, guides=args.guides, params=_read_params(args.params),
                                      progress=say)
    result.update(component="animation", files=args.animation, lod=args.lod)
    if args.json:
        _print_json(result)
    else:
        def db(value, width, sign=""):  # None: identical images (infinite PSNR)
            return format("inf" if value is None else format(value, f"{sign}.2f"), f">{width}")

        print(f"{'frame':>5} {'strand seg':>10} {'lod seg':>8} {'lod bPSNR':>9} {'strands adj':>11} {'lod adj':>8}")
        for row in result["rows"]:
            adjacent = (f"{db(row['strands_adjacent_psnr'], 11)} {db(row['lod_adjacent_psnr'], 8)}"
                        if "lod_adjacent_psnr" in row else f"{'-':>11} {'-':>8}")
            print(f"{row['frame']:>5} {row['strand_segments']:>10} {row['lod_segments']:>8} "
                  f"{db(row['lod_blurred_psnr'], 9)} {adjacent}")
        print(f"adjacent-frame blurred PSNR: strands {db(result['mean_strands_adjacent_psnr'], 0)} dB, LoD "
              f"{db(result['mean_lod_adjacent_psnr'], 0)} dB (gap {db(result['adjacent_psnr_gap_db'], 0, '+')} dB); "
              f"{result['mean_segment_reduction']:.1f}x fewer segments")
    return 0


def command_bench(args):
    return {"bcsdf": _bench_bcsdf, "lod": _bench_lod, "skinning": _bench_skinning, "generate": _bench_generate,
            "quality": _bench_quality, "animation": _bench_animation, "thick-hairs": _bench_thick_hairs}[args.component](args)


def build_parser():
    from . import quality, thick_hair_check
    from .render import BLUR_BOX, MAX_BOUNCES, OWN_HAIR, VIEWS

    parser = _Parser(prog="python3 -m hairlod", description="Strand hair to real-time LoD assets.")
    parser.add_argument("--version", action="version", version=f"hairlod {__version__}")
    commands = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    commands.required = True

    info = commands.add_parser("info", help="summarise a hair file")
    info.add_argument("file", type=_path, help="hair file (.hair .data .bin .ply .tfx)")
    info.add_argument("--json", action="store_true", help="print one JSON object")
    info.set_defaults(run=command_info)

    convert = commands.add_parser("convert", help="convert between hair file formats")
    convert.add_argument("input", type=_path, help="hair file to read (.hair .data .bin .ply .tfx)")
    convert.add_argument("output", type=_path, help="hair file to write (.hair .data)")
    convert.add_argument("--json", action="store_true", help="print one JSON object")
    convert.set_defaults(run=command_convert)

    generate = commands.add_parser("generate", help="generate strands from a hair mesh (.json)")
    generate.add_argument("hairmesh", type=_path, help="hair mesh file (JSON, docs/hairmesh-format.md)")
    generate.add_argument("--count", type=_integer(1), default=10000, help="strands at full LoD (default 10000)")
    generate.add_argument("--vertices", type=_integer(2), default=17, help="vertices per strand, 2^e + 1 (default 17)")
    generate.add_argument("--seed", type=_integer(0, SEED_MAX), default=0, help="random seed (default 0)")
    generate.add_argument("--lod", type=_number(above=0, at_most=1), default=1.0,
                          help="level of detail in (0, 1] (default 1)")
    generate.add_argument("--subdivision", type=_integer(0, 3), default=0, help="OpenSubdiv level 0-3 (default 0)")
    generate.add_argument("--radius", type=_number(at_least=0, at_most=FLOAT32_MAX), default=None,
                          help="strand radius (default: the file's)")
    generate.add_argument("--out", type=_path, default=None,
                          help="hair file to write (.hair .data); omitted: generate only")
    generate.add_argument("--json", action="store_true", help="print one JSON object")
    generate.set_defaults(run=command_generate)

    lod = commands.add_parser("lod", help="build an LoD asset and export it to a folder")
    lod.add_argument("input", type=_path, help="hair file to read (.hair .data .bin .ply .tfx)")
    lod.add_argument("--out", type=_path, required=True, help="folder to write; an existing one is replaced (atomically) only "
                     "when it is an LoD folder hairlod wrote")
    lod.add_argument("--force", action="store_true", help="replace --out even when it is not an LoD folder hairlod "
                     "wrote (never the current, home or root folder, nor one holding the input)")
    lod.add_argument("--guides", type=_integer(1), default=None, help="k of the guide k-means (default: one per 128 "
                     "strands, 16 to 256)")
    lod.add_argument("--levels", type=_integer(MIN_LEVELS, MAX_LEVELS), default=LOD_DEFAULTS["levels"],
                     help=f"levels including the strands, {MIN_LEVELS} to {MAX_LEVELS} (default {LOD_DEFAULTS['levels']})")
    lod.add_argument("--control-points", type=_integer(MIN_CONTROL_POINTS, MAX_CONTROL_POINTS),
                     default=LOD_DEFAULTS["control_points"],
                     help=f"control points per hair (default {LOD_DEFAULTS['control_points']})")
    lod.add_argument("--seed", type=_integer(0, SEED_MAX), default=LOD_DEFAULTS["seed"],
                     help=f"random seed (default {LOD_DEFAULTS['seed']})")
    lod.add_argument("--width-px", type=_width_px(), default=DEFAULT_WIDTH_PX,
                     help=f"screen width threshold in pixels (default {DEFAULT_WIDTH_PX:g})")
    lod.add_argument("--cameras", type=_path, help="JSON list of {view, projection, viewport}: export only the levels they select")
    lod.add_argument("--animation", type=_path, nargs="+", metavar="FRAME_FILE",
                     help="hair files of the same hair at successive frames (same curves, moved): their guides are "
                     "stored in the LoD folder (guide_animation.npy), which the asset's skinning turns into each frame")
    lod.add_argument("--first-frame", type=_integer(-2**31, 2**31 - 1), default=1,
                     help="frame number of the first --animation file (default 1)")
    lod.add_argument("--json", action="store_true", help="print one JSON object")
    lod.set_defaults(run=command_lod)

    bake = commands.add_parser("bake", help="bake the aggregated BCSDF's lookup tables (OpenEXR + manifest.json)")
    bake.add_argument("--params", type=_path, metavar="FILE.json", help="HairParams fields as a JSON object (default: defaults)")
    bake.add_argument("--from-blend", type=_path, metavar="FILE.blend", help="read the parameters from a material's Principled "
                      "Hair BSDF (runs blender -b)")
    bake.add_argument("--material", metavar="NAME", help="the material of --from-blend")
    bake.add_argument("--lod", type=_path, metavar="DIR", help="LoD folder (python3 -m hairlod lod): the n range covers the "
                      "most hairs a ray crosses in its thick hairs")
    bake.add_argument("--out", type=_path, required=True, metavar="DIR", help="output folder; an existing one is replaced "
                      "(atomically) only when it holds tables hairlod baked")
    bake.add_argument("--force", action="store_true", help="replace --out even when it does not hold tables hairlod "
                      "baked (never the current, home or root folder, nor the --lod folder)")
    bake.add_argument("--theta-samples", type=_integer(2), default=64, help="theta_d resolution (default 64)")
    bake.add_argument("--hair-count-samples", type=_integer(2), default=64, help="hair count n resolution (default 64)")
    bake.add_argument("--max-hair-count", type=_number(at_least=1), default=None,
                      help="largest hair count n the tables cover (default: from --lod, else 64)")
    bake.add_argument("--table-samples", type=_integer(3), default=65,
                      help="theta_d nodes of the per-hair table the aggregated tables interpolate (default 65, "
                           "bcsdf_bake.DEFAULT_TABLE_SAMPLES)")
    bake.add_argument("--tables", default="aggregated",
                      help="comma-separated table sets: aggregated, xu (Xu et al. 2011 C_k, H_k) (default aggregated)")
    bake.add_argument("--json", action="store_true", help="print one JSON object")
    bake.set_defaults(run=command_bake)

    rend = commands.add_parser("render", help="render hair with the Embree reference renderer (EXR or PNG)")
    rend.add_argument("input", type=_path, help="hair file to read (.hair .data .bin .ply .tfx)")
    rend.add_argument("--lod", type=_path, metavar="DIR", help="LoD asset folder (needed by the lod methods)")
    rend.add_argument("--frame", type=_integer(-2**31, 2**31 - 1), default=None,
                      help="lod methods: skin the asset to the guides of this frame of its guide animation (IN is the "
                      "hair at that frame, for the view and the pt reference)")
    rend.add_argument("--method", choices=["pt", "ds", "lod", "lod-single", "lod-no-s"], default="pt",
                      help="pt (reference), ds (dual scattering), lod (aggregated BCSDF), lod-single, lod-no-s")
    rend.add_argument("--view", choices=["near", "mid", "far"], default="mid",
                      help="hair covering about 60%%, 20%% or 2%% of the image (default mid)")
    rend.add_argument("--out", type=_path, required=True, help="image to write (.exr linear or .png sRGB)")
    rend.add_argument("--spp", type=_integer(1), default=16, help="samples per pixel (default 16)")
    rend.add_argument("--width", type=_integer(1), default=256, help="image width and height in pixels (default 256)")
    rend.add_argument("--seed", type=_integer(0, SEED_MAX), default=0, help="random seed (default 0)")
    rend.add_argument("--params", type=_path, help="HairParams JSON (default: the BCSDF defaults)")
    rend.add_argument("--own-hair", choices=OWN_HAIR, default=None,
                      help="lod-single: paths leaving a strand inside a thick hair skip its other strands, keeping the "
                      "share dual scattering passes forwards (attenuate, the default), or meet them and scatter there "
                      "(scatter)")
    rend.add_argument("--vertex-tolerance-px", type=_vertex_tolerance(), default=DEFAULT_VERTEX_TOLERANCE_PX,
                      help="lod methods: each drawn strand keeps the control points its shape needs within this many "
                      "pixels (vertex LoD; thick hairs keep every section; 0 keeps every point; default "
                      f"{DEFAULT_VERTEX_TOLERANCE_PX:g})")
    rend.add_argument("--progress", action="store_true", help="progress bar on stderr even when not a terminal")
    rend.add_argument("--json", action="store_true", help="print one JSON object")
    rend.set_defaults(run=command_render)

    bench = commands.add_parser("bench", help="speed against error of a component (no assertions)")
    bench.add_argument("component", choices=["bcsdf", "lod", "skinning", "generate", "quality", "animation", "thick-hairs"],
                       help="what to benchmark")
    bench.add_argument("input", type=_path, nargs="?", help="quality, thick-hairs: hair file to render (.hair .data .bin "
                       ".ply .tfx)")
    bench.add_argument("--json", action="store_true", help="print one JSON object")
    bench.add_argument("--repeats", type=_integer(1), default=5, help="bcsdf: timing repeats (median; default 5)")
    bench.add_argument("--plot", type=_path, metavar="FILE.png", help="bcsdf, generate, quality: also write a plot")
    bench.add_argument("--strands", type=_integer(1), default=100_000, help="lod, skinning, generate: strands (default 100000)")
    bench.add_argument("--vertices", type=_integer(2), default=33, help="generate: vertices per strand (default 33)")
    bench.add_argument("--points", type=_integer(2), default=32, help="lod, skinning: points per synthetic strand (default 32)")
    bench.add_argument("--guides", type=_integer(1), default=None, help="lod, skinning, quality, animation, thick-hairs: guides (default: one per 128 "
                       "strands, 16 to 256)")
    bench.add_argument("--levels", type=_integer(MIN_LEVELS, MAX_LEVELS), default=LOD_DEFAULTS["levels"],
                       help=f"lod, skinning: levels including the strands (default {LOD_DEFAULTS['levels']})")
    bench.add_argument("--control-points", type=_integer(MIN_CONTROL_POINTS, MAX_CONTROL_POINTS),
                       default=LOD_DEFAULTS["control_points"],
                       help=f"lod, skinning: control points (default {LOD_DEFAULTS['control_points']})")
    bench.add_argument("--width-px", type=_width_px(), default=DEFAULT_WIDTH_PX,
                       help=f"lod, quality, animation: LoD width threshold eps_w in pixels (default {DEFAULT_WIDTH_PX:g})")
    bench.add_argument("--frames", type=_integer(1), default=200, help="lod: selection frames timed per camera; "
                       "skinning: animation frames (default 200)")
    bench.add_argument("--lod", type=_path, metavar="DIR", help="quality, animation, thick-hairs: LoD asset folder (default: built "
                       "with --guides; animation: of the first frame)")
    bench.add_argument("--spp", type=_integer(1), default=None, help="quality, animation: samples per pixel of the methods "
                       f"(default 256); thick-hairs: of the renders of single hairs (default {thick_hair_check.SPP})")
    bench.add_argument("--hairs", type=_integer(1), default=None,
                       help=f"thick-hairs: hairs per level rendered against their strands (default {thick_hair_check.RENDERED_HAIRS})")
    bench.add_argument("--reference-spp", type=_integer(1), default=1024,
                       help="quality: spp of the pt reference (default 1024)")
    bench.add_argument("--max-view-spp-scale", type=_integer(1), default=quality.MAX_VIEW_SPP_SCALE,
                       help="quality: the most a view whose hair covers fewer pixels raises --spp and --reference-spp, "
                       f"a power of two (1: every view at the spp given; default {quality.MAX_VIEW_SPP_SCALE})")
    bench.add_argument("--equal-time-spp", type=_integer(1), default=16,
                       help="quality: spp of the methods in the equal-time table (default 16)")
    bench.add_argument("--width", type=_integer(BLUR_BOX), default=128,
                       help=f"quality, animation: image width and height, at least {BLUR_BOX} (default 128)")
    bench.add_argument("--max-bounces", type=_integer(0), default=MAX_BOUNCES,
                       help=f"quality: scatterings after the camera ray's hit at most, in every render, the reference's "
                       f"too; 0: direct light only (default {MAX_BOUNCES})")
    bench.add_argument("--own-hair", choices=OWN_HAIR, default=None,
                       help="quality: how the lod-single rows treat paths inside their own thick hair (see render "
                       "--own-hair; default attenuate)")
    bench.add_argument("--vertex-tolerance-px", type=_vertex_tolerance(), default=DEFAULT_VERTEX_TOLERANCE_PX,
                       help="quality: the lod methods' vertex LoD, pixels a left-out control point of a strand may lie "
                       f"off the drawn one (0 keeps every point; default {DEFAULT_VERTEX_TOLERANCE_PX:g})")
    bench.add_argument("--images", type=_path, metavar="DIR", help="quality: write DIR/<view>.png, reference | ds | lod | "
                       "lod-single | lod - reference (other files in DIR are left alone)")
    bench.add_argument("--eps-w", default="0.5,1,2,4,8", help="quality: eps_w sweep in pixels at the mid view "
                       "(default 0.5,1,2,4,8)")
    bench.add_argument("--params", type=_path, help="quality, animation, thick-hairs: HairParams JSON (default: the BCSDF "
                       "defaults)")
    bench.add_argument("--animation", type=_path, nargs="+", metavar="FRAME_FILE",
                       help="animation: the hair at successive frames (same curves, moved)")
    bench.add_argument("--view", choices=list(VIEWS), default="mid", help="animation: camera distance (default mid)")
    bench.set_defaults(run=command_bench)
    return parser


def _subject(args):
    """The user's file or folder a failure is about, for errors that do not name one themselves."""
    for name in ("input", "file", "hairmesh", "lod", "params", "out"):
        value = getattr(args, name, None)
        if value:
            return f"{args.command} {value}"
    return args.command


def _one_line(message):
    return " ".join(str(message).split()) or "failed"


def _names_a_path(message, args):
    paths = [getattr(args, name, None) for name in ("input", "file", "hairmesh", "lod", "params", "cameras",
                                                    "from_blend", "out", "output", "plot", "images")]
    return any(isinstance(path, str) and path and (path in message or os.path.abspath(path) in message)
               for path in paths)


def _error_line(error, args):
    """The one line a failure prints: the message of a bad input, prefixed with the command and its
    input when it does not name one of the user's files itself; otherwise what failed and on which."""
    subject = _subject(args) if args is not None else "hairlod"
    if isinstance(error, UsageError):
        return _one_line(error)
    if isinstance(error, (ValueError, OSError)):
        message = _one_line(error)
        return message if args is None or _names_a_path(message, args) else f"{subject}: {message}"
    if isinstance(error, MemoryError):
        return f"{subject}: out of memory (reduce the input or the sizes asked for)"
    if isinstance(error, RecursionError):
        return f"{subject}: input nested too deeply"
    if isinstance(error, RuntimeWarning):
        return f"{subject}: numeric overflow or invalid value ({_one_line(error)})"
    return f"{subject}: {type(error).__name__}: {_one_line(error)}"


class _Interrupted(BaseException):
    def __init__(self, signal_number):
        super().__init__(signal_number)
        self.signal_number = signal_number


def _run_interruptibly(args, program):
    """Runs the command in a worker thread so that SIGINT and SIGTERM are handled at once, even during
    a long C++ call: the process's temporaries are removed and it exits 128 + the signal number.
    In-process callers get their handlers back; the program (`program`) instead ignores the two
    signals once the command is done: with the default action back, a signal in the moment between
    the finished command and the exit would kill it (-15) after its output was complete."""
    if threading.current_thread() is not threading.main_thread():
        return args.run(args)
    outcome = {}

    def work():
        try:
            outcome["code"] = args.run(args)
        except BaseException as error:  # handed to the main thread, which reports it
            outcome["error"] = error

    received = []

    def handle(signal_number, _frame):
        received.append(signal_number)

    previous = {number: signal.signal(number, handle) for number in (signal.SIGINT, signal.SIGTERM)}
    try:
        worker = threading.Thread(target=work, name="hairlod-command", daemon=True)
        worker.start()
        while worker.is_alive() and not received:
            worker.join(0.05)
        if received:
            raise _Interrupted(received[0])
    finally:
        for number, handler in previous.items():
            signal.signal(number, signal.SIG_IGN if program and not received else handler)
    if "error" in outcome:
        raise outcome["error"]
    return outcome["code"]


def main(argv=None, program=False):
    """The command line; `program` when it is the process (python3 -m hairlod), see _run_interruptibly."""
    args = None
    with warnings.catch_warnings():
        # A numeric warning means a result is no longer finite: report it as the failure it is.
        # Other warnings (deprecations in libraries) are not the user's concern: stderr stays one line.
        warnings.simplefilter("ignore")
        warnings.simplefilter("error", RuntimeWarning)
        try:
            args = build_parser().parse_args(argv)
            return _run_interruptibly(args, program)
        except _Interrupted as interrupted:
            written = atomic_output.stop_writing()
            name = signal.Signals(interrupted.signal_number).name
            done = f"; {', '.join(written)} complete" if written else ""
            print(f"hairlod: interrupted by {name}; unfinished output removed{done}", file=sys.stderr, flush=True)
            sys.stdout.flush()
            # The worker may still be inside C++: end the process without waiting for it.
            os._exit(128 + interrupted.signal_number)
        except BrokenPipeError:
            # The reader of stdout went away (`| head`): not a failure of the command, nothing to say.
            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
            return 128 + signal.SIGPIPE
        except KeyboardInterrupt:
            atomic_output.remove_own_temporaries()
            print("hairlod: interrupted; unfinished output removed", file=sys.stderr)
            return 128 + signal.SIGINT
        except Exception as error:  # the error contract: one line, exit 2, whatever failed
            print(f"hairlod: error: {_error_line(error, args)}", file=sys.stderr)
    return EXIT_BAD_INPUT
