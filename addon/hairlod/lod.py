"""Hair LoD assets: guides, L0 clusters, thick elliptical hairs per level, skinning and selection.

Implements hair-lod-aggregated-bcsdf.txt Sec. 5 over the C++ core (no bpy). Arrays are numpy copies.
"""

import os
import tokenize
import zipfile
import zlib
from dataclasses import dataclass
from io import BytesIO

import numpy as np

from . import _core, atomic_output, memory_budget, strict_json

# The screen-width threshold (pixels) every tool defaults to, and the smallest accepted: defined in C++
# (lod/selection.h), where the selection uses them.
DEFAULT_WIDTH_PX = round(_core.DEFAULT_WIDTH_PX, 6)  # float32 in C++; rounded for messages
MIN_WIDTH_PX = round(_core.MIN_WIDTH_PX, 6)
# Vertex LoD of the drawn strands (lod/vertex_lod.h): pixels a left-out control point may lie off them.
DEFAULT_VERTEX_TOLERANCE_PX = round(_core.DEFAULT_VERTEX_TOLERANCE_PX, 6)
# The build's defaults (guides 0 = automatic, levels, control_points, seed, ellipse_coverage) and ranges,
# defined in C++ (lod/lod_asset.h LodOptions) for every tool.
LOD_DEFAULTS = {name: (round(value, 6) if isinstance(value, float) else value)
                for name, value in _core.LOD_DEFAULTS.items()}
MIN_LEVELS, MAX_LEVELS = _core.LEVELS_RANGE
MIN_CONTROL_POINTS = _core.MIN_CONTROL_POINTS
# Strands.resampled(n_c, LOD_ARC_LENGTH_SUBDIVISIONS) resamples as build_lod does: the rest pose the
# asset's skinning reproduces.
LOD_ARC_LENGTH_SUBDIVISIONS = _core.LOD_ARC_LENGTH_SUBDIVISIONS
SKIN_MAP_TEXELS = _core.SKIN_MAP_TEXELS  # RGBA texels per skinning map (FrameSkinning.maps, skinning.glsl)

__all__ = ["DEFAULT_VERTEX_TOLERANCE_PX", "DEFAULT_WIDTH_PX", "LOD_ARC_LENGTH_SUBDIVISIONS", "LOD_DEFAULTS", "MAX_LEVELS", "MIN_CONTROL_POINTS", "MIN_LEVELS", "MIN_WIDTH_PX", "BuildCancelled", "BuildProgress", "LodAsset", "ThickLevel", "build_lod", "check_animation", "curve_subset", "following_error", "frame_guides", "keep_scene_levels", "load",
           "load_animation", "pack",
           "read_cameras", "save", "scene_levels", "unpack"]

MANIFEST = "manifest.json"
FORMAT_KIND = "hairlod-lod/"  # the manifest "format" prefix that marks a folder as an LoD asset hairlod wrote
WHAT = "an LoD folder"  # the kind in messages
# 2: compact cross-sections and strand coordinates, hierarchy order; 3: strand_radius once per strand
# where every strand's radius is the same along it; 4: no cross-sections (a function of the stored
# strands and ellipse_coverage, fitted again on reading: C++ fit_sections). A version reads the ones
# before it.
FORMAT = FORMAT_KIND + "4"
READABLE_FORMATS = (FORMAT_KIND + "2", FORMAT_KIND + "3", FORMAT)


@dataclass(frozen=True)
class ThickLevel:
    """One level of thick hairs at rest; per-control-point arrays are [hairs, n_c, ...]."""

    centres: np.ndarray        # float32 [H, n_c, 3]
    major_axis: np.ndarray     # float32 [H, n_c, 3], unit (decoded from the compact storage)
    minor_axis: np.ndarray     # float32 [H, n_c, 3], unit
    radii: np.ndarray          # float32 [H, n_c, 2] (major, minor)
    density: np.ndarray        # float32 [H, n_c], rho = n_total r^2 / (|r_A| |r_B|) (Sec. 4), derived
    n_total: np.ndarray        # int32 [H], member strands
    parent: np.ndarray         # int32 [H], hair one level coarser (-1 on L0)
    membership: np.ndarray     # int32 [strands], hair of this level holding each strand
    cluster_first: np.ndarray  # int32 [clusters + 1], hairs of L0 cluster c: [first[c], first[c + 1])
    coverage: float            # fraction of member control points inside their ellipse
    mean_area: float           # mean pi r_A r_B


