#!/bin/sh
# Runs each tests/blender/test_*.py in its own headless Blender (pytest inside Blender's Python),
# prints a summary and fails if any file fails. BLENDER overrides the binary; extra arguments go
# to pytest (e.g. -k round_trip).
. "$(dirname "$0")/blender_test_env.sh"
blender_test_env run_blender_tests.sh blender

summary=""
failed=0
for test_file in tests/blender/test_*.py; do
    echo "== $test_file"
    "$BLENDER" -b --factory-startup --python-exit-code 1 \
        --python tests/blender/pytest_main.py -- -q -rs "$test_file" "$@" >"$TMPDIR/log" 2>&1
    status=$?
    cat "$TMPDIR/log"
    # pytest's last line counts the tests ("9 passed in 0.20s"); a crash leaves none.
    counts=$(grep -E '^=* ?([0-9]+ (passed|failed|error|deselected)|no tests ran)' "$TMPDIR/log" | tail -n 1 | tr -d '=')
    # Status 5 is pytest's "no tests selected" (a -k filter that matches nothing in this file).
    [ "$status" -eq 0 ] || [ "$status" -eq 5 ] || failed=$((failed + 1))
    summary="$summary
  $test_file: ${counts:-no pytest summary} (exit $status)"
done

echo "blender tests:$summary"
if [ "$failed" -ne 0 ]; then
    echo "blender tests: $failed file(s) FAILED"
    exit 1
fi
echo "blender tests: all passed"
