#!/bin/sh
# usage: run_blender_test.sh SOURCE_DIR BUILD_DIR [SCRIPT (default test_blender_addon.py)]; exits 77 (skipped) without blender or numpy.
set -eu
blender=${BLENDER:-blender}
if ! command -v "$blender" >/dev/null 2>&1; then
  echo "test_blender_addon: SKIPPED: blender is not installed (apt-get install blender; ./setup.sh test installs it)"
  exit 77
fi
exec "$blender" -b --factory-startup --python-exit-code 1 --python "$1/tests/blender/${3:-test_blender_addon.py}" -- "$1" "$2"