class LodAsset:
    """A built LoD hierarchy; the strands themselves are the finest level (index len(levels))."""

    def __init__(self, core_asset, level_ids=None, timings=None):
        self._core = core_asset
        self._timings = dict(timings) if timings is not None else core_asset.timings
        self.levels = [ThickLevel(**level) for level in core_asset.thick_levels()]
        # Index of each thick level in the full hierarchy it was built as (scene_levels may drop some).
        self.level_ids = list(range(len(self.levels))) if level_ids is None else list(level_ids)
        self._skinning_rest = None  # derived from the rest pose on the first skin (quadratic_stencil.h)

    guide_count = property(lambda self: self._core.guide_count)
    cluster_count = property(lambda self: self._core.cluster_count)
    strand_count = property(lambda self: self._core.strand_count)
    control_points = property(lambda self: self._core.control_points)
    guide_strands = property(lambda self: self._core.guide_strands)
    strand_order = property(lambda self: self._core.strand_order)  # the strands in hierarchy order
    rest_guides = property(lambda self: self._core.rest_guides)
    cluster_guides = property(lambda self: self._core.cluster_guides)
    timings = property(lambda self: dict(self._timings))  # build seconds per stage
    memory_bytes = property(lambda self: self._core.memory_bytes)  # held in memory, cross-sections included
    stored_bytes = property(lambda self: self._core.stored_bytes)  # in a file or pack: without them

    @property
    def coverage(self):
        """Coverage per thick level (target >= 0.95)."""
        return [level.coverage for level in self.levels]

    @property
    def area_ratios(self):
        """Mean cross-section area of each level over the next finer one (about 4 by design)."""
        return [coarse.mean_area / fine.mean_area for coarse, fine in zip(self.levels, self.levels[1:])]

    def arrays(self, sections=True):
        """Every array by name, flat [n] or [n, components]; 'levels' holds one dict per thick level,
        with its compact cross-sections unless `sections` is False (what save() and pack() store)."""
        return self._core.arrays(sections)

    def scalars(self):
        """control_points, radius_exponent, ellipse_coverage, coverage and mean_area per thick level."""
        return self._core.scalars()

    def with_levels(self, kept):
        """A copy keeping only the thick levels at positions `kept` (sorted); each kept level's parent
        points to the next kept coarser level (composed through dropped ones), -1 on the first."""
        kept = sorted(set(kept))
        if not kept or kept[0] < 0 or kept[-1] >= len(self.levels):
            raise ValueError(f"levels to keep must be a non-empty subset of 0..{len(self.levels) - 1}")
        return LodAsset(self._core.with_levels(kept), [self.level_ids[level] for level in kept], self.timings)

    def _rest(self):
        # What skinning derives from the rest pose (about 0.1 s for 10^5 strands), kept for later frames.
        if self._skinning_rest is None:
            self._skinning_rest = self._core.skinning_rest()
        return self._skinning_rest

    def skin(self, deformed_guides=None):
        """Strands and thick hairs for guides [G, n_c, 3], or at the rest pose exactly (None; skinning
        the rest guides gives it up to float rounding): dict with 'strands' (Strands), 'levels'
        (centres, tangents, major/minor semi-axes, corners) and 'cluster_bounds' [C, 4]."""
        if deformed_guides is None:
            return self._core.rest_geometry()
        return self._core.skin(np.asarray(deformed_guides, dtype=np.float32), self._rest())

    def preview_vertices(self):
        """Rest-pose vertex arrays of the viewport preview, in the layout preview_buffers describes
        (made in one parallel C++ pass): dict with 'levels' (per thick level: position, tangent,
        major, minor [2 H n_c, 3], cluster (n_total, rho) and select_key (L0 cluster, control point)
        [2 H n_c, 2]), 'strands' (position, tangent [S n_c, 3], select_key [S n_c, 2], hierarchy
        order) and 'rest_strands' (Strands at n_c points, input order)."""
        return self._core.preview_vertices()

    def select(self, view, projection, viewport_size, width_px=DEFAULT_WIDTH_PX, previous=None, guides=None):
        """LoD selection from column-major-convention 4x4 matrices (numpy rows are matrix rows,
        as Blender's Matrix converts): the initial selection, or Huang 2025 Eq. 16 from `previous`; on
        the hair skinned to `guides` [G, n_c, 3], or at the rest pose (None)."""
        if guides is not None:
            guides = np.asarray(guides, dtype=np.float32)
        return self._core.select(guides, np.asarray(view, dtype=np.float32), np.asarray(projection, dtype=np.float32),
                                 tuple(float(v) for v in viewport_size), float(width_px), previous,
                                 None if guides is None else self._rest())

    def view_selection(self, guides=None, skinning=None):
        """Per-view selection state for drawing (initial selection, then one Huang 2025 Eq. 16 step per
        update), on the rest pose, the skinned guides [G, n_c, 3], or the current frame of a
        FrameSkinning of this asset (which skins no strand; ``selection.set_geometry(skinning)``
        follows its later frames)."""
        if skinning is not None:
            return _core.ViewSelection(skinning)
        return _core.ViewSelection(self._core, None if guides is None else np.asarray(guides, dtype=np.float32))

    def frame_skinning(self):
        """Per-frame skinning for drawing on the GPU (Sec. 5.1 step 4): ``update(guides)`` computes
        the quadratic map of every L0 cluster and control point (``maps`` [clusters, n_c,
        SKIN_MAP_TEXELS, 4], applied by ``apply_maps``) and what selection reads, in O(clusters n_c)."""
        return _core.FrameSkinning(self._core)

    def resample_guides(self, guide_curves):
        """Guides [G, n_c, 3] from ``guide_curves`` (Strands: the guide strands, in the order of
        guide_strands, as they are now), resampled as build_lod resamples them."""
        return self._core.resample_guides(guide_curves)


