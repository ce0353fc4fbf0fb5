#!/usr/bin/env bash
# The README demo: describe the sample cloud, render it with virtual ray lights to a multi-layer
# EXR and a PNG preview (a quick, noisy render: raise --passes/--light-paths for quality).
# usage: samples/demo.sh BUILD_DIR OUT_DIR   (under a minute on 2 cores)
set -euo pipefail
if [ $# -ne 2 ]; then
  echo "usage: $0 BUILD_DIR OUT_DIR" >&2
  exit 2
fi
build="$1"; out="$2"
here="$(cd "$(dirname "$0")" && pwd)"
vbl="$build/bin/vbl"
cloud="$build/samples/cloud.vdb"
for f in "$vbl" "$cloud"; do
  if [ ! -e "$f" ]; then
    echo "demo: $f is missing: build first (cmake --build $build)" >&2
    exit 3
  fi
done
mkdir -p "$out"
"$vbl" --version
echo "== vbl info $cloud"
"$vbl" info "$cloud"
echo "== vbl render (vrl) -> $out/cloud.exr, $out/cloud.png"
"$vbl" render "$here/cloud.json" --vdb "$cloud" --method vrl --passes 6 --spp 1 --light-paths 200 \
  --aov all -o "$out/cloud.exr" --preview "$out/cloud.png"
echo "demo: wrote $out/cloud.exr and $out/cloud.png"
