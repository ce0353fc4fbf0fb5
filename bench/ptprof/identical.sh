#!/bin/sh
# bench/ptprof/identical.sh NEW_VBL [OUTDIR]: renders small images of the race scenes and other
# volume scenes with the baseline binary (/work/base, LD_LIBRARY_PATH) and NEW_VBL, every method
# that shares the volume code, and prints `vbl diff` max abs error per pair (0 = bit-identical).
NEW=${1:-build/bin/vbl}
OUT=${2:-/tmp/ptprof/ident}
BASE=${VBL_BASE:-/work/base}
NEWLIB=$(dirname "$NEW") # a copied binary with its libvbl.so.0 beside it (else its RUNPATH's)
mkdir -p "$OUT"
run() { # name scene args...
    name=$1; scene=$2; shift 2
    LD_LIBRARY_PATH=$BASE $BASE/vbl render "$scene" -o "$OUT/$name.old.exr" -q "$@" >/dev/null 2>&1 || echo "$name: old failed"
    LD_LIBRARY_PATH=$NEWLIB $NEW render "$scene" -o "$OUT/$name.new.exr" -q "$@" >/dev/null 2>&1 || echo "$name: new failed"
    printf '%-28s ' "$name"
    LD_LIBRARY_PATH=$NEWLIB $NEW diff "$OUT/$name.new.exr" "$OUT/$name.old.exr" --json | /usr/bin/python3 -c '
import json,sys
d=json.load(sys.stdin)
L=d.get("layers",d)
m=max((l.get("max_abs",l.get("max_abs_error",0)) for l in (L if isinstance(L,list) else L.values())),default=None)
print("max abs diff over layers:", m, "identical" if m==0 else "DIFFERENT")'
}
S=bench/scenes
for sc in race_cloud race_cloud_dense race_room race_cloud_ground smoky_quad_room_thin race_spot_smoke; do
    run "pt_$sc" $S/$sc.json --resolution 32x32 --passes 2 --spp 2 --threads 2
done
run pt_room_residual_mid $S/race_room.json --resolution 32x32 --passes 2 --spp 2 --pt-shadow-transmittance residual-mid
run pt_cloud_delta $S/race_cloud.json --resolution 32x32 --passes 2 --spp 2 --transmittance delta
run pt_cloud_march $S/race_cloud.json --resolution 32x32 --passes 2 --spp 2 --transmittance march
for m in vrl vbl; do
    run "${m}_room" $S/race_room.json --method $m --resolution 32x32 --passes 2 --spp 2
    run "${m}_cloud" $S/race_cloud.json --method $m --resolution 32x32 --passes 2 --spp 2
done
for m in vpl beams; do
    run "${m}_room" $S/race_room.json --method $m --resolution 24x24 --passes 1 --spp 1 --light-paths 2000
    run "${m}_cloud" $S/race_cloud.json --method $m --resolution 24x24 --passes 1 --spp 1 --light-paths 2000
done
# motion blur (velocity grids, advected lookups), emissive media and albedo grids, if the samples exist
for sc in samples/*.json; do
    [ -f "$sc" ] || continue
    n=$(basename "$sc" .json)
    run "pt_sample_$n" "$sc" --resolution 24x24 --passes 1 --spp 2
done