def curve_subset(points, offsets, curves):
    """Strands of the curves `curves` (indices, in that order) of the curves given by points [N, 3]
    and offsets [C + 1], positions only (radius 0): the guide strands of an animated frame."""
    offsets = np.asarray(offsets, dtype=np.int64)
    curves = np.asarray(curves, dtype=np.int64)
    counts = offsets[curves + 1] - offsets[curves]
    subset_offsets = np.concatenate([[0], np.cumsum(counts)])
    # Point i of the subset is point i - subset_offsets[c] + offsets[curves[c]] of its curve c.
    gather = np.repeat(offsets[curves] - subset_offsets[:-1], counts) + np.arange(subset_offsets[-1])
    return _core.Strands(np.asarray(points, dtype=np.float32)[gather], subset_offsets, None)


def frame_guides(asset, strands, what="the frame"):
    """The guides [G, n_c, 3] of `asset` in `strands`, the asset's hair as it is at some frame (the
    same curves in the same order, moved or deformed): its guide strands resampled as the build
    resamples them. Raises ValueError when the curves do not match the asset's."""
    if len(strands) != asset.strand_count:
        raise ValueError(f"{what} has {len(strands)} curves, the LoD asset {asset.strand_count}")
    return asset.resample_guides(curve_subset(strands.points, strands.offsets, asset.guide_strands))


def following_error(skinned, truth, strand_radius, size):
    """How far skinned points lie from the same points deformed by other means (every strand moved,
    e.g. by Blender's Deform Curves on Surface, resampled as build_lod resamples: Strands.resampled(
    n_c, LOD_ARC_LENGTH_SUBDIVISIONS)): the mean, 99th percentile and largest distance, in strand
    radii and as fractions of the hair's size."""
    distance = np.linalg.norm(np.asarray(skinned, np.float64).reshape(-1, 3) -
                              np.asarray(truth, np.float64).reshape(-1, 3), axis=1)
    stats = {"mean": float(distance.mean()), "p99": float(np.percentile(distance, 99)), "max": float(distance.max())}
    return {**{f"{k}_radii": v / strand_radius for k, v in stats.items()},
            **{f"{k}_of_size": v / size for k, v in stats.items()}}


