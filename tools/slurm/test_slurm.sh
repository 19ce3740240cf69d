#!/usr/bin/env bash
# End-to-end test of tools/slurm on a real single-host Slurm cluster: starts munged,
# slurmctld and slurmd (Debian's packages, tools/setup.sh installs them) configured in
# a temporary folder, submits a 4-task render array and its merge job with submit.sh,
# waits for them (with a timeout), checks that the merged image is the unsplit
# render's, byte for byte, and tears everything down. Needs root (the daemons run
# as root, without cgroups: proctrack/linuxproc, task/none). `.ci/run` runs it.
#
#   tools/slurm/test_slurm.sh [path/to/wavetrace]   (default: target/debug/wavetrace)
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
wavetrace=$(realpath "${1:-$root/target/debug/wavetrace}")
timeout_s=${SLURM_TEST_TIMEOUT:-600}

fail() {
    echo "test_slurm: FAILED: $*" >&2
    exit 1
}
[ "$(id -u)" -eq 0 ] || fail "needs root (the Slurm daemons run as root here)"
for c in munged slurmctld slurmd sbatch squeue sinfo scontrol; do
    command -v "$c" >/dev/null || fail "$c is missing: run tools/setup.sh"
done
[ -x "$wavetrace" ] || fail "no wavetrace binary at $wavetrace (cargo build first)"

tmp=$(mktemp -d /tmp/wavetrace-slurm.XXXXXX)
chmod 755 "$tmp"
pids=()
cleanup() {
    local status=$?
    if [ $status -ne 0 ]; then
        for log in "$tmp"/log/*.log "$tmp"/out/*.parts/*.log; do
            [ -f "$log" ] || continue
            echo "== $log" >&2
            tail -n 30 "$log" >&2
        done
    fi
    if [ -n "${SLURM_CONF:-}" ]; then
        scancel --quiet --user=root 2>/dev/null || true
    fi
    for pid in "${pids[@]}"; do
        kill "$pid" 2>/dev/null || true
    done
    for pid in "${pids[@]}"; do
        for _ in $(seq 50); do
            kill -0 "$pid" 2>/dev/null || break
            sleep 0.1
        done
        kill -9 "$pid" 2>/dev/null || true
    done
    rm -rf "$tmp"
    exit $status
}
trap cleanup EXIT

# munge: a fresh key and its own socket.
mkdir -p "$tmp/munge" "$tmp/log" "$tmp/state" "$tmp/spool" "$tmp/etc" "$tmp/out"
chmod 700 "$tmp/munge"
dd if=/dev/urandom of="$tmp/munge/munge.key" bs=1024 count=1 status=none
chmod 400 "$tmp/munge/munge.key"
socket="$tmp/munge/munge.socket"
munged --force --key-file="$tmp/munge/munge.key" --socket="$socket" \
    --pid-file="$tmp/munge/munged.pid" --log-file="$tmp/log/munged.log" \
    --seed-file="$tmp/munge/munged.seed" --foreground >"$tmp/log/munged.out" 2>&1 &
pids+=($!)
for _ in $(seq 100); do [ -S "$socket" ] && break; sleep 0.1; done
[ -S "$socket" ] || fail "munged did not start"

# Slurm: this host's real name as its one node, at 127.0.0.1; ports from a range
# unlikely to be in use, tried until both are free.
host=$(hostname -s)
port_free() { ! (exec 3<>"/dev/tcp/127.0.0.1/$1") 2>/dev/null; }
while :; do
    ctld_port=$((20000 + RANDOM % 20000))
    port_free "$ctld_port" && port_free $((ctld_port + 1)) && break
done
cpus=$(nproc)
export SLURM_CONF="$tmp/etc/slurm.conf"
cat >"$SLURM_CONF" <<CONF
ClusterName=wavetrace-test
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$((ctld_port + 1))
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$socket
StateSaveLocation=$tmp/state
SlurmdSpoolDir=$tmp/spool
SlurmctldPidFile=$tmp/slurmctld.pid
SlurmdPidFile=$tmp/slurmd.pid
SlurmctldLogFile=$tmp/log/slurmctld.log
SlurmdLogFile=$tmp/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/backfill
MpiDefault=none
ReturnToService=2
SlurmctldTimeout=30
SlurmdTimeout=30
InactiveLimit=0
KillWait=5
NodeName=$host NodeAddr=127.0.0.1 CPUs=$cpus State=UNKNOWN
PartitionName=test Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
# An empty cgroup.conf: nothing here uses cgroups, but slurmd reads it if present.
: >"$tmp/etc/cgroup.conf"
slurmctld -D -i -f "$SLURM_CONF" >"$tmp/log/slurmctld.out" 2>&1 &
pids+=($!)
slurmd -D -f "$SLURM_CONF" -N "$host" >"$tmp/log/slurmd.out" 2>&1 &
pids+=($!)
deadline=$((SECONDS + 60))
until sinfo -h -N -o '%T' 2>/dev/null | grep -Eq '^(idle|mixed|allocated)'; do
    [ $SECONDS -lt $deadline ] || fail "the node did not come up: $(sinfo -N 2>&1)"
    sleep 1
done
echo "test_slurm: single-host Slurm up ($host, $cpus CPUs, port $ctld_port)"

# The render: 4 parts of 4 samples per pixel, one sample each, so the merge adds the
# samples in the unsplit render's order and must be its image byte for byte.
scene="$root/scenes/media/thin_textured.xml"
args=(-D res=24 --spp 4 --sampler stratified --seed 7)
out="$tmp/out/image.exr"
export WAVETRACE="$wavetrace"
ids=$("$root/tools/slurm/submit.sh" -n 4 -o "$out" "$scene" "${args[@]}")
echo "$ids"
merge_id=$(echo "$ids" | sed -n 's/^merge: *job \([0-9]*\).*/\1/p')
[ -n "$merge_id" ] || fail "submit.sh printed no merge job id"
deadline=$((SECONDS + timeout_s))
while squeue -h -o '%i' 2>/dev/null | grep -q .; do
    [ $SECONDS -lt $deadline ] || fail "jobs still queued after ${timeout_s}s: $(squeue 2>&1)"
    sleep 2
done
state=$(scontrol show job "$merge_id" 2>/dev/null | sed -n 's/.*JobState=\([A-Z_]*\).*/\1/p')
[ -f "$out" ] || fail "no merged image (merge job $merge_id: ${state:-gone})"
for i in 0 1 2 3; do
    [ -f "$tmp/out/image.parts/part-$i.exr" ] || fail "part $i is missing"
done

"$wavetrace" render "$scene" "${args[@]}" -o "$tmp/out/unsplit.exr" -q 2>"$tmp/log/unsplit.log" \
    || fail "the unsplit render failed: $(cat "$tmp/log/unsplit.log")"
cmp "$out" "$tmp/out/unsplit.exr" || fail "the merged image differs from the unsplit render"
cmp "${out%.exr}.png" "$tmp/out/unsplit.png" || fail "the merged PNG differs from the unsplit render's"
echo "test_slurm: ok: 4 array tasks + merge (afterok) = the unsplit render, byte for byte"
