#!/bin/sh
# Issue 13 (session 6, vlclass): virtual-light defaults and scene classes at equal CPU time.
# Each job renders bench/scenes/race_SCENE.json at RES on one thread with a fixed pass count into
# OUT/SCENE.CONFIG.SEED.exr, with its user+sys CPU seconds in OUT/SCENE.CONFIG.SEED.time.
# bench/vlclass_summary.py then scores them with `vbl diff` against REF/SCENE.exr (long pt renders)
# at equal CPU: rMAE x sqrt(cpu_s), lower wins.
# usage: bench/vlclass_defaults.sh VBL RES JOBS OUT [PARALLEL]
#   JOBS: one job a line: "SCENE CONFIG_NAME PASSES SEED ARGS..." (ARGS: vbl render flags)
set -eu
VBL=$1 RES=$2 JOBS=$3 OUT=$4 PAR=${5:-2}
export VBL RES OUT
mkdir -p "$OUT"
grep -v '^#' "$JOBS" | grep . | xargs -P "$PAR" -L1 sh -c '
  sc=$0 name=$1 passes=$2 seed=$3; shift 3
  img=$OUT/$sc.$name.$seed.exr
  echo "$sc $name $passes $seed $*" > "$img.cmd"
  /usr/bin/time -f "%U %S" -o "$img.time" "$VBL" render "bench/scenes/race_$sc.json" --resolution "$RES" \
    --threads 1 --passes "$passes" --seed "$seed" -q -o "$img" "$@" >"$img.log" 2>&1 || echo "$sc $name $seed FAILED"
'