def apply_maps(maps, rest):
    """Rest points [..., 3] moved by skinning maps [..., SKIN_MAP_TEXELS, 4] (FrameSkinning.maps, one
    per point, broadcast), float64: what the preview's skinning.glsl computes."""
    maps = np.asarray(maps, dtype=np.float64)
    d = np.asarray(rest, dtype=np.float64) - maps[..., 0, :3]
    products = np.stack([d[..., 0] * d[..., 1], d[..., 1] * d[..., 2], d[..., 2] * d[..., 0]], axis=-1)
    return (np.einsum("...rj,...j->...r", maps[..., 1:4, :3], d) + maps[..., 1:4, 3]
            + np.einsum("...rj,...j->...r", maps[..., 4:7, :3], d * d)
            + np.einsum("...rj,...j->...r", maps[..., 7:10, :3], products))


def strand_bytes(strands):
    """Bytes of the strand data an asset's memory is compared with: points, radius, offsets."""
    return strands.points.nbytes + strands.radius.nbytes + strands.offsets.nbytes


def level_report(asset):
    """Per thick level: its id, hairs, coverage and mean cross-section area, as plain Python."""
    return [{"level": level_id, "hairs": int(len(level.n_total)), "coverage": level.coverage,
             "mean_area": level.mean_area}
            for level_id, level in zip(asset.level_ids, asset.levels)]


BuildProgress = _core.LodBuildProgress
BuildCancelled = _core.BuildCancelled


# Peak bytes of a build per strand and control point (resampled strands, k-means features, thick
# levels, skinning coordinates) and per input point; measured with build_lod on 100 to 10^5 strands.
BUILD_BYTES_PER_CONTROL_POINT = 256
# Each thick level is also written as a .hair file, which stores at most 65536 points per curve.
MAX_CONTROL_POINTS = 65536
BUILD_BYTES_PER_POINT = 64


def build_bytes(strand_count, point_count, control_points):
    """Estimated peak bytes of build_lod, for the memory budget."""
    return int(strand_count) * int(control_points) * BUILD_BYTES_PER_CONTROL_POINT + \
        int(point_count) * BUILD_BYTES_PER_POINT


def _require_integer(name, value, lowest, highest=2**31 - 1):
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or not lowest <= value <= highest:
        raise _core.HairlodError(f"{name} must be an integer from {lowest} to {highest}, got {value!r}")
    return int(value)


def build_lod(strands, guides=None, levels=LOD_DEFAULTS["levels"], control_points=LOD_DEFAULTS["control_points"],
              seed=LOD_DEFAULTS["seed"], ellipse_coverage=LOD_DEFAULTS["ellipse_coverage"], progress=None):
    """Builds an LodAsset from Strands (Sec. 5.1); `guides` None (or 0) picks auto_guide_count(len(strands)).
    Raises ValueError on invalid input (before
    allocating when the sizes asked for exceed the memory budget). The C++ build releases the GIL:
    another thread may watch `progress` (BuildProgress: done / total steps) and call its cancel(),
    after which this raises BuildCancelled."""
    guides = 0 if guides is None else _require_integer("guides", guides, 0)
    levels = _require_integer("levels", levels, MIN_LEVELS, MAX_LEVELS)
    control_points = _require_integer("control_points", control_points, MIN_CONTROL_POINTS, MAX_CONTROL_POINTS)
    seed = _require_integer("seed", seed, 0, 2**64 - 1)
    memory_budget.check(build_bytes(len(strands), strands.point_count, control_points),
                        f"an LoD of {len(strands)} strands with {control_points} control points (control_points)")
    return LodAsset(_core.build_lod(strands, guides=guides, levels=levels, control_points=control_points,
                                    seed=seed, ellipse_coverage=ellipse_coverage, progress=progress))


