"""Benchmarks: speed against error of the BCSDF tiers and of the LoD build and selection (the README's
"Speed against error (measured)" holds the latest numbers).

bench_bcsdf() measures, for each model and tier, nanoseconds per evaluation (median of repeats,
batched through the C++ core), relative error against a reference over a dense grid that includes
grazing angles and phi -> 0, the white-furnace energy of a lossless fibre, and for baked lookup tables
their bytes, lookup time and error against direct quadrature. No assertions: a benchmark, not a test.

Relative error: |value - reference| / max(|reference|, 1e-2 * max |reference| over the grid), per
channel, so that near-zero references do not dominate.
"""

import time

import numpy as np

from . import _core, bcsdf, bcsdf_bake, hair_params, memory_budget
from .thick_hair_check import axes_coordinates, strands_through_sections

def median_seconds(function, repeats=3):
    """Median wall time of `repeats` calls of `function()`, in seconds."""
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return float(np.median(times))


BROWN = {"sigma_a": [0.2, 0.5, 1.2]}
LOSSLESS = {"sigma_a": 0.0}


def _grid(seed):
    thetas = np.array([-0.5 * np.pi + 1e-3, -1.2, -0.6, 0.0, 0.6, 1.2, 0.5 * np.pi - 1e-3])
    phis = np.concatenate([np.linspace(-np.pi, np.pi, 24, endpoint=False) + np.pi / 24, [1e-9, np.pi]])
    ti, to, ph = (a.ravel() for a in np.meshgrid(thetas, thetas, phis, indexing="ij"))
    rng = np.random.default_rng(seed)
    ti = np.concatenate([ti, np.arcsin(rng.uniform(-1, 1, 2000))])
    to = np.concatenate([to, np.arcsin(rng.uniform(-1, 1, 2000))])
    ph = np.concatenate([ph, rng.uniform(-np.pi, np.pi, 2000)])

    def direction(theta, phi):
        return np.stack([np.sin(theta), np.cos(theta) * np.cos(phi), np.cos(theta) * np.sin(phi)], axis=1)

    return direction(ti, np.zeros_like(ti)).astype(np.float32), direction(to, ph).astype(np.float32)


def _relative_error(value, reference):
    value = np.asarray(value, dtype=np.float64)
    reference = np.asarray(reference, dtype=np.float64)
    floor = 1e-2 * np.abs(reference).max(axis=0, keepdims=True)
    error = np.abs(value - reference) / np.maximum(np.abs(reference), np.maximum(floor, 1e-300))
    return float(error.max()), float(error.mean())


def _ns_per_item(function, items, repeats):
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return float(np.median(times)) / items * 1e9


def _energy(model, **inputs):
    # The lossless fibre's white furnace at a few inclinations, grazing included (max |E - 1| and max E),
    # with the model's default inputs.
    values = [bcsdf.white_furnace(model, LOSSLESS, wo=(np.sin(t), np.cos(t), 0.0), tolerance=1e-3, **inputs)[0]
              for t in (0.0, 1.0, 1.5)]
    return float(max(abs(v - 1.0) for v in values)), float(max(values))


def _chiang_brute_force(wi, wo, nodes=64):
    # Far field = 1/2 the integral over h of the near field; Gauss-Legendre in gamma = asin(h).
    x, w = np.polynomial.legendre.leggauss(nodes)
    gamma = 0.5 * np.pi * x
    total = np.zeros((len(wi), 3))
    for g, weight in zip(gamma, w):
        h = np.full(len(wi), np.sin(g), dtype=np.float32)
        total += (0.5 * 0.5 * np.pi * weight * np.cos(g)) * bcsdf.evaluate("chiang", BROWN, wi, wo, h=h)
    return total


