#!/usr/bin/env bash
# Runs samples/demo.sh into a temporary folder and checks its outputs. usage: run_demo.sh DEMO BUILD
set -euo pipefail
out=$(mktemp -d "${TMPDIR:-/tmp}/vbl-demo-XXXXXX")
trap 'rm -rf "$out"' EXIT
bash "$1" "$2" "$out"
test -s "$out/cloud.exr"
test -s "$out/cloud.png"
"$2/bin/vbl" preview "$out/cloud.exr" -o "$out/check.png"
echo "demo ok"
