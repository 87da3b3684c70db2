"""Each thick hair against its own member strands, by brute force (issue 13's "where the LoD departs from
the full geometry"; hair-lod-aggregated-bcsdf.txt Sec. 4 and 5.1).

The renderer crosses a thick hair as a Poisson process of strands placed uniformly in its elliptical
cross-sections, from its first section to its last (render/scene.h). On a real hair each thick level
is checked against what that model assumes, one number per cause:

- ends: how far the members' tips run past the hair's last cross-section and their roots before its
  first, along the end segments, in segment lengths (the model holds no strands there, and all of
  them up to there);
- through sections: the share of members passing through each cross-section's ellipse where they
  cross its plane (the model holds them all in its sections; strands_through_sections);
- crossings: lines in the plane of sampled cross-sections, across the ellipse (uniform direction and
  offset) and from a member inside it outwards, counting the members they pass within a strand radius
  against the model's expected count (bcsdf::expected_hairs_met), and the share passing none against
  the mean of exp(-count);
- renders: sampled hairs (of at least the median member count) rendered alone as their strands (`pt`)
  and as the thick hair: with the single fibre (`lod-single`, paths inside the hair attenuated and
  scattering, render.OWN_HAIR) and with the aggregated BCSDF (`lod`, RENDERED_AGGREGATED), seen across
  the major and across the minor axis of the middle section, under one sun on the viewer's side, to the
  side or behind: the thick hair's mean image over its strands' per channel.

bench_thick_hairs() returns the numbers, format_tables() a Markdown table. A benchmark: no assertions.
"""

import time

import numpy as np

from . import _core, bcsdf, lod, render
from .hair_params import as_params

__all__ = ["LIGHT_SIDES", "LINE_HAIRS", "RENDERED_AGGREGATED", "RENDERED_HAIRS", "SPP", "axes_coordinates", "bench_thick_hairs", "crossings", "format_tables",
           "member_ends", "renders_against_members", "strands_through_sections"]

# The suns of renders_against_members(), towards the light in the hair's frame at its middle section:
# weights of the view axis (towards the camera), of the axis across the view, and of the hair's direction.
LIGHT_SIDES = {"viewer": (1.0, 0.0, 0.5), "side": (0.3, 1.0, 0.0), "behind": (-1.0, 0.0, 0.5)}
IMAGE_PIXELS = 48  # per side of the renders of one hair
CAMERA_DISTANCE = 1.5  # in lengths of the hair
# Defaults: hairs per level rendered against their strands (hair-to-hair spread is large: 6 hairs
# moved the generated hair's ratios by up to 0.1), their samples per pixel, and hairs per level
# whose sections the lines sample.
RENDERED_HAIRS, SPP, LINE_HAIRS = 16, 128, 150
# The key of the renders' ratios with the aggregated BCSDF (method `lod`), beside render.OWN_HAIR's.
RENDERED_AGGREGATED = "aggregated"


def _unit(vectors):
    length = np.linalg.norm(vectors, axis=-1, keepdims=True)
    return vectors / np.maximum(length, 1e-30), length[..., 0]


def member_ends(level, points):
    """How far the members' tips pass their hair's last section and their roots precede its first,
    along the end segments' directions in those segments' lengths, over every strand of `level` (a
    ThickLevel); `points` the rest strands [S, n_c, 3] in input order."""
    centres = level.centres.astype(np.float64)
    hair = level.membership
    end, end_length = _unit(centres[:, -1] - centres[:, -2])
    start, start_length = _unit(centres[:, 1] - centres[:, 0])
    beyond = np.einsum("ij,ij->i", points[:, -1] - centres[hair, -1], end[hair]) / np.maximum(end_length[hair], 1e-30)
    before = np.einsum("ij,ij->i", centres[hair, 0] - points[:, 0], start[hair]) / np.maximum(start_length[hair], 1e-30)
    return {"tips_beyond_fraction": float(np.mean(beyond > 0.0)), "tips_beyond_p90": float(np.percentile(beyond, 90)),
            "tips_beyond_max": float(beyond.max()), "roots_before_p90": float(np.percentile(before, 90))}