def _huang_rows(wi, wo, run, row):
    # Huang et al. 2022's microfacet fibre (Blender 4.x's default): its deterministic residual quadrature
    # against one with 8x the visible-normal samples, then the tiers every other model is built on for a
    # Huang material, the Chiang fibre standing in for it (exact, real-time, and the R/TT/D fibre of the
    # dual-scattering and aggregated tables), against the Huang fibre itself.
    huang = {"fibre": "huang", "huang_sigma_a": BROWN["sigma_a"]}
    reference = bcsdf.evaluate("huang", huang, wi, wo, residual_samples=64)
    values, ns = run("huang", huang)
    row("huang", "exact (8 normals per node)", values, reference, "64 visible normals per node", ns,
        _energy("huang"))
    stand_in = hair_params.chiang_stand_in(huang)[0]
    for model, tier, inputs in (("chiang", "chiang stand-in", {}), ("fiber_rtd", "stand-in r/tt/d fibre (luts)", {}),
                                ("realtime", "stand-in real-time (tafuri)", {"tt": "tafuri"})):
        values, ns = run(model, stand_in, **inputs)
        row("huang", tier, values, reference, "huang exact", ns, _energy(model, **inputs))


def _lut_rows(resolutions, table_samples, repeats):
    # LUT error against resolution: the baked texture's (theta_samples = n samples = resolution) and the
    # per-hair table's it is interpolated from (table_samples), whose linear interpolation is the floor.
    theta = np.linspace(-1.55, 1.55, 257)
    direct = bcsdf.dual_scattering(BROWN, theta, model="fiber_rtd", tolerance=1e-6)
    reference = np.concatenate([direct["a_f"], direct["a_b"]], axis=1)
    rows = []
    default_table = bcsdf_bake.DEFAULT_TABLE_SAMPLES
    for resolution, per_hair in ([(r, default_table) for r in resolutions] +
                                 [(max(resolutions), t) for t in table_samples if t != default_table]):
        tables = {t["name"]: t for t in _core.bcsdf_bake(hair_params.as_params(BROWN), theta_samples=resolution,
                                                          hair_count_samples=resolution, max_hair_count=64.0,
                                                          table_samples=per_hair)}
        table = tables["dual_scattering"]
        axes = [dict(a, range=list(a["range"])) for a in table["axes"]]
        looked_up = bcsdf_bake.lut_lookup(table["values"], axes, theta[:, None])[:, 0:6]
        max_error, mean_error = _relative_error(looked_up, reference)
        ns = _ns_per_item(lambda: bcsdf_bake.lut_lookup(table["values"], axes, theta[:, None]), len(theta), repeats)
        rows.append({"model": "aggregated", "tier": f"lut {resolution} (table {per_hair})", "ns_per_eval": ns,
                     "max_rel_error": max_error,
                     "mean_rel_error": mean_error, "energy_error": None,
                     "bytes": int(sum(t["values"].nbytes for t in tables.values())),
                     "reference": "a_f, a_b by direct quadrature (numpy bilinear lookup)"})
    return rows


