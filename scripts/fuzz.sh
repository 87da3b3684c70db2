#!/usr/bin/env bash
# Builds the libFuzzer targets in build-fuzz/ (clang, ASan + UBSan) and runs one of them.
#
#   scripts/fuzz.sh <target> [seconds=60] [extra libFuzzer flags...]
#   targets: cyhair usc_data ct2hair_bin ply_hair tfx
#
# The corpus lives in fuzz-corpus/<target>/ (git-ignored) and is seeded by make_fuzz_seeds.py;
# crashes are written to fuzz-corpus/artifacts/<target>/.
set -euo pipefail

target=${1:?usage: scripts/fuzz.sh <cyhair|usc_data|ct2hair_bin|ply_hair|tfx> [seconds] [flags...]}
seconds=${2:-60}
shift $(( $# >= 2 ? 2 : 1 ))
root=$(cd "$(dirname "$0")/.." && pwd)
cxx=${HAIRLOD_FUZZ_CXX:-$(command -v clang++ || command -v clang++-14)}

cmake -S "$root" -B "$root/build-fuzz" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_CXX_COMPILER="$cxx" -DHAIRLOD_BUILD_FUZZERS=ON -DHAIRLOD_BUILD_PYTHON=OFF \
    -DHAIRLOD_BUILD_TESTS=OFF -DHAIRLOD_BUILD_BENCH=OFF > /dev/null
cmake --build "$root/build-fuzz" --target "fuzz_$target" -j 2

corpus="$root/fuzz-corpus/$target"
artifacts="$root/fuzz-corpus/artifacts/$target"
[ -d "$corpus" ] || python3 "$root/scripts/make_fuzz_seeds.py" "$root" > /dev/null
mkdir -p "$artifacts"
dictionary=()
[ -f "$root/cpp/fuzz/$target.dict" ] && dictionary=(-dict="$root/cpp/fuzz/$target.dict")

exec "$root/build-fuzz/cpp/fuzz/fuzz_$target" "$corpus" -max_total_time="$seconds" \
    -rss_limit_mb=2048 -max_len=65536 -artifact_prefix="$artifacts/" -print_final_stats=1 \
    "${dictionary[@]}" "$@"
