#!/bin/sh
# bench/ptprof/profile.sh DIR TAG: perf record (no call graph) of `vbl render` with pt defaults,
# 64x64, 16 passes x 4 spp, 1 thread, on race_cloud, race_cloud_dense, race_room; DIR holds vbl
# and libvbl.so. Writes /tmp/ptprof/prof_TAG_SCENE.txt (perf report --no-children, by symbol).
D=$1; TAG=$2
for sc in race_cloud race_cloud_dense race_room; do
    LD_LIBRARY_PATH=$D perf record -F 1999 -o /tmp/ptprof/prof_${TAG}_$sc.data $D/vbl render bench/scenes/$sc.json \
        -o /tmp/ptprof/prof.exr -q --resolution 64x64 --threads 1 --passes 16 --spp 4 >/dev/null 2>&1
    perf report -i /tmp/ptprof/prof_${TAG}_$sc.data --no-children --stdio --sort symbol 2>/dev/null | grep -E "^ +[0-9]" \
        > /tmp/ptprof/prof_${TAG}_$sc.txt
done
