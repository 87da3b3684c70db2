#!/bin/sh
# Blender 3.4.1 (this machine) against Blender 4.3.2 (the Debian 13 chroot of scripts/chroot.sh) on the
# same machine in one run: scripts/bench_preview_latency.py in each under Xvfb, the two alternated
# ROUNDS times (default 2) so that load on the shared machine falls on both, then the medians per
# Blender of the LoD build, its export with the bake, the button build and the first preview frame,
# and 4.3 / 3.4. Needs the core built for both (make build; make test-debian13 or DEBIAN13_SUITES=build).
#   scripts/bench_blender_versions.sh [COUNT (default 100000)] [ROUNDS]
set -eu
cd "$(dirname "$0")/.."
count=${1:-100000}
rounds=${2:-2}
out=${HAIRLOD_BENCH_OUT:-out/bench/blender_versions}
mkdir -p "$out"
bench="scripts/bench_preview_latency.py"
window="xvfb-run -a -s '-screen 0 1280x720x24'"
round=1
while [ "$round" -le "$rounds" ]; do
    echo "round $round: Blender 3.4"
    sh -c "$window blender --factory-startup --python $bench -- --count $count --runs 2 --out $out/b34_$round.json" >"$out/b34_$round.log" 2>&1 ||
        { tail -n 30 "$out/b34_$round.log"; exit 1; }
    echo "round $round: Blender 4.3"
    scripts/chroot.sh debian13 run sh -c "$window blender --factory-startup --python $bench -- --count $count --runs 2 --out $out/b43_$round.json" >"$out/b43_$round.log" 2>&1 ||
        { tail -n 30 "$out/b43_$round.log"; exit 1; }
    round=$((round + 1))
done
/usr/bin/python3 - "$out" <<'PY'
import glob, json, os, statistics, sys
out = sys.argv[1]
keys = ["direct_build_s", "export_bake_s", "button_build_s", "first_frame_s"]
runs = {}
for name in ("b34", "b43"):
    results = [json.load(open(path)) for path in sorted(glob.glob(os.path.join(out, name + "_*.json")))]
    runs[name] = {key: statistics.median(run[key] for result in results for run in result["runs"]) for key in keys}
    runs[name]["blender"] = results[0]["blender"]
    runs[name]["n"] = sum(len(result["runs"]) for result in results)
print(f"| step | Blender {runs['b34']['blender']} (median of {runs['b34']['n']}) | Blender {runs['b43']['blender']} (median of {runs['b43']['n']}) | 4.3 / 3.4 |")
print("| --- | --- | --- | --- |")
for key in keys:
    a, b = runs["b34"][key], runs["b43"][key]
    print(f"| {key} | {a:.3f} s | {b:.3f} s | {b / a:.2f} |")
json.dump(runs, open(os.path.join(out, "summary.json"), "w"), indent=1)
PY
