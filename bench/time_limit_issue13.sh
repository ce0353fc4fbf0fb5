#!/usr/bin/env bash
# Issue 13 item 5: does `vbl render --time-limit L` end within 10% of L, and SIGINT/SIGTERM within
# 1 s, for every method (and blue-noise VSL placement on a scene with surfaces)?
# usage: bench/time_limit_issue13.sh BUILD_DIR OUT.txt   (128x128, default settings otherwise;
# --passes 1000000 so that the limit, not the pass count, ends the render)
set -euo pipefail
build="$1"; out="$2"
vbl="$build/bin/vbl"
tmp="$(mktemp -d)"; trap 'rm -rf "$tmp"' EXIT
cases=("cloud pt samples/cloud.json --method pt" "cloud vpl samples/cloud.json --method vpl"
       "cloud vrl samples/cloud.json --method vrl" "cloud vbl samples/cloud.json --method vbl"
       "cloud beams samples/cloud.json --method beams"
       "smoky_room vpl+blue_noise samples/smoky_room.json --method vpl --vsl-placement blue_noise")
now() { date +%s.%N; }
{
  echo "# vbl render SCENE --resolution 128x128 --passes 1000000 --time-limit L (wall: whole process, scene load included)"
  echo "# load at start: $(uptime | sed 's/.*load average: //') on $(nproc) cores; $(date -u +%FT%TZ)"
  printf "%-11s %-16s %6s %8s %8s %6s %s\n" scene method limit wall_s cpu_s rc over_limit
  for L in 10 3; do
    for c in "${cases[@]}"; do
      read -r scene method file args <<<"$c"
      t0=$(now)
      set +e
      /usr/bin/time -f "%U %S" -o "$tmp/time" "$vbl" render "$file" $args --resolution 128x128 --passes 1000000 \
        --time-limit "$L" -o "$tmp/out.exr" >/dev/null 2>"$tmp/err"
      rc=$?
      set -e
      t1=$(now)
      read -r u s < <(tail -n 1 "$tmp/time")
      awk -v sc="$scene" -v m="$method" -v L="$L" -v t0="$t0" -v t1="$t1" -v u="$u" -v s="$s" -v rc="$rc" \
        'BEGIN { w = t1 - t0; printf "%-11s %-16s %6d %8.2f %8.2f %6d %+.1f%%\n", sc, m, L, w, u + s, rc, 100 * (w / L - 1) }'
    done
  done
  echo
  echo "# signal latency: the render runs 4 s, then SIGINT or SIGTERM; seconds from the signal to the exit"
  printf "%-11s %-16s %-7s %9s %6s\n" scene method signal latency_s rc
  for sig in INT TERM; do
    for c in "${cases[@]}"; do
      read -r scene method file args <<<"$c"
      "$vbl" render "$file" $args --resolution 128x128 --passes 1000000 -o "$tmp/out.exr" >/dev/null 2>"$tmp/err" &
      pid=$!
      sleep 4
      t0=$(now)
      kill -"$sig" "$pid"
      set +e; wait "$pid"; rc=$?; set -e
      t1=$(now)
      awk -v sc="$scene" -v m="$method" -v sig="$sig" -v t0="$t0" -v t1="$t1" -v rc="$rc" \
        'BEGIN { printf "%-11s %-16s SIG%-4s %9.3f %6d\n", sc, m, sig, t1 - t0, rc }'
    done
  done
  echo "# load at end: $(uptime | sed 's/.*load average: //')"
} | tee "$out"
