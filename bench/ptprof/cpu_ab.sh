#!/bin/sh
# bench/ptprof/cpu_ab.sh OLD_DIR NEW_DIR REPS [RES] [PASSES]: process CPU time (user+sys) of
# `vbl render` with pt defaults, 1 thread, old and new binaries interleaved (ABAB) on the race
# scenes; each DIR holds `vbl` and its libvbl.so (run with LD_LIBRARY_PATH=DIR).
OLD=$1; NEW=$2; REPS=${3:-3}; RES=${4:-64x64}; PASSES=${5:-8}
S=bench/scenes
echo "# $(date -u) $(uptime)"
echo "# scene rep old_cpu_s new_cpu_s new/old  (pt defaults, $RES, $PASSES passes x 4 spp, 1 thread, seed = rep)"
for sc in race_cloud race_cloud_dense race_room race_cloud_ground; do
    for r in $(seq 1 $REPS); do
        for which in old new; do
            D=$OLD; [ $which = new ] && D=$NEW
            LD_LIBRARY_PATH=$D /usr/bin/time -o /tmp/ptprof/ab_time.txt -f "%U %S" $D/vbl render $S/$sc.json \
                -o /tmp/ptprof/ab_$which.exr -q --resolution $RES --threads 1 --passes $PASSES --spp 4 --seed $r >/dev/null 2>&1
            eval "$which=\$(tail -1 /tmp/ptprof/ab_time.txt | awk '{print \$1+\$2}')"
        done
        echo "$sc $r $old $new $(echo $old $new | awk '{printf "%.3f", $2/$1}')"
    done
done
