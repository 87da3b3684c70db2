# Sourced by scripts/run_blender_tests.sh and scripts/run_ui_tests.sh, whose $0 puts the working
# folder at the repository root. blender_test_env RUNNER PACKAGES [TOOL ...] checks BLENDER
# (overridable) and the tools, naming the Debian packages that bring them, and gives the runner a
# private TMPDIR (Blender writes temporary files; they stay out of the shared /tmp and go when the
# runner exits).
set -u
cd "$(dirname "$0")/.."
BLENDER=${BLENDER:-blender}

blender_test_env() {
    runner=$1 packages=$2
    shift 2
    for tool in "$BLENDER" "$@"; do
        command -v "$tool" >/dev/null || { echo "$runner: '$tool' not found (apt-get install $packages)" >&2; exit 2; }
    done
    TMPDIR=$(mktemp -d) && export TMPDIR
    trap 'rm -rf "$TMPDIR"' EXIT
}