def read_cameras(path):
    """Cameras from JSON: a list of {"view": 4x4, "projection": 4x4, "viewport": [width, height]}
    (numpy row order, as Blender's Matrix). Raises ValueError naming the file and the problem."""
    entries = strict_json.load(path, "cameras")
    if not isinstance(entries, list) or not entries:
        raise ValueError(f"{path}: expected a non-empty list of cameras")
    cameras = []
    for index, entry in enumerate(entries):
        try:
            view = np.asarray(entry["view"], dtype=np.float64)
            projection = np.asarray(entry["projection"], dtype=np.float64)
            viewport = tuple(float(v) for v in entry["viewport"])
        except (KeyError, TypeError, ValueError) as error:
            raise ValueError(f"{path}: camera {index} needs view, projection (4x4) and viewport [w, h] ({error})") from None
        if view.shape != (4, 4) or projection.shape != (4, 4) or len(viewport) != 2:
            raise ValueError(f"{path}: camera {index}: view and projection must be 4x4, viewport [width, height]")
        if not (np.all(np.isfinite(view)) and np.all(np.isfinite(projection)) and min(viewport) > 0):
            raise ValueError(f"{path}: camera {index}: matrices must be finite and the viewport positive")
        cameras.append({"view": view, "projection": projection, "viewport": viewport})
    return cameras


def scene_levels(asset, cameras, width_px=DEFAULT_WIDTH_PX):
    """Levels (0 = L0 .. len(asset.levels) = the strands) that the initial selection (Sec. 5.1 step 5)
    of some camera picks for some visible segment, at the rest pose."""
    used = set()
    for camera in cameras:
        selection = asset.select(camera["view"], camera["projection"], camera["viewport"], width_px)
        used.update(int(level) for level in np.unique(selection.levels[selection.visible]))
    return sorted(used)


def keep_scene_levels(asset, cameras, width_px=DEFAULT_WIDTH_PX):
    """Item 8: (asset with only the thick levels some camera selects, selected levels). L0 always
    stays: its hairs are the clusters that selection and skinning are defined on."""
    finest = len(asset.levels)
    selected = scene_levels(asset, cameras, width_px)
    kept = sorted({0} | {level for level in selected if level < finest})
    return asset.with_levels(kept), selected


def _level_strands(asset, level):
    """Thick hairs of one level as Strands: rest centre curves, radius = major radius (.hair
    thickness = 2 x major radius)."""
    hairs, nc = level.centres.shape[:2]
    return _core.Strands.from_counts(level.centres.reshape(-1, 3), np.full(hairs, nc, np.int64),
                                     np.ascontiguousarray(level.radii[..., 0].reshape(-1)))


# Per-hair data of each thick level written beside the stored arrays (derived from them, so
# load() checks them instead of reading them): name -> what the manifest says it holds.
PER_HAIR = {
    "n_total": "int32 [hairs]: member strands of each thick hair",
    "density": "float32 [hairs, n_c]: rho = n_total r^2 / (|r_A| |r_B|), Sec. 4, r the members' mean radius",
    "major_axis": "float32 [hairs, n_c, 3]: unit major axis of the rest cross-section",
    "minor_axis": "float32 [hairs, n_c, 3]: unit minor axis of the rest cross-section",
    "radii": "float32 [hairs, n_c, 2]: (major, minor) radii of the rest cross-section",
    "membership": "int32 [strands]: per input strand, the hair of this level holding it",
}


def _write_array(folder, name, array, entries, key=None, meaning=None):
    file_name = f"{name}.npy"
    np.save(os.path.join(folder, file_name), np.ascontiguousarray(array), allow_pickle=False)
    entry = entries[key or name] = {"file": file_name, "dtype": str(array.dtype), "shape": list(array.shape)}
    if meaning is not None:
        entry["meaning"] = meaning


