#!/bin/sh
# Issue 14 item 5 (helper dda): old vs new tracking core in ONE run, interleaved, CPU time.
# Usage: bench/dda_compare.sh OLD_BUILD_DIR NEW_BUILD_DIR [ROUNDS]
#   *_BUILD_DIR/bench/bench_volume and *_BUILD_DIR/bin/vbl of the two binaries (same scenes).
# Prints bench_volume --gap tables (old, new, new with coarse merging) per round, then pt CPU
# seconds (user+sys, 1 thread) per scene/seed for old and new and the vbl diff of the two images.
set -eu
OLD=$1
NEW=$2
ROUNDS=${3:-3}
HERE=$(cd "$(dirname "$0")" && pwd)
TMP=${TMPDIR:-/tmp}/dda_compare.$$
mkdir -p "$TMP"
echo "# $(date -u) load: $(uptime)"
r=1
while [ "$r" -le "$ROUNDS" ]; do
    echo "== round $r: old"
    "$OLD/bench/bench_volume" "$NEW/samples/cloud.vdb" --gap
    echo "== round $r: new (default)"
    "$NEW/bench/bench_volume" "$NEW/samples/cloud.vdb" --gap
    r=$((r + 1))
done
echo "== new, coarse merging by optical depth 0.5"
"$NEW/bench/bench_volume" "$NEW/samples/cloud.vdb" --gap --coarse-depth 0.5
echo "== new, coarse merging by spread 1.5"
"$NEW/bench/bench_volume" "$NEW/samples/cloud.vdb" --gap --coarse-ratio 1.5
echo "# pt: 128x128, 4 passes x 4 spp, 1 thread; cpu = user + sys seconds"
echo "| scene | seed | old cpu s | new cpu s | new/old | image diff (beauty rMAE) |"
echo "|---|---|---|---|---|---|"
for scene in race_cloud race_cloud_dense smoky_lambert_room; do
    for seed in 1 2; do
        for which in old new; do
            B=$OLD
            [ "$which" = new ] && B=$NEW
            /usr/bin/time -f "%U %S" -o "$TMP/$which.time" "$B/bin/vbl" render "$HERE/scenes/$scene.json" \
                -o "$TMP/$which.exr" --resolution 128x128 --passes 4 --spp 4 --threads 1 --seed "$seed" >/dev/null 2>&1
        done
        to=$(awk '{print $1 + $2}' "$TMP/old.time")
        tn=$(awk '{print $1 + $2}' "$TMP/new.time")
        d=$("$NEW/bin/vbl" diff "$TMP/new.exr" "$TMP/old.exr" --layer beauty | awk '/^beauty/ {print $4; exit}')
        echo "| $scene | $seed | $to | $tn | $(awk -v a="$to" -v b="$tn" 'BEGIN{printf "%.3f", b / a}') | $d |"
    done
done
echo "# $(date -u) load: $(uptime)"
rm -rf "$TMP"