def strands_through_sections(centres, major, minor, membership, points):
    """The share of member strands that pass through their hair's elliptical sections: per hair h and
    control point k (`centres`, `major`, `minor` semi-axis vectors [H, n_c, 3]), each member strand
    (`membership` [S] its hair; `points` [S, n_c, 3] its polyline) is crossed with the plane of the
    section's axes where it crosses nearest to its own k-th point, and counted when that crossing lies
    inside the ellipse (a strand that never crosses the plane is outside). This is whether the thick
    hair, a tube of these sections, holds the strand there. The build fits each section to the same
    crossings (lod/cross_section.h, strand_plane_crossing), and its coverage (ThickLevel.coverage) counts
    them too, but takes a member that does not reach the plane (past its ends, near the hair's first and
    last sections) at its k-th point moved onto the plane, where this counts it outside. Fitted to the
    k-th points themselves (Sec. 5.1 step 3 as written, the previous release), the sections lay in a
    plane tilted from the strands wherever they differ in length or spread, and held 0.60-0.75 of them."""
    centres, major, minor = (np.asarray(v, np.float64) for v in (centres, major, minor))
    points = np.asarray(points, np.float64)
    hair = np.asarray(membership, np.int64)
    strands, nc = points.shape[:2]
    if strands == 0:
        return float("nan")
    inside = np.zeros((strands, nc), bool)
    for k in range(nc):
        c, a, b = centres[hair, k], major[hair, k], minor[hair, k]
        normal, _ = _unit(np.cross(a, b))
        depth = np.einsum("sjx,sx->sj", points - c[:, None], normal)  # each point's side of the plane
        nearest, crossing = np.full(strands, np.inf), np.zeros((strands, 3))
        for j in range(nc - 1):
            d0, d1 = depth[:, j], depth[:, j + 1]
            crosses = (d0 * d1 <= 0.0) & (d0 != d1)
            f = np.where(crosses, d0 / np.where(crosses, d0 - d1, 1.0), 0.0)
            closer = crosses & (np.abs(j + f - k) < nearest)
            nearest[closer] = np.abs(j + f - k)[closer]
            crossing[closer] = (points[:, j] + f[:, None] * (points[:, j + 1] - points[:, j]))[closer]
        # The crossing lies in the plane: its coordinates on the (possibly skewed) axes.
        x, y = axes_coordinates(crossing - c, a, b)
        inside[:, k] = np.isfinite(nearest) & (x * x + y * y <= 1.0 + 1e-5)
    return float(inside.mean())


def axes_coordinates(offset, a, b):
    """(x, y) with offset ~ x a + y b in the least-squares sense, per row (`a`, `b` [..., 3] need not
    be orthogonal, as skinned axes are not): exact for an offset in their plane, else its orthogonal
    projection onto it."""
    aa, bb, ab = (a * a).sum(-1), (b * b).sum(-1), (a * b).sum(-1)
    da, db = (offset * a).sum(-1), (offset * b).sum(-1)
    det = np.maximum(aa * bb - ab * ab, 1e-300)
    return (bb * da - ab * db) / det, (aa * db - ab * da) / det


def _line_counts(x, y, r, ox, oy, dx, dy, length, skip=None):
    """Members (x, y) within r of each line o + t d, 0 < t < length (in-plane, d unit): counts per line."""
    px, py = x[None, :] - ox[:, None], y[None, :] - oy[:, None]
    t = px * dx[:, None] + py * dy[:, None]
    passed = (np.abs(px * dy[:, None] - py * dx[:, None]) < r) & (t > 0.0) & (t < length[:, None])
    if skip is not None:
        passed[np.arange(len(skip)), skip] = False
    return passed.sum(axis=1)


