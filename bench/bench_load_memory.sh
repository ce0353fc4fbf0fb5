#!/bin/sh
# Peak RSS of vbl_volume_load on a large generated grid, .vdb and .nvdb (issue 18: at most 1.5x
# the NanoVDB size). Usage: bench/bench_load_memory.sh [EDGE [BUILD]]; EDGE 530 ~ 79 M voxels.
set -eu
edge=${1:-530}
build=${2:-build}
dir=$(mktemp -d "${TMPDIR:-/tmp}/vbl_bigload.XXXXXX")
trap 'rm -rf "$dir"' EXIT
"$build/bench/bench_make_big_grid" "$dir/ball" "$edge"
ls -l "$dir"
for f in "$dir/ball.nvdb" "$dir/ball.vdb"; do
    /usr/bin/time -f "  wall %e s, max RSS %M KiB" "$build/bench/bench_load_volume" "$f"
done
