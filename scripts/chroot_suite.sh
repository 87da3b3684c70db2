#!/bin/sh
# The test suites inside a Debian chroot of scripts/chroot.sh, from `make test-debian13` (Debian 13:
# Blender 4.3, Python 3.13, Embree 4, TBB 2022, OpenSubdiv 3.6, NumPy 2) and `make test-sid` (Debian
# unstable: Blender 5.2 LTS, Python 3.14, GCC 16, pybind11 3). Builds the core for the chroot's
# Python into build-<chroot>/ (its _core.cpython-3XY-*.so lands in addon/hairlod beside the host's
# cp311 one; each Python loads its own) and runs the C++, Python, headless-Blender and UI suites,
# then packs the extension for that Python and installs it in that Blender (package). Arguments name
# the suites to run (default: all of cpp python blender ui package; `build` only builds; `core`
# builds the Python module alone, without the C++ tests).
set -eu
cd "$(dirname "$0")/.."
case "$(cat /etc/debian_version 2>/dev/null)" in
    13*|trixie*) chroot=debian13 ;;
    */sid) chroot=sid ;;
    *) echo "chroot_suite.sh: runs inside the debian13 or sid chroot: use 'make test-debian13' or 'make test-sid'" >&2
       exit 2 ;;
esac
build=build-$chroot
python_tag=$(python3 -c 'import sys; print(f"cp{sys.version_info[0]}{sys.version_info[1]}")')

suites=${*:-cpp python blender ui package}
echo "$chroot: $(blender --version 2>/dev/null | head -n 1), $(python3 --version), NumPy $(python3 -c 'import numpy; print(numpy.__version__)')"

# The C++ tests are built only where they run (cpp) or everything is asked for (build).
target="--target _core"
case " $suites " in *" cpp "*|*" build "*) target="" ;; esac
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DPython_EXECUTABLE=/usr/bin/python3 \
    -DHAIRLOD_BUILD_BENCH=OFF >/dev/null
# shellcheck disable=SC2086  # $target is empty or two words
cmake --build "$build" -j "${JOBS:-2}" $target >"$build/build.log" 2>&1 ||
    { tail -n 40 "$build/build.log"; echo "$chroot: build failed ($build/build.log)" >&2; exit 1; }
grep -E 'warning:' "$build/build.log" || true

# The extension as an artist gets it: validated by Blender, installed into a fresh user folder, then
# the headless pipeline from the installed copy (tests/packages/blender_extension.py).
check_extension() (
    set -e
    rm -rf "$build/packages"
    python3 scripts/build_addon.py --output-dir "$build/packages"
    extension=$(ls "$build"/packages/hairlod-*-"$python_tag"-linux_x64.zip)
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
    echo "== $chroot $suite"
    case "$suite" in
        cpp) ctest --test-dir "$build" --output-on-failure -j "${JOBS:-2}" || failed="$failed cpp" ;;
        python) python3 -m pytest -q -rs -p no:cacheprovider tests/python || failed="$failed python" ;;
        blender) scripts/run_blender_tests.sh || failed="$failed blender" ;;
        ui) HAIRLOD_UI_OUT=${HAIRLOD_UI_OUT:-$PWD/out/ui-$chroot} scripts/run_ui_tests.sh || failed="$failed ui" ;;
        package) check_extension || failed="$failed package" ;;
        build|core) ;;  # the core is built above
        *) echo "chroot_suite.sh: unknown suite '$suite' (cpp python blender ui package)" >&2; exit 2 ;;
    esac
done
if [ -n "$failed" ]; then
    echo "$chroot: FAILED:$failed"
    exit 1
fi
echo "$chroot: all of '$suites' passed"
