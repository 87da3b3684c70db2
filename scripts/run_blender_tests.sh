#!/bin/sh
# Runs each tests/blender/test_*.py in its own headless Blender (pytest inside Blender's Python),
# prints a summary and fails if any file fails. BLENDER overrides the binary; extra arguments go
# to pytest (e.g. -k round_trip).
set -u
cd "$(dirname "$0")/.."
BLENDER=${BLENDER:-blender}
command -v "$BLENDER" >/dev/null || { echo "run_blender_tests.sh: '$BLENDER' not found (apt-get install blender)" >&2; exit 2; }

# Blender writes temporary files; keep them out of the shared /tmp and remove them afterwards.
TMPDIR=$(mktemp -d) && export TMPDIR
trap 'rm -rf "$TMPDIR"' EXIT

failed=""
passed=0
for test_file in tests/blender/test_*.py; do
    echo "== $test_file"
    if "$BLENDER" -b --factory-startup --python-exit-code 1 \
        --python tests/blender/pytest_main.py -- -q "$test_file" "$@"; then
        passed=$((passed + 1))
    else
        failed="$failed $test_file"
    fi
done

if [ -n "$failed" ]; then
    echo "blender tests: $passed file(s) passed, FAILED:$failed"
    exit 1
fi
echo "blender tests: all $passed file(s) passed"
