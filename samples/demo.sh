#!/usr/bin/env bash
# Demo: describe the sample cloud and render it. usage: samples/demo.sh BUILD_DIR OUT_DIR
set -euo pipefail
build="$1"; out="$2"
"$build/bin/vbl" --version
echo "demo: nothing to render yet"
