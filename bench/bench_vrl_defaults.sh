#!/bin/sh
# Light-path defaults of vrl and vbl at equal time (issue #13, goal "defaults that finish").
# For each scene (128x128 copies of samples/cloud.json and bench/scenes/cloud_dense.json, made by
# the caller: see docs/readme/vrl.md "Light paths per pass") and each configuration, renders for T seconds
# (--passes 100000 --time-limit T; the first pass always completes, so secs, the time of the
# passes kept, is printed too) and prints the rMAE of the
# beauty and of volume_from_volume against a long pt reference, the passes done and the energy
# (sum of the non-emission layers' means / the reference's).
# The reference must come from another seed than 7 (pt here runs with --seed 7).
# usage: bench_vrl_defaults.sh VBL_BINARY T SCENE_NAME SCENE.json REF.exr [SCENE_NAME SCENE.json REF.exr ...]
set -eu
VBL=$1 T=$2
shift 2
OUT=${TMPDIR:-/tmp}/bench_vrl_defaults.$$
mkdir -p "$OUT"
printf '%-6s %-4s %-40s %6s %6s %8s %8s %7s\n' scene meth config passes secs rMAE vfv_rMAE energy
while [ $# -ge 3 ]; do
  name=$1 scene=$2 ref=$3
  shift 3
  for cfg in "vrl --light-paths 3" "vrl --light-paths 10" "vrl --light-paths 30" \
             "vrl --light-paths 10 --transmittance-majorant-scale 4" \
             "vbl --light-paths 3" "vbl --light-paths 10" "vbl --light-paths 30" \
             "vbl --light-paths 10 --transmittance-majorant-scale 4" \
             "pt --seed 7"; do
    m=${cfg%% *}
    rest=${cfg#"$m"}
    img="$OUT/img.exr"
    # shellcheck disable=SC2086
    "$VBL" render "$scene" --method $m $rest --passes 100000 --time-limit "$T" -o "$img" >"$OUT/log" 2>&1
    passes=$(grep -c 'pass [0-9]*/' "$OUT/log" || true)
    secs=$(sed -n 's/.*(total \([0-9.]*\) s.*/\1/p' "$OUT/log" | tail -1)
    j=$("$VBL" diff "$img" "$ref" --json)
    k=$("$VBL" diff "$ref" "$img" --json)
    python3 - "$name" "$m" "$rest" "$passes" "$secs" "$j" "$k" <<'P'
import json, sys
name, m, rest, passes, secs, j, k = sys.argv[1:]
a = {l["name"]: l for l in json.loads(j)["layers"]}
b = {l["name"]: l for l in json.loads(k)["layers"]}
vol = [n for n in a if n not in ("", "emission")]
energy = sum(b[n]["mean_abs_reference"] for n in vol) / sum(a[n]["mean_abs_reference"] for n in vol)
print("%-6s %-4s %-40s %6s %6s %8.3f %8.3f %7.3f" % (name, m, rest.strip() or "-", passes, secs, a[""]["rmae"],
      a["volume_from_volume"]["rmae"], energy))
P
  done
done
rm -rf "$OUT"
