"""Hair LoD assets: guides, L0 clusters, thick elliptical hairs per level, skinning and selection.

Implements hair-lod-aggregated-bcsdf.txt Sec. 5 over the C++ core (no bpy). Arrays are numpy copies.
"""

import json
import os
import shutil
import tempfile
from dataclasses import dataclass

import numpy as np

from . import _core

__all__ = ["LodAsset", "ThickLevel", "build_lod", "load", "read_cameras", "save", "scene_levels"]

MANIFEST = "manifest.json"
FORMAT = "hairlod-lod/2"  # 2: compact cross-sections and strand coordinates, hierarchy order


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

    guide_count = property(lambda self: self._core.guide_count)
    cluster_count = property(lambda self: self._core.cluster_count)
    strand_count = property(lambda self: self._core.strand_count)
    control_points = property(lambda self: self._core.control_points)
    guide_strands = property(lambda self: self._core.guide_strands)
    rest_guides = property(lambda self: self._core.rest_guides)
    cluster_guides = property(lambda self: self._core.cluster_guides)
    timings = property(lambda self: dict(self._timings))  # build seconds per stage
    memory_bytes = property(lambda self: self._core.memory_bytes)

    @property
    def coverage(self):
        """Coverage per thick level (target >= 0.95)."""
        return [level.coverage for level in self.levels]

    @property
    def area_ratios(self):
        """Mean cross-section area of each level over the next finer one (about 4 by design)."""
        return [coarse.mean_area / fine.mean_area for coarse, fine in zip(self.levels, self.levels[1:])]

    def arrays(self):
        """Every stored array by name, flat [n] or [n, components]; 'levels' holds one dict per thick level."""
        return self._core.arrays()

    def scalars(self):
        """control_points, radius_exponent, coverage and mean_area per thick level."""
        return self._core.scalars()

    def with_levels(self, kept):
        """A copy keeping only the thick levels at positions `kept` (sorted); each kept level's parent
        points to the next kept coarser level (composed through dropped ones), -1 on the first."""
        kept = sorted(set(kept))
        if not kept or kept[0] < 0 or kept[-1] >= len(self.levels):
            raise ValueError(f"levels to keep must be a non-empty subset of 0..{len(self.levels) - 1}")
        arrays, scalars = self.arrays(), self.scalars()
        levels = arrays["levels"]
        for previous, level in zip([None] + kept, kept):
            parent = np.full(len(levels[level]["parent"]), -1, np.int32)
            if previous is not None:
                parent = levels[level]["parent"]
                for between in range(level - 1, previous, -1):
                    parent = levels[between]["parent"][parent]
            levels[level] = dict(levels[level], parent=parent.astype(np.int32))
        arrays["levels"] = [levels[level] for level in kept]
        scalars["coverage"] = [scalars["coverage"][level] for level in kept]
        scalars["mean_area"] = [scalars["mean_area"][level] for level in kept]
        return LodAsset(_core.LodAsset.from_arrays(scalars, arrays), [self.level_ids[level] for level in kept],
                        self.timings)

    def skin(self, deformed_guides):
        """Strands and thick hairs for guides [G, n_c, 3]: dict with 'strands' (Strands), 'levels'
        (centres, tangents, major/minor semi-axes, corners) and 'cluster_bounds' [C, 4]."""
        return self._core.skin(np.asarray(deformed_guides, dtype=np.float32))

    def select(self, view, projection, viewport_size, width_px=2.0, previous=None, guides=None):
        """LoD selection from column-major-convention 4x4 matrices (numpy rows are matrix rows,
        as Blender's Matrix converts): the initial selection, or Eq. 16 from `previous`."""
        guides = self.rest_guides if guides is None else np.asarray(guides, dtype=np.float32)
        return self._core.select(guides, np.asarray(view, dtype=np.float32), np.asarray(projection, dtype=np.float32),
                                 tuple(float(v) for v in viewport_size), float(width_px), previous)

    def view_selection(self, guides=None):
        """Per-view selection state for drawing (initial selection, then one Eq. 16 step per
        update), on the rest pose or the skinned guides [G, n_c, 3]."""
        guides = self.rest_guides if guides is None else np.asarray(guides, dtype=np.float32)
        return _core.ViewSelection(self._core, guides)


