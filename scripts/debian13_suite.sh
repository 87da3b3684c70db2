#!/bin/sh
# The test suites on Debian 13 (Blender 4.3, Python 3.13, Embree 4, TBB 2022, OpenSubdiv 3.6,
# NumPy 2): run inside the debian13 chroot of scripts/chroot.sh, from `make test-debian13`. Builds the core
# for this Python into build-debian13/ (its _core.cpython-313-*.so lands in addon/hairlod beside the
# host's cp311 one; each Python loads its own) and runs the C++, Python, headless-Blender and UI
# suites, then packs the cp313 extension and installs it in Blender 4.3 (package). Arguments name the
# suites to run (default: all of cpp python blender ui package; `build` only builds).
set -eu
cd "$(dirname "$0")/.."
[ -f /etc/debian_version ] && case "$(cat /etc/debian_version)" in 13*|trixie*) ;; *)
    echo "debian13_suite.sh: runs inside the Debian 13 chroot: use 'make test-debian13'" >&2; exit 2 ;; esac

suites=${*:-cpp python blender ui package}
echo "debian13: $(blender --version 2>/dev/null | head -n 1), $(python3 --version), NumPy $(python3 -c 'import numpy; print(numpy.__version__)')"

cmake -S . -B build-debian13 -DCMAKE_BUILD_TYPE=Release -DPython_EXECUTABLE=/usr/bin/python3 \
    -DHAIRLOD_BUILD_BENCH=OFF >/dev/null
cmake --build build-debian13 -j "${JOBS:-2}" >build-debian13/build.log 2>&1 ||
    { tail -n 40 build-debian13/build.log; echo "debian13: build failed (build-debian13/build.log)" >&2; exit 1; }
grep -E 'warning:' build-debian13/build.log || true

# The cp313 extension as an artist gets it: validated by Blender, installed into a fresh user folder,
# then the headless pipeline from the installed copy (tests/packages/blender_extension.py).
check_extension() (
    set -e
    rm -rf build-debian13/packages
    python3 scripts/build_addon.py --output-dir build-debian13/packages
    extension=$(ls build-debian13/packages/hairlod-*-cp313-linux_x64.zip)
    blender --command extension validate "$extension"
    # The cp311 extension built on the host (make test-packages), where present: its manifest and wheel too.
    for host_extension in build/packages/hairlod-*-cp311-linux_x64.zip; do
        [ -f "$host_extension" ] && blender --command extension validate "$host_extension"
    done
    users=$(mktemp -d) work=$(mktemp -d)
    BLENDER_USER_RESOURCES=$users blender --command extension install-file -r user_default -e "$extension"
    BLENDER_USER_RESOURCES=$users blender -b --python-exit-code 1 --python tests/packages/blender_extension.py \
        -- examples/data/bob.hair "$work" >"$work/log" 2>&1 || { tail -n 40 "$work/log"; exit 1; }
    grep '^extension in' "$work/log"
    rm -rf "$users" "$work"
)

failed=""
for suite in $suites; do
    echo "== debian13 $suite"
    case "$suite" in
        cpp) ctest --test-dir build-debian13 --output-on-failure -j "${JOBS:-2}" || failed="$failed cpp" ;;
        python) python3 -m pytest -q -rs -p no:cacheprovider tests/python || failed="$failed python" ;;
        blender) scripts/run_blender_tests.sh || failed="$failed blender" ;;
        ui) HAIRLOD_UI_OUT=${HAIRLOD_UI_OUT:-$PWD/out/ui-debian13} scripts/run_ui_tests.sh || failed="$failed ui" ;;
        package) check_extension || failed="$failed package" ;;
        build) ;;  # the core is built above
        *) echo "debian13_suite.sh: unknown suite '$suite' (cpp python blender ui package)" >&2; exit 2 ;;
    esac
done
if [ -n "$failed" ]; then
    echo "debian13: FAILED:$failed"
    exit 1
fi
echo "debian13: all of '$suites' passed"