def _srbf_multiple_rows(repeats):
    # Xu et al. 2011, Sec. 4.3 under a narrow, a wide and a nearly uniform SRBF light (bandwidths 0.3, 2, 50)
    # against the brute-force integral of the same dual-scattering model. A call first tabulates A_b,
    # Delta_b, sigma_b for the parameters (seconds, adaptive quadrature); ns per (light, view) includes
    # it, spread over 4096 views for the fast path and over one view for the brute force.
    thetas = np.array([-0.5 * np.pi + 1e-3, -1.0, -0.3, 0.0, 0.5, 1.2, 0.5 * np.pi - 1e-3])
    phis = np.linspace(-np.pi, np.pi, 4, endpoint=False) + 0.1
    tt, pp = (a.ravel() for a in np.meshgrid(thetas, phis, indexing="ij"))
    wo = np.stack([np.sin(tt), np.cos(tt) * np.cos(pp), np.cos(tt) * np.sin(pp)], axis=1)
    lam = np.array([0.3, 2.0, 50.0])
    centres = np.array([[np.sin(0.3), np.cos(0.3) * np.cos(-0.5), np.cos(0.3) * np.sin(-0.5)]] * 3)
    forward = {"forward_attenuation": [0.8, 0.6, 0.4], "forward_variance": 0.05}
    values, reference = [], []
    for j in range(3):
        light = {"directions": centres[j:j + 1], "lambdas": lam[j:j + 1], "coefficients": np.ones((1, 3))}
        values.append(bcsdf.srbf_multiple_scattering(BROWN, light, wo, **forward))
        reference.append(bcsdf.srbf_multiple_scattering(BROWN, light, wo, reference=True, theta_samples=96,
                                                        phi_samples=192, **forward))
    lights = {"directions": centres, "lambdas": lam, "coefficients": np.ones((3, 3))}
    many = np.tile(wo, (4096 // len(wo) + 1, 1))
    full = median_seconds(lambda: bcsdf.srbf_multiple_scattering(BROWN, lights, many, **forward), 1)
    brute = median_seconds(lambda: bcsdf.srbf_multiple_scattering(BROWN, lights, wo[:1], reference=True,
                                                                  theta_samples=96, phi_samples=192, **forward), 1)
    items = 3 * len(many)
    max_error, mean_error = _relative_error(np.concatenate(values), np.concatenate(reference))
    return [{"model": "marschner", "tier": "SRBF multiple scattering (Eq. 27-31, m = 4, incl. table)",  # Xu 2011
             "ns_per_eval": full / items * 1e9, "max_rel_error": max_error, "mean_rel_error": mean_error,
             "energy_error": None, "max_energy": None, "bytes": None,
             "reference": "brute force of the same model, 96 x 192 grid"},
            {"model": "marschner", "tier": "SRBF multiple scattering, brute force (96 x 192 grid)",
             "ns_per_eval": brute / 3 * 1e9, "max_rel_error": None, "mean_rel_error": None,
             "energy_error": None, "max_energy": None, "bytes": None, "reference": "itself"}]


def bench_bcsdf(seed=1, repeats=5, lut_resolutions=(16, 32, 64, 128), table_samples=(33, 65, 129, 257)):
    """Rows of {model, tier, ns_per_eval, max_rel_error, mean_rel_error, energy_error, bytes, reference}."""
    wi, wo = _grid(seed)
    count = len(wi)
    rows = []

    def row(model, tier, values, reference, reference_name, ns, energy):
        max_error, mean_error = _relative_error(values, reference) if reference is not None else (None, None)
        rows.append({"model": model, "tier": tier, "ns_per_eval": ns, "max_rel_error": max_error,
                     "mean_rel_error": mean_error, "energy_error": energy[0], "max_energy": energy[1], "bytes": None,
                     "reference": reference_name})

    def run(model, params=BROWN, **inputs):
        values = bcsdf.evaluate(model, params, wi, wo, **inputs)
        ns = _ns_per_item(lambda: bcsdf.evaluate(model, params, wi, wo, **inputs), count, repeats)
        return values, ns

    marschner, ns = run("marschner")
    row("marschner", "exact", marschner, None, "itself (roots of Eq. 10)", ns, _energy("marschner"))  # Marschner 2003
    values, ns = run("marschner_cg")
    row("marschner", "circular gaussian", values, marschner, "marschner exact", ns, _energy("marschner_cg"))
    for tt in ("tafuri", "karis"):
        values, ns = run("realtime", tt=tt)
        energy = _energy("realtime", tt=tt)
        row("marschner", f"realtime ({tt})", values, marschner, "marschner exact", ns, energy)
    values, ns = run("chiang")
    row("chiang", "exact", values, _chiang_brute_force(wi, wo), "64-node quadrature over h of the near field", ns,
        _energy("chiang"))
    values, ns = run("fiber_rtd")
    row("fiber_rtd", "exact", values, None, "itself", ns, _energy("fiber_rtd"))
    _huang_rows(wi, wo, run, row)
    values, ns = run("aggregated", hair_count=4.0, density=0.5)
    row("aggregated", "exact (n = 4, rho = 0.5)", values, None, "itself", ns, _energy("aggregated"))
    rows.extend(_lut_rows(lut_resolutions, table_samples, repeats))
    rows.extend(_srbf_multiple_rows(repeats))
    return {"pairs": count, "repeats": repeats, "rows": rows}


def plot_bcsdf(result, path):
    """ns per evaluation against max relative error, one point per tier (matplotlib, PNG)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figure, axes = plt.subplots(figsize=(7, 4.5))
    for r in result["rows"]:
        if r["max_rel_error"] is None:
            continue
        axes.scatter(r["ns_per_eval"], max(r["max_rel_error"], 1e-8))
        axes.annotate(f"{r['model']}: {r['tier']}", (r["ns_per_eval"], max(r["max_rel_error"], 1e-8)), fontsize=7)
    axes.set_xscale("log")
    axes.set_yscale("log")
    axes.set_xlabel("ns per evaluation")
    axes.set_ylabel("max relative error")
    axes.set_title("BCSDF tiers: speed against error")
    figure.tight_layout()
    figure.savefig(path, dpi=120, format="png")
    plt.close(figure)


def bench_hair_mesh(rings=8, segments=24, layers=5, length=0.6):
    """A hair mesh on the upper hemisphere of a unit sphere without its polar cap (latitudes 10 to
    80 degrees; rings x segments quads), extruded outwards and drooping under gravity into `layers`
    layers over `length`, with latitude-longitude uv."""
    latitude = np.radians(np.linspace(10.0, 80.0, rings + 1))
    longitude = np.linspace(0.0, 2.0 * np.pi, segments, endpoint=False)
    lat, lon = (a.ravel() for a in np.meshgrid(latitude, longitude, indexing="ij"))
    normal = np.stack([np.cos(lat) * np.cos(lon), np.cos(lat) * np.sin(lon), np.sin(lat)], axis=1)
    step = np.linspace(0.0, 1.0, layers + 1)[:, None, None]
    droop = np.array([0.0, 0.0, -0.5 * length])
    points = normal[None] * (1.0 + length * step) + droop * step ** 2
    ring, segment = np.meshgrid(np.arange(rings), np.arange(segments), indexing="ij")
    corner = ring * segments + segment
    following = ring * segments + (segment + 1) % segments
    quads = np.stack([corner, following, following + segments, corner + segments], axis=-1).reshape(-1, 4)
    # uv of each corner: the seam at longitude 2 pi closes with u = 1 rather than wrapping to 0.
    u = np.stack([segment, segment + 1, segment + 1, segment], axis=-1).reshape(-1) / segments
    v = np.stack([ring, ring, ring + 1, ring + 1], axis=-1).reshape(-1) / rings
    uv = np.stack([u, v], axis=1).astype(np.float32)
    return _core.HairMesh(points.astype(np.float32), np.full(len(quads), 4, np.int32),
                          quads.reshape(-1).astype(np.int32), uv)


# Every styling operation, with amplitudes for a head of radius 1 (bench_hair_mesh).
BENCH_STYLING = [
    {"op": "curl", "radius": 0.02, "frequency": 8.0, "randomness": 0.3},
    {"op": "wave", "amplitude": 0.03, "frequency": 2.0, "randomness": 0.5},
    {"op": "twist", "rate": 0.5},
    {"op": "clump", "amount": 0.5, "profile": 2.0},
    {"op": "frizz", "amplitude": 0.004, "frequency": 20.0},
    {"op": "trim", "amount": 0.3},
]


def _strand_bytes(strands):
    arrays = [strands.points, strands.radius, strands.offsets]
    arrays += [strands.attribute(name) for name in strands.attribute_names()]
    return sum(np.asarray(a).nbytes for a in arrays)


def bench_generate(strands=100_000, vertices=33, repeats=7, seed=0):
    """Strand generation from a hair mesh (hair-meshes-realtime.txt): median seconds of
    StrandGenerator.generate into reused output with every styling operation, with none and with
    each alone; vertices per second; the ratio to a copy of an array of the output's bytes (every
    output array: points, radius, offsets, tangent, uvw, bundle), timed in the same run; and the
    storage of the hair mesh JSON with its styling against the generated strands."""
    import json

    from . import hairmesh

    mesh = bench_hair_mesh()
    start = time.perf_counter()
    generator = hairmesh.strand_generator(mesh, strands, seed)
    setup_s = time.perf_counter() - start
    radius = hairmesh.default_radius(mesh)

    def timed(styling):
        operations = hairmesh.styling_from_dicts(styling)
        out = generator.generate(vertices=vertices, styling=operations, radius=radius)  # warm-up, allocates

        def run():
            generator.generate(vertices=vertices, styling=operations, radius=radius, out=out)

        return median_seconds(run, repeats), out

    all_s, output = timed(BENCH_STYLING)
    output_bytes = _strand_bytes(output)
    point_count = int(output.point_count)
    source = np.ones(output_bytes, np.uint8)
    target = np.empty_like(source)
    np.copyto(target, source)
    copy_s = median_seconds(lambda: np.copyto(target, source), repeats)
    none_s, plain = timed([])
    operations = {}
    for operation in BENCH_STYLING:
        seconds, _ = timed([operation])
        operations[operation["op"]] = {"seconds": seconds, "over_none_s": seconds - none_s}

    text = json.dumps(hairmesh.hair_mesh_to_dict(mesh, BENCH_STYLING), separators=(",", ":"))
    plain_bytes = _strand_bytes(plain)
    core_bytes = sum(np.asarray(a).nbytes for a in (plain.points, plain.radius, plain.offsets))
    return {
        "strands": strands,
        "vertices": vertices,
        "hair_mesh": {"faces": mesh.face_count, "layers": mesh.layer_count, "vertices": mesh.vertex_count},
        "styling": BENCH_STYLING,
        "repeats": repeats,
        "setup_s": setup_s,
        "generate_s": all_s,
        "points": point_count,
        "vertices_per_s": point_count / all_s,
        "output_bytes": output_bytes,
        "copy_s": copy_s,
        "ratio_to_copy": all_s / copy_s,
        "generate_no_styling_s": none_s,
        "no_styling_ratio_to_copy": none_s / copy_s,
        "operations": operations,
        "storage": {
            "hair_mesh_json_bytes": len(text.encode("utf-8")),
            "strand_bytes": core_bytes,
            "strand_bytes_with_attributes": plain_bytes,
            "ratio": core_bytes / len(text.encode("utf-8")),
        },
    }


def plot_generate(result, path):
    """Bar chart of generation times: no styling, each operation alone, all, and the copy baseline."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    labels = ["copy", "no styling"] + list(result["operations"]) + ["all"]
    values = [result["copy_s"], result["generate_no_styling_s"]]
    values += [row["seconds"] for row in result["operations"].values()] + [result["generate_s"]]
    figure, axes = plt.subplots(figsize=(7, 4))
    axes.bar(labels, [1e3 * v for v in values], color=["grey", "tab:blue"] + ["tab:orange"] * (len(labels) - 3)
             + ["tab:red"])
    axes.set_ylabel("median ms")
    axes.set_title(f"generate: {result['strands']:,} strands x {result['vertices']} vertices "
                   f"({result['output_bytes'] / 1e6:.0f} MB out)")
    figure.tight_layout()
    figure.savefig(path, dpi=120, format="png")
    plt.close(figure)


__all__ = ["bench_bcsdf", "bench_generate", "bench_hair_mesh", "plot_bcsdf", "plot_generate"]


def synthetic_hair(strands, points, seed=7):
    """Wavy strands hanging from a unit cylinder-capped head (the C++ benchmark's shape)."""
    from . import Strands

    rng = np.random.default_rng(seed)
    azimuth, height = rng.uniform(0, 2 * np.pi, strands), rng.uniform(0, 1, strands)
    roots = np.stack([np.cos(azimuth), np.sin(azimuth), height], axis=1)
    t = np.linspace(0, 1, points)
    wave = np.stack([0.05 * np.sin(12 * t[None, :] + azimuth[:, None]), np.zeros((strands, points)),
                     -np.broadcast_to(t, (strands, points))], axis=2)
    positions = (roots[:, None, :] * (1 + 0.3 * t[None, :, None]) + wave).astype(np.float32).reshape(-1, 3)
    return Strands.from_counts(positions, np.full(strands, points), np.full(strands * points, 0.001, np.float32))


def bench_lod(strands=100_000, points=32, guides=None, levels=6, control_points=16, width_px=_core.DEFAULT_WIDTH_PX, frames=200):
    """LoD build stages, selection time per frame at three distances, memory and quality per level
    on synthetic hair. No assertions: a benchmark, not a test."""
    from . import lod
    from .camera import look_at, perspective

    # numpy builds the synthetic strands in float64 (about 8 arrays of [strands, points, 3]).
    memory_budget.check(int(strands) * int(points) * 3 * 8 * 8 +
                        lod.build_bytes(strands, int(strands) * int(points), control_points),
                        f"bench lod with {strands} strands of {points} points (--strands, --points)")
    hair = synthetic_hair(strands, points)
    start = time.perf_counter()
    asset = lod.build_lod(hair, guides=guides, levels=levels, control_points=control_points)
    build_seconds = time.perf_counter() - start
    projection = perspective(np.radians(40), 16 / 9, 0.05, 100)
    selection = {}
    for distance in (3.0, 6.0, 30.0):
        view = look_at((distance, 0, 0), (0, 0, -0.5))
        seconds = asset._core.time_selection(view.astype(np.float32), projection.astype(np.float32),
                                             (1920.0, 1080.0), width_px, frames)
        selected = asset.select(view, projection, (1920, 1080), width_px).levels
        selection[f"distance_{distance:g}"] = {"seconds_per_frame": seconds, "mean_level": float(selected.mean())}
    return {
        "component": "lod",
        "strands": strands,
        "points_per_strand": points,
        "guides": asset.guide_count,
        "clusters": asset.cluster_count,
        "control_points": control_points,
        "built_levels": len(asset.levels) + 1,
        "build_seconds": build_seconds,
        "stages": asset.timings,
        "selection": selection,
        "memory_ratio": asset.memory_bytes / lod.strand_bytes(hair),  # held in memory
        "stored_ratio": asset.stored_bytes / lod.strand_bytes(hair),  # in the folder's arrays / a pack
        "levels": lod.level_report(asset),
        "area_ratios": asset.area_ratios,
    }


def _skinned_coverage(asset, geometry, points=None):
    """Per thick level: the fraction of member control points inside their skinned ellipse, each
    point projected onto the plane of the ellipse's skinned axes (least squares on the two axes).
    `points` [strands, n_c, 3]: the strands as they really moved (default: as skinned)."""
    if points is None:
        points = geometry["strands"].points.reshape(asset.strand_count, asset.control_points, 3)
    points = np.asarray(points, np.float64)
    coverage = []
    for level, skinned in zip(asset.levels, geometry["levels"]):
        hair = level.membership
        offset = points - skinned["centres"][hair]
        x, y = axes_coordinates(offset, skinned["major"][hair].astype(np.float64), skinned["minor"][hair].astype(np.float64))
        coverage.append(float(np.mean(x * x + y * y <= 1.0 + 1e-5)))
    return coverage


def bench_skinning(strands=100_000, points=32, guides=None, levels=6, control_points=16, frames=30, seed=7):
    """Following animated hair (Sec. 5.1 step 4): per frame, the GPU path's work (FrameSkinning:
    the maps and the selection geometry, the maps' copy for upload, Huang 2025 Eq. 16 on the moved
    geometry) against a static frame's selection in the same run, and the CPU skin of every strand and
    thick hair (export, rendering). Accuracy: the skinned strands against every strand moved by the
    same rigid turn and by a non-rigid bend, and the skinned thick hairs' coverage of the skinned and of
    the truly bent strands. No assertions: a benchmark, not a test."""
    from . import lod, temporal
    from .camera import look_at, perspective

    memory_budget.check(int(strands) * int(points) * 3 * 8 * 8 +
                        lod.build_bytes(strands, int(strands) * int(points), control_points),
                        f"bench skinning with {strands} strands of {points} points (--strands, --points)")
    hair = synthetic_hair(strands, points, seed)
    asset = lod.build_lod(hair, guides=guides, levels=levels, control_points=control_points)
    rest_guides = asset.rest_guides
    view = look_at((6.0, 0.0, 0.0), (0.0, 0.0, -0.5)).astype(np.float32)
    projection = perspective(np.radians(40), 16 / 9, 0.05, 100).astype(np.float32)
    viewport = (1920.0, 1080.0)

    skinning = asset.frame_skinning()
    moving = asset.view_selection(skinning=skinning)
    static = asset.view_selection(skinning=asset.frame_skinning())
    moving.update(view, projection, viewport)
    static.update(view, projection, viewport)
    times = {"skin_maps": [], "maps_copy": [], "select_moved": [], "select_static": []}
    for frame in range(frames):
        guides = temporal.turn(temporal.bend(rest_guides, 0.4 * frame / frames), 0.8 * frame / frames)
        start = time.perf_counter()
        skinning.update(guides)
        skinned = time.perf_counter()
        np.ascontiguousarray(skinning.maps).ravel()  # the copy an upload makes (FrameSkinning.maps copies)
        copied = time.perf_counter()
        moving.set_geometry(skinning)
        moving.update(view, projection, viewport)
        selected = time.perf_counter()
        static.update(view, projection, viewport)
        done = time.perf_counter()
        for name, seconds in zip(times, (skinned - start, copied - skinned, selected - copied, done - selected)):
            times[name].append(seconds)
    per_frame_ms = {name: 1e3 * float(np.median(values)) for name, values in times.items()}
    bent_guides = temporal.bend(rest_guides, 0.4)
    cpu_skin_ms = 1e3 * median_seconds(lambda: asset.skin(bent_guides), repeats=5)

    rest_geometry = asset.skin(rest_guides)
    rest = rest_geometry["strands"].points.reshape(-1, control_points, 3)
    size = float(np.linalg.norm(rest.reshape(-1, 3).max(0) - rest.reshape(-1, 3).min(0)))
    radius = float(np.median(hair.radius))
    turn_angle, bend_angle = np.radians(30.0), 0.4
    turned = asset.skin(temporal.turn(rest_guides, turn_angle))
    bent = asset.skin(bent_guides)
    # The GPU path: the maps applied to the rest pose, as skinning.glsl does.
    skinning.update(bent_guides)
    gpu_points = lod.apply_maps(skinning.maps[asset.levels[0].membership], rest)  # maps [strands, n_c, texels, 4]
    bent_points = bent["strands"].points.reshape(-1, control_points, 3)
    return {
        "component": "skinning",
        "strands": strands,
        "control_points": control_points,
        "guides": asset.guide_count,
        "clusters": asset.cluster_count,
        "built_levels": len(asset.levels) + 1,
        "thick_hairs": int(sum(len(level.n_total) for level in asset.levels)),
        "frames": frames,
        "per_frame_ms": per_frame_ms,
        "gpu_path_ms": per_frame_ms["skin_maps"] + per_frame_ms["maps_copy"],
        "cpu_skin_ms": cpu_skin_ms,
        "maps_bytes": int(skinning.maps.nbytes),
        "hair_size": size,
        "strand_radius": radius,
        "rigid_turn_30deg": lod.following_error(turned["strands"].points.reshape(-1, control_points, 3),
                                             temporal.turn(rest, turn_angle), radius, size),
        "bend": lod.following_error(bent_points, temporal.bend(rest, bend_angle), radius, size),
        "gpu_path_vs_cpu_skin_max_of_size": float(np.abs(gpu_points - bent_points).max()) / size,
        "coverage_rest": [level.coverage for level in asset.levels],
        # The skinned thick hairs against the skinned strands, and against the strands really bent.
        "coverage_bent": _skinned_coverage(asset, bent),
        "coverage_of_bent_strands": _skinned_coverage(asset, bent, temporal.bend(rest, bend_angle)),
        # The same as strands passing through their hair's sections (thick_hair_check.strands_through_sections):
        # at rest, skinned, and the strands really bent.
        "through_sections_rest": _through_sections(asset, rest_geometry, rest),
        "through_sections_bent": _through_sections(asset, bent, bent_points),
        "through_sections_of_bent_strands": _through_sections(asset, bent, temporal.bend(rest, bend_angle)),
    }


def _through_sections(asset, geometry, points):
    """Per thick level of `geometry` (LodAsset.skin): the share of strands (`points` [S, n_c, 3]) passing
    through their hair's sections."""
    return [strands_through_sections(skinned["centres"], skinned["major"], skinned["minor"], level.membership, points)
            for level, skinned in zip(asset.levels, geometry["levels"])]