def strand_bytes(strands):
    """Bytes of the strand data an asset's memory is compared with: points, radius, offsets."""
    return strands.points.nbytes + strands.radius.nbytes + strands.offsets.nbytes


def level_report(asset):
    """Per thick level: its id, hairs, coverage and mean cross-section area, as plain Python."""
    return [{"level": level_id, "hairs": int(len(level.n_total)), "coverage": level.coverage,
             "mean_area": level.mean_area}
            for level_id, level in zip(asset.level_ids, asset.levels)]


def build_lod(strands, guides=256, levels=6, control_points=16, seed=0, ellipse_coverage=0.95):
    """Builds an LodAsset from Strands (Sec. 5.1); raises ValueError on invalid input."""
    return LodAsset(_core.build_lod(strands, guides=guides, levels=levels, control_points=control_points,
                                    seed=seed, ellipse_coverage=ellipse_coverage))


def read_cameras(path):
    """Cameras from JSON: a list of {"view": 4x4, "projection": 4x4, "viewport": [width, height]}
    (numpy row order, as Blender's Matrix). Raises ValueError naming the file and the problem."""
    try:
        with open(path, encoding="utf-8") as file:
            entries = json.load(file)
    except json.JSONDecodeError as error:
        raise ValueError(f"{path}: not JSON ({error})") from None
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


def scene_levels(asset, cameras, width_px=2.0):
    """Levels (0 = L0 .. len(asset.levels) = the strands) that the initial selection (Sec. 5.1 step 5)
    of some camera picks for some visible segment, at the rest pose."""
    used = set()
    for camera in cameras:
        selection = asset.select(camera["view"], camera["projection"], camera["viewport"], width_px)
        used.update(int(level) for level in np.unique(selection.levels[selection.visible]))
    return sorted(used)


def _level_strands(asset, level):
    """Thick hairs of one level as Strands: rest centre curves, radius = major radius (.hair
    thickness = 2 x major radius)."""
    hairs, nc = level.centres.shape[:2]
    return _core.Strands.from_counts(level.centres.reshape(-1, 3), np.full(hairs, nc, np.int64),
                                     np.ascontiguousarray(level.radii[..., 0].reshape(-1)))


def _write_array(folder, name, array, entries):
    file_name = f"{name}.npy"
    np.save(os.path.join(folder, file_name), np.ascontiguousarray(array), allow_pickle=False)
    entries[name] = {"file": file_name, "dtype": str(array.dtype), "shape": list(array.shape)}


