#!/bin/sh
# vrl/vbl settings at equal CPU time (issue #13: light paths per pass, transmittance_majorant_scale
# of the connections): each configuration renders a fixed number of passes on one thread, and
# the line gives the user CPU
# seconds, the rMAE of the beauty and of volume_from_volume against a long pt reference, and the
# efficiency 1 / (rMAE^2 x seconds) of volume_from_volume (higher wins; equal-time error ratio =
# sqrt of the efficiency ratio).
# usage: [CONFIGS="vrl --light-paths 3;vbl --light-paths 3"] bench_vrl_efficiency.sh VBL_BINARY PASSES
#        SCENE_NAME SCENE.json REF.exr [...]   (CONFIGS: ';'-separated; default: the majorant scales)
set -eu
VBL=$1 P=$2
shift 2
OUT=${TMPDIR:-/tmp}/bench_vrl_efficiency.$$
CONFIGS=${CONFIGS:-"vrl --light-paths 10;vrl --light-paths 10 --transmittance-majorant-scale 2;\
vrl --light-paths 10 --transmittance-majorant-scale 4;vbl --light-paths 10;\
vbl --light-paths 10 --transmittance-majorant-scale 2;vbl --light-paths 10 --transmittance-majorant-scale 4"}
mkdir -p "$OUT"
printf '%-6s %-4s %-40s %7s %8s %8s %9s\n' scene meth config cpu_s rMAE vfv_rMAE vfv_eff
while [ $# -ge 3 ]; do
  name=$1 scene=$2 ref=$3
  shift 3
  old_ifs=$IFS
  IFS=';'
  set -f
  for cfg in $CONFIGS; do
    IFS=$old_ifs
    m=${cfg%% *}
    rest=${cfg#"$m"}
    img="$OUT/img.exr"
    # shellcheck disable=SC2086
    /usr/bin/time -f '%U' -o "$OUT/time" "$VBL" render "$scene" --method $m $rest --passes "$P" --threads 1 -q \
      -o "$img" >"$OUT/log" 2>&1
    j=$("$VBL" diff "$img" "$ref" --json)
    python3 - "$name" "$m" "$rest" "$(tail -1 "$OUT/time")" "$j" <<'P'
import json, sys
name, m, rest, cpu, j = sys.argv[1:]
a = {l["name"]: l for l in json.loads(j)["layers"]}
cpu = float(cpu)
e = a["volume_from_volume"]["rmae"]
print("%-6s %-4s %-40s %7.1f %8.3f %8.3f %9.4f" % (name, m, rest.strip(), cpu, a[""]["rmae"], e, 1.0 / (e * e * cpu)))
P
  done
  IFS=$old_ifs
  set +f
done
rm -rf "$OUT"