def _header(asset):
    """Everything of an asset but its arrays, as JSON-able data (shared by save() and pack())."""
    scalars = asset.scalars()
    levels = [{"level": asset.level_ids[position], "hairs": int(len(level.n_total)),
               "coverage": scalars["coverage"][position], "mean_area": scalars["mean_area"][position]}
              for position, level in enumerate(asset.levels)]
    return {
        "format": FORMAT,
        "control_points": scalars["control_points"],
        "radius_exponent": scalars["radius_exponent"],
        "ellipse_coverage": scalars["ellipse_coverage"],
        "strands": asset.strand_count,
        "guides": asset.guide_count,
        "clusters": asset.cluster_count,
        "thick_levels": levels,
        "area_ratios": [levels[i]["mean_area"] / levels[i + 1]["mean_area"] for i in range(len(levels) - 1)],
        "timings": asset.timings,
        "memory_bytes": asset.memory_bytes,
        "stored_bytes": asset.stored_bytes,
    }


# The manifest's description of guide_animation.npy, for readers without hairlod.
ANIMATION_MEANING = ("guides[f, g, k] (float32 [frames, guides, n_c, 3], object space): control point k of guide g "
                     "(the order of guide_strands) at frame frames[f]. Every strand and thick hair follows by the "
                     "linear skinning of hair-lod-aggregated-bcsdf.txt Sec. 5.1 step 4: LodAsset.skin(guides[f]) "
                     "in hairlod: per L0 cluster c and control point k a quadratic field fitted to the nearest "
                     "guides' points (hairlod's quadratic_stencil.h), applied to the stored offsets, which the "
                     "frame of its cluster_guides (frame_kinds) settles where the guides leave directions open.")


def check_animation(asset, frames, guides):
    """(frames int64 [F], guides float32 [F, G, n_c, 3]) checked against `asset`: strictly increasing
    frames, one guide pose per frame, finite coordinates. Raises ValueError naming what is wrong."""
    frames = np.asarray(frames)
    guides = np.asarray(guides, dtype=np.float32)
    if frames.ndim != 1 or len(frames) == 0 or not np.issubdtype(frames.dtype, np.integer):
        raise ValueError("animation frames must be a non-empty list of integers")
    if np.any(np.diff(frames) <= 0):
        raise ValueError("animation frames must be strictly increasing")
    expected = (len(frames), asset.guide_count, asset.control_points, 3)
    if guides.shape != expected:
        raise ValueError(f"animation guides must have shape {list(expected)} (frames, guides, control points, xyz), "
                         f"got {list(guides.shape)}")
    if not np.all(np.isfinite(guides)):
        raise ValueError("animation guides contain NaN or infinite coordinates")
    return frames.astype(np.int64), guides


def save(asset, directory, extra=None, force=False, inputs=(), animation=None):
    """Writes `asset` into folder `directory` atomically (atomic_output.replace_folder: built under a
    temporary name, moved into place when complete): manifest.json, one .npy per stored array, the
    per-hair arrays of PER_HAIR and one .hair per thick level (thickness = 2 x major radius).
    An existing `directory` is replaced only when it is an LoD folder hairlod wrote, or with
    `force`; never when it holds one of `inputs` (paths this run reads). `extra` (JSON-able dict)
    is stored in the manifest under "extra". `animation`: (frames [F], guides [F, G, n_c, 3]), the
    guides of an animated hair per frame (check_animation), stored as guide_animation.npy and
    described under "animation" (load_animation reads them back). Returns the manifest."""
    if animation is not None:
        animation = check_animation(asset, *animation)
    return atomic_output.replace_folder(directory, FORMAT_KIND,
                                        lambda folder: _write_folder(asset, folder, extra, animation),
                                        force=force, inputs=inputs, what=WHAT)


def load_animation(directory, asset):
    """(frames int64 [F], guides float32 [F, G, n_c, 3]) stored by save(..., animation=...) in the LoD
    folder `directory` of `asset`, or None when it holds no animation; ValueError when damaged."""
    directory = os.fspath(directory)
    manifest = strict_json.load(os.path.join(directory, MANIFEST), f"the manifest of LoD folder {directory}")
    entry = manifest.get("animation") if isinstance(manifest, dict) else None
    if entry is None:
        return None
    if not isinstance(entry, dict) or not isinstance(entry.get("frames"), list):
        raise ValueError(f"{directory}: {MANIFEST}: animation must be an object with a list of frames")
    guides = _read_array(directory, entry, "guide_animation")
    try:
        return check_animation(asset, np.asarray(entry["frames"]), guides)
    except ValueError as error:
        raise ValueError(f"{directory}: {error}") from None


