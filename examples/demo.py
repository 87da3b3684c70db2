"""The main job on the bundled default input: read examples/data/bob.hair and summarise it.

`make demo` runs this. Later stages of the pipeline (hair-mesh generation, LoD, bake, preview)
extend it as they land.
"""

import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "addon"))

from hairlod import io  # noqa: E402
from hairlod.cli import strand_summary  # noqa: E402

DEFAULT_INPUT = REPO / "examples" / "data" / "bob.hair"


def main():
    path = Path(sys.argv[1]) if len(sys.argv) > 1 else DEFAULT_INPUT
    start = time.perf_counter()
    strands = io.read(path)
    read_seconds = time.perf_counter() - start
    summary = strand_summary(strands)
    per_strand = summary["points_per_strand"]
    print(f"hairlod demo: {path.relative_to(REPO) if path.is_relative_to(REPO) else path}")
    print(f"  {summary['strands']} strands, {summary['points']} points "
          f"({per_strand['min']}-{per_strand['max']} per strand), total length {summary['total_length']:.1f}")
    print("  bounding box  min ({:.1f}, {:.1f}, {:.1f})  max ({:.1f}, {:.1f}, {:.1f})".format(
        *summary["bounding_box"]["min"], *summary["bounding_box"]["max"]))
    start = time.perf_counter()
    resampled = strands.resampled(16)
    resample_seconds = time.perf_counter() - start
    print(f"  read in {read_seconds * 1e3:.1f} ms; resampled to {resampled.point_count // len(resampled)} "
          f"points per strand along Catmull-Rom curves in {resample_seconds * 1e3:.1f} ms")


if __name__ == "__main__":
    main()
