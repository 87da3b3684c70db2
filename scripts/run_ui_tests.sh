#!/bin/sh
# Runs each tests/ui/test_*.py in a real Blender window under Xvfb, prints a summary and fails if
# any fails. Screenshots land in $HAIRLOD_UI_OUT (default out/ui). BLENDER overrides the binary.
. "$(dirname "$0")/blender_test_env.sh"
blender_test_env run_ui_tests.sh "blender xvfb" xvfb-run
HAIRLOD_UI_OUT=${HAIRLOD_UI_OUT:-$PWD/out/ui} && export HAIRLOD_UI_OUT

failed=""
passed=0
for test_file in tests/ui/test_*.py; do
    echo "== $test_file"
    # The scripts end Blender with their own exit status; timeout guards against a hung window.
    if timeout 300 xvfb-run -a -s '-screen 0 1280x720x24' \
        "$BLENDER" --factory-startup --enable-event-simulate --python "$test_file"; then
        passed=$((passed + 1))
    else
        failed="$failed $test_file"
    fi
done

if [ -n "$failed" ]; then
    echo "ui tests: $passed passed, FAILED:$failed (screenshots in $HAIRLOD_UI_OUT)"
    exit 1
fi
echo "ui tests: all $passed passed (screenshots in $HAIRLOD_UI_OUT)"
