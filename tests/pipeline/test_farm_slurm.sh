#!/bin/sh
# Slurm integration test for `vbl farm submit` (issue 7): starts munged, slurmctld and slurmd on
# localhost with their own key, sockets, ports and state in a temporary folder, submits a
# 2-task array render plus its merge job, waits for the merged EXR and compares it with a
# single-process render of the same passes (vbl diff: max error per layer). Every exit path
# stops the daemons it started. Exit 77 (skipped) without root or the Slurm/munge binaries.
# usage: test_farm_slurm.sh VBL_BINARY BOX_VDB
set -u
VBL=$1
BOX=$2
skip() { echo "SKIP: $*"; exit 77; }
[ "$(id -u)" = 0 ] || skip "needs root (slurmd runs jobs as their user; SlurmUser=root here)"
for b in munged mungekey slurmctld slurmd sbatch sinfo squeue scontrol; do
    command -v "$b" >/dev/null 2>&1 || skip "$b not installed (Debian: slurm-wlm, munge)"
done
[ -x "$VBL" ] && [ -f "$BOX" ] || { echo "FAIL: $VBL or $BOX missing"; exit 1; }

T=$(mktemp -d "${TMPDIR:-/tmp}/vbl-slurm-XXXXXX") || exit 1
chmod 755 "$T"
stop_daemons() {
    for f in "$T/slurmd.pid" "$T/slurmctld.pid" "$T/munge/munged.pid"; do
        [ -s "$f" ] && kill "$(cat "$f")" 2>/dev/null
    done
    for p in ${DAEMON_PIDS:-}; do kill "$p" 2>/dev/null; done
    sleep 1
    for p in ${DAEMON_PIDS:-}; do kill -9 "$p" 2>/dev/null; done
}
DAEMON_PIDS=""
cleanup() {
    stop_daemons
    [ "${KEEP:-0}" = 1 ] || rm -rf "$T"
}
trap cleanup EXIT
trap 'exit 1' INT TERM HUP
fail() {
    echo "FAIL: $*"
    for f in "$T"/slurmctld.log "$T"/slurmd.log "$T"/munge/munged.log "$T"/out.exr.farm/*.log; do
        [ -f "$f" ] && { echo "---- $f"; tail -n 30 "$f"; }
    done
    exit 1
}

# munge: its own key and socket
mkdir -m 700 "$T/munge"
mungekey -c -k "$T/munge/munge.key" >/dev/null 2>&1 || dd if=/dev/urandom of="$T/munge/munge.key" bs=1024 count=1 2>/dev/null
chmod 600 "$T/munge/munge.key"
munged --foreground --force --key-file="$T/munge/munge.key" --socket="$T/munge/munge.sock" \
    --pid-file="$T/munge/munged.pid" --log-file="$T/munge/munged.log" --seed-file="$T/munge/munged.seed" \
    >"$T/munge/munged.out" 2>&1 &
DAEMON_PIDS="$!"
for i in $(seq 50); do [ -S "$T/munge/munge.sock" ] && break; sleep 0.1; done
[ -S "$T/munge/munge.sock" ] || fail "munged did not start"

# slurm.conf for this host, ports picked from the PID so parallel runs do not collide
HOST=$(hostname -s)
PORT=$((20000 + ($$ % 2000) * 2))
mkdir -p "$T/state" "$T/spool"
cat > "$T/slurm.conf" <<CONF
ClusterName=vbltest
SlurmctldHost=$HOST(127.0.0.1)
SlurmctldPort=$PORT
SlurmdPort=$((PORT + 1))
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$T/munge/munge.sock
StateSaveLocation=$T/state
SlurmdSpoolDir=$T/spool
SlurmctldPidFile=$T/slurmctld.pid
SlurmdPidFile=$T/slurmd.pid
SlurmctldLogFile=$T/slurmctld.log
SlurmdLogFile=$T/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/builtin
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
JobCompType=jobcomp/none
MpiDefault=none
ReturnToService=2
SlurmdTimeout=60
NodeName=$HOST NodeAddr=127.0.0.1 CPUs=2 State=UNKNOWN
PartitionName=vbl Nodes=ALL Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF="$T/slurm.conf"
slurmctld -D -i -f "$SLURM_CONF" >"$T/slurmctld.out" 2>&1 &
DAEMON_PIDS="$DAEMON_PIDS $!"
slurmd -D -N "$HOST" -f "$SLURM_CONF" >"$T/slurmd.out" 2>&1 &
DAEMON_PIDS="$DAEMON_PIDS $!"
state=""
for i in $(seq 60); do
    state=$(sinfo -h -o %t 2>/dev/null | head -n 1)
    [ "$state" = idle ] && break
    sleep 1
done
[ "$state" = idle ] || fail "the node did not come up idle in 60 s (sinfo: '$state')"

# the scene, a farm render of 4 passes in 2 tasks, and the same render in one process
cat > "$T/scene.json" <<JSON
{"camera": {"position": [0.75, -3.0, 0.75], "look_at": [0.75, 0.75, 0.75], "fov_deg": 40, "resolution": [16, 12]},
 "lights": [{"type": "distant", "direction": [-0.3, 0.5, -0.8], "irradiance": [2.0, 1.8, 1.5]},
            {"type": "environment", "radiance": [0.10, 0.12, 0.20]}],
 "media": [{"vdb": "$BOX", "density_scale": 3.0, "albedo": [0.9, 0.8, 0.7], "phase": {"type": "hg", "g": 0.3}}],
 "render": {"method": "pt", "passes": 4, "spp": 2, "seed": 3, "max_bounces": 4}}
JSON
ids=$("$VBL" farm submit "$T/scene.json" -o "$T/out.exr" --passes 4 --chunks 2 --partition vbl \
      --sbatch-arg=--time=10 -- --threads 1 --aov samples) || fail "vbl farm submit failed"
echo "$ids"
array=$(echo "$ids" | awk '$1 == "array_job" {print $2}')
merge=$(echo "$ids" | awk '$1 == "merge_job" {print $2}')
[ -n "$array" ] && [ -n "$merge" ] || fail "no job ids in: $ids"
i=0
while [ $i -lt 240 ]; do
    [ -z "$(squeue -h -j "$array,$merge" 2>/dev/null)" ] && break
    sleep 1
    i=$((i + 1))
done
[ -s "$T/out.exr" ] || fail "no merged EXR after $i s (squeue: $(squeue -h 2>&1))"
"$VBL" render "$T/scene.json" -o "$T/single.exr" -q --threads 1 --aov samples || fail "single render failed"
diff=$("$VBL" diff "$T/out.exr" "$T/single.exr" --json) || fail "vbl diff failed"
echo "$diff"
# every layer's max_abs below 1e-5 (pixel values are O(0.1..1); samples must be equal)
echo "$diff" | tr ',{}[]' '\n\n\n\n\n' | awk -F: '/"max_abs"/ { if ($2 + 0 > 1e-5) bad = 1; n++ }
    END { exit (n >= 4 && !bad) ? 0 : 1 }' || fail "merged farm render differs from the single-process render"
echo "farm render ok: array job $array, merge job $merge, merged EXR equals the single render"
exit 0