def save(asset, directory, extra=None):
    """Writes `asset` into folder `directory` atomically (a temporary sibling folder renamed when
    complete; an existing folder is replaced): manifest.json, one .npy per stored array and one
    .hair per thick level (thickness = 2 x major radius). `extra` (JSON-able dict) is stored in the
    manifest under "extra". Returns the manifest."""
    from . import io

    directory = os.path.abspath(os.fspath(directory))
    parent = os.path.dirname(directory)
    os.makedirs(parent, exist_ok=True)
    temporary = tempfile.mkdtemp(prefix=f".{os.path.basename(directory)}.", dir=parent)
    try:
        arrays, scalars = asset.arrays(), asset.scalars()
        entries = {}
        for name, array in arrays.items():
            if name != "levels":
                _write_array(temporary, name, array, entries)
        levels = []
        for position, (level, level_arrays) in enumerate(zip(asset.levels, arrays["levels"])):
            level_entries = {}
            for name, array in level_arrays.items():
                _write_array(temporary, f"level{position}_{name}", array, level_entries)
            hair_file = f"level{position}.hair"
            io.write(os.path.join(temporary, hair_file), _level_strands(asset, level))
            levels.append({
                "level": asset.level_ids[position],
                "hairs": int(len(level.n_total)),
                "hair_file": hair_file,
                "coverage": scalars["coverage"][position],
                "mean_area": scalars["mean_area"][position],
                # The cluster tree and per-hair data live in these arrays: parent (hair one kept level
                # coarser), member_first (hair h holds the strands at positions [member_first[h],
                # member_first[h + 1]) of strand_order), cluster_first, and the compact cross-sections
                # centre_offset (uint16 in offset_boxes), major_axis (octahedral int16), minor_axis
                # (uint16 angle about the major axis), radii (halves x 2^radius_exponent). Density is
                # derived: rho = n_total r^2 / (|r_A| |r_B|).
                "arrays": level_entries,
            })
        manifest = {
            "format": FORMAT,
            "control_points": scalars["control_points"],
            "radius_exponent": scalars["radius_exponent"],
            "strands": asset.strand_count,
            "guides": asset.guide_count,
            "clusters": asset.cluster_count,
            "thick_levels": levels,
            "area_ratios": [levels[i]["mean_area"] / levels[i + 1]["mean_area"] for i in range(len(levels) - 1)],
            "timings": asset.timings,
            "memory_bytes": asset.memory_bytes,
            "arrays": entries,
            "extra": extra or {},
        }
        with open(os.path.join(temporary, MANIFEST), "w", encoding="utf-8") as file:
            json.dump(manifest, file, indent=1)
        if os.path.exists(directory):
            retired = tempfile.mkdtemp(prefix=f".{os.path.basename(directory)}.old.", dir=parent)
            os.rename(directory, os.path.join(retired, "asset"))
            os.rename(temporary, directory)
            shutil.rmtree(retired, ignore_errors=True)
        else:
            os.rename(temporary, directory)
    except BaseException:
        shutil.rmtree(temporary, ignore_errors=True)
        raise
    return manifest


def _read_array(folder, entry, what):
    try:
        path = os.path.join(folder, os.path.basename(entry["file"]))
        array = np.load(path, allow_pickle=False)
    except (KeyError, TypeError) as error:
        raise ValueError(f"{folder}: manifest entry for {what} is malformed ({error})") from None
    except (OSError, ValueError) as error:
        raise ValueError(f"{folder}: cannot read {what} ({error})") from None
    if list(array.shape) != list(entry.get("shape", [])) or str(array.dtype) != entry.get("dtype"):
        raise ValueError(f"{folder}: {what} does not match its manifest shape/dtype")
    return array


def load(directory):
    """Reads a folder written by save() back into an identical LodAsset; raises ValueError naming
    the folder and the problem."""
    directory = os.fspath(directory)
    try:
        with open(os.path.join(directory, MANIFEST), encoding="utf-8") as file:
            manifest = json.load(file)
    except OSError as error:
        raise ValueError(f"{directory}: no readable {MANIFEST} ({error.strerror})") from None
    except json.JSONDecodeError as error:
        raise ValueError(f"{directory}: {MANIFEST} is not JSON ({error})") from None
    if not isinstance(manifest, dict) or manifest.get("format") != FORMAT:
        raise ValueError(f"{directory}: not a hairlod LoD folder (format must be {FORMAT})")
    try:
        arrays = {name: _read_array(directory, entry, name) for name, entry in manifest["arrays"].items()}
        levels = manifest["thick_levels"]
        arrays["levels"] = [{name.split("_", 1)[1]: _read_array(directory, entry, name)
                             for name, entry in level["arrays"].items()} for level in levels]
        scalars = {"control_points": int(manifest["control_points"]),
                   "radius_exponent": int(manifest["radius_exponent"]),
                   "coverage": [float(level["coverage"]) for level in levels],
                   "mean_area": [float(level["mean_area"]) for level in levels]}
        level_ids = [int(level["level"]) for level in levels]
        timings = {str(stage): float(seconds) for stage, seconds in manifest["timings"].items()}
    except (KeyError, TypeError, AttributeError, IndexError) as error:
        raise ValueError(f"{directory}: {MANIFEST} is missing or malforms an entry ({error})") from None
    try:
        return LodAsset(_core.LodAsset.from_arrays(scalars, arrays), level_ids, timings)
    except ValueError as error:
        raise ValueError(f"{directory}: {error}") from None