def _exit_distance(ox, oy, dx, dy, major, minor):
    """Distance along d from o (inside) to the ellipse's boundary."""
    a = (dx / major) ** 2 + (dy / minor) ** 2
    b = 2.0 * (ox * dx / major ** 2 + oy * dy / minor ** 2)
    c = (ox / major) ** 2 + (oy / minor) ** 2 - 1.0
    return (-b + np.sqrt(np.maximum(b * b - 4.0 * a * c, 0.0))) / (2.0 * a)


def crossings(level, members, points, radius, rng, hairs=LINE_HAIRS, rays=200):
    """Lines in the planes of sampled cross-sections of `level` against its members (`members(h)` the
    input indices of hair h's strands; `points` [S, n_c, 3] and `radius` [S, n_c], input order): "across"
    the ellipse and "from_member" (from a member inside it outwards). Per kind: the mean count of members passed within their radius ("members") and the
    model's expected count ("model"), and the share of lines passing none ("members_transmittance")
    against the mean of exp(-expected) ("model_transmittance")."""
    nc = points.shape[1]
    candidates = np.nonzero(level.n_total >= 2)[0]
    sums = {"across": np.zeros(5), "from_member": np.zeros(5)}  # model, members, exp(-model), none, lines
    for h in rng.choice(candidates, size=min(len(candidates), hairs), replace=False):
        strands = members(h)
        for k in (nc // 4, nc // 2, (3 * nc) // 4):
            major, minor = (float(v) for v in level.radii[h, k])
            offset = points[strands, k] - level.centres[h, k]
            x, y = offset @ level.major_axis[h, k], offset @ level.minor_axis[h, k]
            r = float(radius[strands, k].mean())
            per_length = bcsdf.strands_met(level.density[h, k], 1.0, len(strands), major, minor)
            # Across: a direction, and an offset uniform over the ellipse's extent normal to it.
            phi = rng.uniform(0.0, np.pi, rays)
            nx, ny = -np.sin(phi), np.cos(phi)
            half = np.sqrt((major * nx) ** 2 + (minor * ny) ** 2)
            s = rng.uniform(-1.0, 1.0, rays) * half
            chord = 2.0 * np.sqrt(np.maximum(half ** 2 - s ** 2, 0.0)) * major * minor / half ** 2
            # The whole line, members outside the ellipse included: from far behind to far ahead.
            dx, dy = ny, -nx
            far = 10.0 * (major + minor) + np.abs(s)
            counts = _line_counts(x, y, r, s * nx - far * dx, s * ny - far * dy, dx, dy, 2.0 * far)
            sums["across"] += [np.sum(per_length * chord), counts.sum(), np.exp(-per_length * chord).sum(),
                               np.sum(counts == 0), rays]
            inside = np.nonzero((x / major) ** 2 + (y / minor) ** 2 < 1.0)[0]
            if len(inside) < 2:
                continue
            start = rng.choice(inside, rays)
            phi = rng.uniform(0.0, 2.0 * np.pi, rays)
            dx, dy = np.cos(phi), np.sin(phi)
            length = _exit_distance(x[start], y[start], dx, dy, major, minor)
            counts = _line_counts(x, y, r, x[start], y[start], dx, dy, length, skip=start)
            sums["from_member"] += [np.sum(per_length * length), counts.sum(), np.exp(-per_length * length).sum(),
                                    np.sum(counts == 0), rays]
    names = ("model", "members", "model_transmittance", "members_transmittance")
    return {kind: {name: float(v / max(total[4], 1.0)) for name, v in zip(names, total[:4])} | {"lines": int(total[4])}
            for kind, total in sums.items()}


def renders_against_members(level, members, points, radius, params, rng, hairs=RENDERED_HAIRS, spp=SPP, seed=0):
    """Sampled hairs of `level` (n_total at least the median; `members` as for crossings()) rendered alone: per own-hair treatment and
    light side (LIGHT_SIDES), the thick hair's mean image over its strands' per channel, averaged over
    the hairs and the two views (across the major and across the minor axis of the middle section)."""
    nc = points.shape[1]
    candidates = np.nonzero(level.n_total >= max(np.median(level.n_total), 2))[0]
    chosen = rng.choice(candidates, size=min(len(candidates), hairs), replace=False)
    sums = {kind: {side: np.zeros(3) for side in LIGHT_SIDES} for kind in (*render.OWN_HAIR, RENDERED_AGGREGATED)}
    for h in chosen:
        member_strands = members(h)
        strands = _core.Strands.from_counts(np.ascontiguousarray(points[member_strands].reshape(-1, 3), np.float32),
                                            np.full(len(member_strands), nc, np.int64),
                                            np.ascontiguousarray(radius[member_strands].reshape(-1), np.float32))
        thick = {"centres": level.centres[h].astype(np.float32), "major_axis": level.major_axis[h].astype(np.float32),
                 "radii": level.radii[h].astype(np.float32), "density": np.minimum(level.density[h], 1.0).astype(np.float32),
                 "offsets": np.array([0, nc], np.int64), "n_total": np.array([len(member_strands)], np.float32)}
        middle = level.centres[h, nc // 2].astype(np.float64)
        along, length = _unit(level.centres[h, -1].astype(np.float64) - level.centres[h, 0])
        for view_axis in (level.major_axis[h, nc // 2], level.minor_axis[h, nc // 2]):
            view_axis = view_axis.astype(np.float64)
            camera = {"eye": (middle + CAMERA_DISTANCE * max(float(length), 1e-6) * view_axis).tolist(),
                      "target": middle.tolist(), "up": along.tolist(), "fov_y": 0.8, "width": IMAGE_PIXELS,
                      "height": IMAGE_PIXELS}
            across = np.cross(view_axis, along)
            for side, (w_view, w_across, w_along) in LIGHT_SIDES.items():
                towards, _ = _unit(w_view * view_axis + w_across * across + w_along * along)
                lights = {"directional": [(tuple(-towards), (3.0, 3.0, 3.0))], "points": [],
                          "environment": np.zeros(3, np.float32)}
                reference = _core.render(strands, None, camera, lights, params, method="pt", spp=spp,
                                         seed=seed + 1)["image"].mean(axis=(0, 1))
                for kind in sums:
                    method, own = ("lod", None) if kind == RENDERED_AGGREGATED else ("lod-single", kind)
                    image = _core.render(None, thick, camera, lights, params, method=method, spp=spp, seed=seed + 2,
                                         own_hair=own)["image"].mean(axis=(0, 1))
                    sums[kind][side] += image / np.maximum(reference, 1e-30)
    views = max(2 * len(chosen), 1)
    return {"hairs": int(len(chosen)),
            "ratios": {own: {side: (total / views).tolist() for side, total in by_side.items()} for own, by_side in sums.items()}}


def bench_thick_hairs(strands, asset=None, guides=None, params=None, hairs=RENDERED_HAIRS, spp=SPP, lines_hairs=LINE_HAIRS, seed=0,
                      progress=None):
    """Every thick level of `asset` (built from `strands` when None) checked against its members:
    dict with settings, per level {level, hairs, ends, crossings, renders} and bench_seconds."""
    if int(hairs) < 1 or int(spp) < 1 or int(lines_hairs) < 1:
        raise ValueError(f"hairs, spp and lines hairs must be >= 1, got {hairs}, {spp}, {lines_hairs}")
    say = progress or (lambda message: None)
    start = time.perf_counter()
    if asset is None:
        say("building the LoD")
        asset = lod.build_lod(strands, guides=guides)
    params = as_params(params)
    rest = asset.skin(None)["strands"]
    nc = asset.control_points
    points = rest.points.reshape(-1, nc, 3).astype(np.float64)
    radius = rest.radius.reshape(-1, nc)
    # Hair h of a level holds the strands at hierarchy positions [member_first[h], member_first[h + 1]).
    stored = asset.arrays()
    strand_order = stored["strand_order"]
    levels = []
    for position, level in enumerate(asset.levels):
        say(f"level {asset.level_ids[position]}: {len(level.n_total)} thick hairs")
        rng = np.random.default_rng(seed + position)
        member_first = stored["levels"][position]["member_first"]

        def members(h, first=member_first):  # in input order
            return np.sort(strand_order[first[h]:first[h + 1]])

        levels.append({"level": asset.level_ids[position], "hairs": int(len(level.n_total)),
                       "mean_members": float(np.mean(level.n_total)),
                       "ends": member_ends(level, points),
                       "through_sections": strands_through_sections(
                           level.centres, level.major_axis * level.radii[..., :1], level.minor_axis * level.radii[..., 1:],
                           level.membership, points),
                       "coverage_in_plane": float(level.coverage),
                       "crossings": crossings(level, members, points, radius, rng, hairs=lines_hairs),
                       "renders": renders_against_members(level, members, points, radius, params, rng, hairs=hairs,
                                                          spp=spp, seed=seed)})
    return {"strands": asset.strand_count, "control_points": nc, "spp": int(spp), "image_pixels": IMAGE_PIXELS,
            "levels": levels, "bench_seconds": time.perf_counter() - start}


def _rgb(values):
    return " / ".join(f"{v:.2f}" for v in values)


def format_tables(result):
    """Markdown: one row per thick level, after a line saying what it measures."""
    lines = [f"Each thick level against its member strands ({result['strands']} strands at {result['control_points']} "
             f"control points). Ends: members' tips past the last section (share, 90th percentile and most, in "
             f"segment lengths), roots before the first (90th percentile). Through: the share of member strands "
             f"passing through their sections' ellipses where they cross each section's plane (in brackets the "
             f"build's coverage: the same crossings, a member not reaching a plane taken at its k-th point). Lines in sampled sections' planes: "
             f"members passed over the model's count, and the share passing none (members / model), across the "
             f"ellipse and from a member outwards. Renders: hairs alone at {result['spp']} spp, the thick hair "
             f"(lod-single attenuated and scattering inside, lod) over its strands (pt), R / G / B, per sun.", "",
             "| level | hairs | strands per hair | tips past the end | roots before | through | across: count ratio, none | "
             "from a member: count ratio, none | attenuated: viewer / side / behind | scattering: viewer / side / "
             "behind | aggregated (lod): viewer / side / behind |",
             "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    for level in result["levels"]:
        ends, lines_ = level["ends"], level["crossings"]

        def line_cell(kind):
            c = lines_[kind]
            ratio = c["members"] / c["model"] if c["model"] > 0 else float("nan")
            return f"{ratio:.2f}, {c['members_transmittance']:.3f} / {c['model_transmittance']:.3f}"

        ratios = level["renders"]["ratios"]
        lines.append(f"| {level['level']} | {level['hairs']} | {level['mean_members']:.1f} | "
                     f"{100 * ends['tips_beyond_fraction']:.0f} %, {ends['tips_beyond_p90']:.2f}, {ends['tips_beyond_max']:.1f} | "
                     f"{ends['roots_before_p90']:.2f} | {level['through_sections']:.2f} ({level['coverage_in_plane']:.2f}) | "
                     f"{line_cell('across')} | {line_cell('from_member')} | "
                     + " ; ".join(_rgb(ratios["attenuate"][side]) for side in LIGHT_SIDES) + " | "
                     + " ; ".join(_rgb(ratios["scatter"][side]) for side in LIGHT_SIDES) + " | "
                     + " ; ".join(_rgb(ratios[RENDERED_AGGREGATED][side]) for side in LIGHT_SIDES) + " |")
    return "\n".join(lines)