def _write_folder(asset, folder, extra, animation=None):
    from . import io

    arrays = asset.arrays(sections=False)
    manifest = _header(asset)
    entries = {}
    for name, array in arrays.items():
        if name != "levels":
            _write_array(folder, name, array, entries)
    for position, (level, level_arrays) in enumerate(zip(asset.levels, arrays["levels"])):
        level_entries, per_hair = {}, {}
        for name, array in level_arrays.items():
            _write_array(folder, f"level{position}_{name}", array, level_entries)
        for name, meaning in PER_HAIR.items():
            _write_array(folder, f"level{position}_hair_{name}", getattr(level, name), per_hair, name, meaning)
        hair_file = f"level{position}.hair"
        io.write(os.path.join(folder, hair_file), _level_strands(asset, level))
        manifest["thick_levels"][position].update({
            "hair_file": hair_file,
            # The stored arrays the asset is read back from: parent (hair one kept level coarser;
            # the cluster tree), member_first (hair h holds the strands at positions
            # [member_first[h], member_first[h + 1]) of strand_order), cluster_first. The
            # cross-sections are fitted again to those strands on reading (ellipse_coverage).
            "arrays": level_entries,
            # The same data decoded per thick hair, for readers without the decoder.
            "per_hair": per_hair,
        })
    manifest.update(arrays=entries, extra=extra or {})
    if animation is not None:
        frames, guides = animation
        holder = {}
        _write_array(folder, "guide_animation", guides, holder, meaning=ANIMATION_MEANING)
        manifest["animation"] = dict(holder["guide_animation"], frames=[int(f) for f in frames])
    text = strict_json.dumps(manifest, indent=1)
    with open(os.path.join(folder, MANIFEST), "w", encoding="utf-8") as file:
        file.write(text)
    return manifest


# What numpy's .npy / .npz readers raise on damaged data: besides OSError and ValueError, a header
# that does not parse raises tokenize's or ast's errors, a huge declared shape MemoryError, a
# damaged zip member zlib.error or EOFError.
_NPY_ERRORS = (OSError, ValueError, EOFError, MemoryError, SyntaxError, tokenize.TokenError, zipfile.BadZipFile,
               zlib.error, KeyError, NotImplementedError, RuntimeError, TypeError, OverflowError)


def _read_array(folder, entry, what):
    try:
        path = os.path.join(folder, os.path.basename(entry["file"]))
        array = np.load(path, allow_pickle=False)
    except (KeyError, TypeError, AttributeError) as error:
        raise ValueError(f"{folder}: manifest entry for {what} is malformed ({error})") from None
    except _NPY_ERRORS as error:
        raise ValueError(f"{folder}: cannot read {what} ({type(error).__name__}: {error})") from None
    shape = entry.get("shape")
    if not isinstance(shape, list) or list(array.shape) != shape or str(array.dtype) != entry.get("dtype"):
        raise ValueError(f"{folder}: {what} does not match its manifest shape/dtype")
    return array


def _asset_from(header, read, where):
    """An LodAsset from a header (_header()) and read(name) giving the stored array `name`
    (level arrays as 'level{position}_{name}'); ValueError names `where` and the problem."""
    if not isinstance(header, dict) or header.get("format") not in READABLE_FORMATS:
        raise ValueError(f"{where}: not a hairlod LoD asset (format must be one of {', '.join(READABLE_FORMATS)})")
    try:
        levels = header["thick_levels"]
        arrays = {name: read(name, None) for name in header["array_names"]}
        arrays["levels"] = [{name: read(f"level{position}_{name}", position) for name in header["level_array_names"]}
                            for position in range(len(levels))]
        scalars = {"control_points": int(header["control_points"]),
                   "radius_exponent": int(header["radius_exponent"]),
                   # Format 4: what the cross-sections are fitted with (earlier formats store them).
                   **({"ellipse_coverage": float(header["ellipse_coverage"])} if header["format"] == FORMAT else {}),
                   "coverage": [float(level["coverage"]) for level in levels],
                   "mean_area": [float(level["mean_area"]) for level in levels]}
        level_ids = [int(level["level"]) for level in levels]
        timings = {str(stage): float(seconds) for stage, seconds in header["timings"].items()}
    except (KeyError, TypeError, AttributeError, IndexError, ValueError, OverflowError) as error:
        raise ValueError(f"{where}: the asset description is missing or malforms an entry ({error})") from None
    try:
        return LodAsset(_core.LodAsset.from_arrays(scalars, arrays), level_ids, timings)
    except ValueError as error:
        raise ValueError(f"{where}: {error}") from None


def load(directory):
    """Reads a folder written by save() back into an identical LodAsset, checking the per-hair
    arrays against the ones it decodes; raises ValueError naming the folder and the problem."""
    directory = os.fspath(directory)
    manifest = strict_json.load(os.path.join(directory, MANIFEST), f"the manifest of LoD folder {directory}")
    if not isinstance(manifest, dict) or manifest.get("format") not in READABLE_FORMATS:
        raise ValueError(f"{directory}: not a hairlod LoD folder (format must be one of {', '.join(READABLE_FORMATS)})")
    try:
        entries = dict(manifest["arrays"])
        for level in manifest["thick_levels"]:
            entries.update(level["arrays"])  # named level{position}_{array}
        level_names = list(manifest["thick_levels"][0]["arrays"]) if manifest["thick_levels"] else []
        header = dict(manifest, array_names=list(manifest["arrays"]),
                      level_array_names=[name.split("_", 1)[1] for name in level_names])
    except (KeyError, TypeError, AttributeError, IndexError, ValueError) as error:
        raise ValueError(f"{directory}: {MANIFEST} is missing or malforms an entry ({error})") from None
    asset = _asset_from(header, lambda name, _: _read_array(directory, entries.get(name), name), directory)
    for position, (level, entry) in enumerate(zip(asset.levels, manifest["thick_levels"])):
        per_hair = entry.get("per_hair", {}) if isinstance(entry, dict) else None
        if not isinstance(per_hair, dict):
            raise ValueError(f"{directory}: {MANIFEST}: per_hair of thick level {position} must be an object")
        for name, file_entry in per_hair.items():
            if name in PER_HAIR and not np.array_equal(_read_array(directory, file_entry, name), getattr(level, name)):
                raise ValueError(f"{directory}: per-hair {name} of thick level {position} disagrees with the stored arrays")
    return asset


def pack(asset):
    """The asset as one bytes object (a compressed .npz holding the stored arrays and the header),
    to keep inside another file such as a .blend; unpack() reads it back identically."""
    arrays = asset.arrays(sections=False)
    stored = {name: array for name, array in arrays.items() if name != "levels"}
    for position, level_arrays in enumerate(arrays["levels"]):
        stored.update({f"level{position}_{name}": array for name, array in level_arrays.items()})
    header = dict(_header(asset), array_names=[name for name in arrays if name != "levels"],
                  level_array_names=list(arrays["levels"][0]) if arrays["levels"] else [])
    stored["header"] = np.frombuffer(strict_json.dumps(header).encode("utf-8"), np.uint8)
    buffer = BytesIO()
    np.savez_compressed(buffer, **stored)
    return buffer.getvalue()


def unpack(data, where="packed LoD asset"):
    """The LodAsset of pack()'s bytes; raises ValueError naming `where` and the problem."""
    try:
        with np.load(BytesIO(bytes(data)), allow_pickle=False) as archive:
            stored = {name: archive[name] for name in archive.files}
        header = stored.pop("header").tobytes()
    except _NPY_ERRORS as error:
        # A damaged pack fails anywhere in the zip and .npy readers, each with its own exception.
        raise ValueError(f"{where}: not a packed hairlod LoD asset ({type(error).__name__}: {error})") from None
    header = strict_json.loads(header, f"{where} (header)")

    def read(name, _):
        if name not in stored:
            raise ValueError(f"{where}: array {name} is missing")
        return stored[name]

    return _asset_from(header, read, where)
