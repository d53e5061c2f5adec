#!/usr/bin/env bash
# Real single-node Slurm test of deploy/slurm/render.sbatch.
#
# Brings up munged, slurmctld and slurmd on this machine (one node, "localhost", with every
# core of the machine) from a private slurm.conf in a temporary folder, then:
#   1. renders frames 0..=7 of the shipped fly-through in one process (the reference);
#   2. submits the same range as a 4-task job array (1 CPU per task) and SIGKILLs task 2 while
#      it is inside its first frame (`scancel --batch --signal=KILL`: a real SIGKILL, not the
#      SIGTERM a cancel starts with, which penumbra would handle cleanly);
#   3. checks that no frame file is partial and that exactly task 2's frames are missing;
#   4. resubmits task 2 alone and checks that it renders only its own frames;
#   5. compares every frame with the reference byte for byte and asks `penumbra status`.
# The daemons it started are stopped by PID on every exit path. Run it from anywhere, as root
# (it may apt-get install slurm-wlm and munge, and writes /etc/munge/munge.key if missing),
# after `cargo test --release` (or it builds the release binary itself).
#
# Knobs (environment): SLURM_TEST_WIDTH / SLURM_TEST_HEIGHT (frame size, default 1920x1080, so
# a frame takes long enough on one core to be killed in the middle of it), SLURM_TEST_KEEP=1
# (keep the temporary folder), SLURM_TEST_PENUMBRA (another binary to test, for development).
set -euo pipefail

# Become a child subreaper (prctl PR_SET_CHILD_SUBREAPER = 36, kept across exec) so that the
# daemons that fork into the background (munged, slurmstepd) are reparented to this shell, which
# reaps them when they exit, rather than to PID 1, which in containers may reap late or never:
# when this script ends, no slurm or munge process is left, not even a zombie.
if [ -z "${SLURM_TEST_SUBREAPER:-}" ] && command -v python3 >/dev/null; then
    export SLURM_TEST_SUBREAPER=1
    exec python3 -c 'import ctypes, os, sys
ctypes.CDLL(None).prctl(36, 1, 0, 0, 0)
os.execvp("bash", ["bash"] + sys.argv[1:])' "$0" "$@"
fi

cd "$(dirname "$0")/.."
ROOT=$PWD
export PATH="$PATH:/usr/sbin:/sbin"

WIDTH=${SLURM_TEST_WIDTH:-1920}
HEIGHT=${SLURM_TEST_HEIGHT:-1080}
FIRST=0
LAST=7
NFRAMES=$((LAST - FIRST + 1))
SHARDS=4
VICTIM=2 # the array task that gets killed

log() { echo "slurm-test: $*"; }
die() {
    echo "slurm-test: FAIL: $*" >&2
    exit 1
}
now() { date +%s.%N; }
elapsed() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.1f", b - a }'; }

# ---------------------------------------------------------------------------------------------
# The binary under test.
if [ -n "${SLURM_TEST_PENUMBRA:-}" ]; then
    BIN=$SLURM_TEST_PENUMBRA
else
    BIN=${CARGO_TARGET_DIR:-target}/release/penumbra
    if [ ! -x "$BIN" ]; then
        log "building the release binary"
        cargo build --release
    fi
fi
BIN=$(realpath "$BIN")
[ -x "$BIN" ] || die "no penumbra binary at $BIN"
command -v python3 >/dev/null || die "python3 is needed (PNG and JSON checks)"

WORK=$(mktemp -d "${TMPDIR:-/tmp}/penumbra-slurm.XXXXXX")
chmod 0755 "$WORK"
mkdir -p "$WORK/etc" "$WORK/state" "$WORK/spool" "$WORK/log" "$WORK/jobs"

# ---------------------------------------------------------------------------------------------
# Cleanup: cancel our jobs, stop the daemons we started (by PID), always.
MUNGED_PID=
SLURMCTLD_PID=
SLURMD_PID=
JOBIDS=$WORK/jobids # every job submitted (a file: submissions run in command substitutions)
: >"$JOBIDS"

# Stop one process we started: SIGTERM, up to 15 s, then SIGKILL. Zombies count as stopped.
stop_pid() {
    local pid=$1 name=$2 i
    [ -n "$pid" ] || return 0
    kill -0 "$pid" 2>/dev/null || return 0
    kill -TERM "$pid" 2>/dev/null || true
    for i in $(seq 150); do
        if ! kill -0 "$pid" 2>/dev/null || [ "$(ps -o stat= -p "$pid" 2>/dev/null | cut -c1)" = Z ]; then
            wait "$pid" 2>/dev/null || true
            return 0
        fi
        sleep 0.1
    done
    log "$name ($pid) ignored SIGTERM; sending SIGKILL"
    kill -KILL "$pid" 2>/dev/null || true
    wait "$pid" 2>/dev/null || true
}

cleanup() {
    local rc=$? i f
    set +e
    trap - EXIT INT TERM ERR
    local jobs=()
    [ -f "$JOBIDS" ] && mapfile -t jobs <"$JOBIDS"
    if [ ${#jobs[@]} -gt 0 ] && [ -n "$SLURMCTLD_PID" ] && kill -0 "$SLURMCTLD_PID" 2>/dev/null; then
        # Cancel what is pending, kill what runs; wait for the steps to end.
        scancel --full --signal=KILL "${jobs[@]}" 2>/dev/null
        scancel "${jobs[@]}" 2>/dev/null
        for i in $(seq 150); do
            [ -z "$(squeue -h -j "$(IFS=,; echo "${jobs[*]}")" 2>/dev/null)" ] && break
            sleep 0.1
        done
    fi
    stop_pid "$SLURMD_PID" slurmd
    stop_pid "$SLURMCTLD_PID" slurmctld
    stop_pid "$MUNGED_PID" munged
    # Anything else still here descends from the daemons above and was adopted by this shell (a
    # subreaper): a job step that outlived slurmd, or its render. Kill it (what a killed step
    # leaves behind is adopted in turn, hence the rounds).
    for i in 1 2 3 4 5; do
        ps -o pid=,stat=,comm= --ppid $$ >"$WORK/ps" 2>/dev/null # no other child of ours now
        awk '$3 != "ps" && $2 !~ /^Z/ { print $1, $3 }' "$WORK/ps" >"$WORK/children"
        [ -s "$WORK/children" ] || break
        log "killing leftover processes: $(tr '\n' ' ' <"$WORK/children")"
        while read -r f _; do kill -KILL "$f" 2>/dev/null; done <"$WORK/children"
        sleep 0.2
    done
    if [ "$rc" -ne 0 ]; then
        for f in "$WORK"/log/*.log "$WORK"/log/*.out "$WORK"/jobs/*.out; do
            [ -s "$f" ] || continue
            echo "----- $f (last 25 lines)" >&2
            tail -n 25 "$f" >&2
        done
    fi
    if [ "${SLURM_TEST_KEEP:-0}" = 1 ]; then
        log "kept $WORK"
    else
        rm -rf "$WORK"
    fi
    exit "$rc"
}
trap cleanup EXIT
trap 'echo "slurm-test: FAIL: line $LINENO: $BASH_COMMAND exited with $?" >&2' ERR
trap 'exit 130' INT
trap 'exit 143' TERM

# ---------------------------------------------------------------------------------------------
# Bring-up.
T_UP0=$(now)

if ! command -v sbatch >/dev/null || ! command -v slurmctld >/dev/null ||
    ! command -v slurmd >/dev/null || ! command -v munged >/dev/null; then
    log "installing slurm-wlm and munge"
    export DEBIAN_FRONTEND=noninteractive
    apt-get install -y -q slurm-wlm munge ||
        { apt-get update -q && apt-get install -y -q slurm-wlm munge; }
fi

munge_ok() { munge -n 2>/dev/null | unmunge >/dev/null 2>&1; }

if munge_ok; then
    log "munged is already running; using it"
else
    KEY=/etc/munge/munge.key
    mkdir -p /etc/munge
    if [ ! -s "$KEY" ]; then
        log "creating $KEY"
        if command -v mungekey >/dev/null; then
            mungekey --create --keyfile="$KEY"
        else
            dd if=/dev/urandom of="$KEY" bs=1024 count=1 status=none
        fi
    fi
    chown munge:munge /etc/munge "$KEY"
    chmod 0700 /etc/munge
    chmod 0400 "$KEY"
    mkdir -p /run/munge /var/lib/munge /var/log/munge
    chown munge:munge /run/munge /var/lib/munge /var/log/munge
    chmod 0755 /run/munge
    chmod 0700 /var/lib/munge /var/log/munge
    rm -f /run/munge/munged.pid
    # munged daemonizes and writes its PID file; it insists on running as the key's owner.
    runuser -u munge -- /usr/sbin/munged || /usr/sbin/munged --force
    for i in $(seq 50); do
        [ -s /run/munge/munged.pid ] && munge_ok && break
        sleep 0.1
    done
    MUNGED_PID=$(cat /run/munge/munged.pid 2>/dev/null || true)
    munge_ok || die "munged did not start"
    [ -n "$MUNGED_PID" ] || die "munged wrote no PID file"
fi

CPUS=$(nproc)
CONF=$WORK/etc/slurm.conf
cat >"$CONF" <<EOF
# Minimal single-node cluster for .ci/slurm-test.sh (no cgroups, no systemd, no accounting).
ClusterName=penumbra-ci
SlurmctldHost=localhost
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
MpiDefault=none
MailProg=/bin/true
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/backfill
ReturnToService=2
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
KillWait=5
StateSaveLocation=$WORK/state
SlurmdSpoolDir=$WORK/spool
SlurmctldPidFile=$WORK/slurmctld.pid
SlurmdPidFile=$WORK/slurmd.pid
SlurmctldLogFile=$WORK/log/slurmctld.log
SlurmdLogFile=$WORK/log/slurmd.log
NodeName=localhost CPUs=$CPUS State=UNKNOWN
PartitionName=debug Nodes=localhost Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF=$CONF

# In the foreground (-D), backgrounded here, so that $! is the daemon itself. slurmd needs
# -N localhost: the node is named localhost, the host is not.
slurmctld -D -f "$CONF" >"$WORK/log/slurmctld.out" 2>&1 &
SLURMCTLD_PID=$!
slurmd -D -N localhost -f "$CONF" >"$WORK/log/slurmd.out" 2>&1 &
SLURMD_PID=$!

STATE=
for i in $(seq 600); do
    kill -0 "$SLURMCTLD_PID" 2>/dev/null || die "slurmctld exited"
    kill -0 "$SLURMD_PID" 2>/dev/null || die "slurmd exited"
    STATE=$(sinfo -h -N -n localhost -o %t 2>/dev/null || true)
    [ "$STATE" = idle ] && break
    sleep 0.1
done
[ "$STATE" = idle ] || die "node localhost is not idle after 60 s (state: ${STATE:-none})"
T_UP=$(elapsed "$T_UP0" "$(now)")
log "Slurm is up in ${T_UP} s: node localhost idle with $CPUS CPUs"

# ---------------------------------------------------------------------------------------------
# The reference: one process, every core.
SCENE=$ROOT/scenes/flythrough.ron
SCRIPT=$ROOT/scripts/flythrough.rhai
SIZE=(--width "$WIDTH" --height "$HEIGHT")
T0=$(now)
"$BIN" animate "$SCENE" "$SCRIPT" --frames "$FIRST..=$LAST" --fps 24 -o "$WORK/single" "${SIZE[@]}" --quiet
T_SINGLE=$(elapsed "$T0" "$(now)")
log "reference: $NFRAMES frames at ${WIDTH}x${HEIGHT} in one process in ${T_SINGLE} s"

# The frames of array task $1 (contiguous split: block sizes differ by at most one, the first
# blocks larger).
shard_frames() {
    local i=$1 base=$((NFRAMES / SHARDS)) rem=$((NFRAMES % SHARDS)) start len f
    start=$((FIRST + i * base + (i < rem ? i : rem)))
    len=$((base + (i < rem ? 1 : 0)))
    for ((f = start; f < start + len; f++)); do echo "$f"; done
}
frame_file() { printf '%s/frame_%04d.png' "$1" "$2"; }

# Submit the array; the environment carries the parameters (sbatch exports it).
ARRAY=$WORK/array
submit() { # ARRAY_SPEC EXTRA_ARGS
    local id
    id=$(env FRAMES="$FIRST..=$LAST" FPS=24 OUT="$ARRAY" PENUMBRA="$BIN" SCENE="$SCENE" \
        SCRIPT="$SCRIPT" EXTRA_ARGS="$2" \
        sbatch --parsable --array="$1" --cpus-per-task=1 --chdir="$WORK" \
        --output="$WORK/jobs/%A_%a.out" "$ROOT/deploy/slurm/render.sbatch")
    id=${id%%;*}
    echo "$id" >>"$JOBIDS"
    echo "$id"
}
wait_job() { # JOBID TIMEOUT_S
    local i
    for ((i = 0; i < $2 * 5; i++)); do
        [ -z "$(squeue -h -j "$1")" ] && return 0
        sleep 0.2
    done
    die "job $1 still queued after $2 s: $(squeue -h -r -j "$1" -o '%i %T' | tr '\n' ' ')"
}
task_state() { squeue -h -r -j "$1" -o '%i %T' | awk -v t="$1_$2" '$1 == t { print $2 }'; }

mapfile -t VICTIM_FRAMES < <(shard_frames "$VICTIM")

T0=$(now)
JOB=$(submit "0-$((SHARDS - 1))" "${SIZE[*]} --split contiguous")
log "submitted array job $JOB (tasks 0-$((SHARDS - 1)), 1 CPU each)"

# Kill task $VICTIM inside its first frame: wait until Slurm runs it and its batch script has
# reached `exec penumbra` (it logs a line just before), then wait a moment. The moment is half
# of the reference's time per frame, which used every core, so it is at most half of the time
# one frame takes on the task's single core, wherever this runs (and at least 0.3 s, so that
# penumbra is past start-up and rendering).
DELAY=$(awk -v t="$T_SINGLE" -v n="$NFRAMES" 'BEGIN { d = t / n / 2; if (d < 0.3) d = 0.3; printf "%.2f", d }')
VLOG=$WORK/jobs/${JOB}_${VICTIM}.out
for i in $(seq 600); do
    S=$(task_state "$JOB" "$VICTIM")
    [ "$S" = RUNNING ] && grep -q '^penumbra-render:' "$VLOG" 2>/dev/null && break
    case "$S" in PENDING | CONFIGURING | RUNNING | "") ;; *) die "task $VICTIM is $S before it could be killed" ;; esac
    sleep 0.1
done
[ "$S" = RUNNING ] || die "task $VICTIM never started"
sleep "$DELAY"
for f in "${VICTIM_FRAMES[@]}"; do
    [ ! -e "$(frame_file "$ARRAY" "$f")" ] ||
        die "task $VICTIM finished frame $f before the kill; make frames slower (SLURM_TEST_WIDTH/HEIGHT)"
done
T_KILL=$(elapsed "$T0" "$(now)")
# A real SIGKILL, no chance to clean up: signal the batch step (the batch script exec's
# penumbra, so that is penumbra itself). Not `scancel --full --signal=KILL JOB` nor plain
# `scancel JOB`: slurmctld turns a SIGKILL for the whole job into a cancel, and slurmd cancels
# with SIGTERM first (SIGKILL only KillWait later), which penumbra handles cleanly.
scancel --batch --signal=KILL "${JOB}_${VICTIM}"
log "SIGKILLed task $VICTIM (${JOB}_${VICTIM}) ${DELAY} s into its first frame, ${T_KILL} s after submitting"

wait_job "$JOB" 120
T_ARRAY=$(elapsed "$T0" "$(now)")
# Slurm keeps finished jobs (MinJobAge) and reports how task 2 ended: killed by signal 9.
VICTIM_END=$(scontrol show job "${JOB}_${VICTIM}" | grep -oE 'JobState=[A-Z_]+|ExitCode=[0-9:]+' | paste -sd ' ')
case "$VICTIM_END" in
*"ExitCode=0:9"*) ;;
*) die "task $VICTIM did not end by SIGKILL: $VICTIM_END" ;;
esac
if grep -q 'stopped by' "$WORK/jobs/${JOB}_${VICTIM}.out"; then
    die "task $VICTIM stopped cleanly instead of being killed"
fi
log "array job $JOB done in ${T_ARRAY} s (task $VICTIM: $VICTIM_END)"

# No partial frames: every frame_*.png present is a complete PNG (chunk CRCs, IEND, inflatable
# image data), and no other file claims to be a frame.
check_pngs() {
    python3 - "$@" <<'PY'
import struct, sys, zlib
bad = []
for path in sys.argv[1:]:
    data = open(path, "rb").read()
    ok, pos, idat, end = data[:8] == b"\x89PNG\r\n\x1a\n", 8, [], False
    while ok and not end:
        if pos + 12 > len(data):
            ok = False
            break
        (n,) = struct.unpack(">I", data[pos:pos + 4])
        kind, body = data[pos + 4:pos + 8], data[pos + 8:pos + 8 + n]
        if pos + 12 + n > len(data):
            ok = False
            break
        (crc,) = struct.unpack(">I", data[pos + 8 + n:pos + 12 + n])
        ok = zlib.crc32(kind + body) & 0xFFFFFFFF == crc
        if kind == b"IDAT":
            idat.append(body)
        end = kind == b"IEND"
        pos += 12 + n
    try:
        ok = ok and end and len(zlib.decompress(b"".join(idat))) > 0
    except zlib.error:
        ok = False
    if not ok:
        bad.append(path)
if bad:
    print("partial or corrupt PNG:", *bad, file=sys.stderr)
    sys.exit(1)
PY
}
shopt -s nullglob
PRESENT=("$ARRAY"/frame_*.png)
[ ${#PRESENT[@]} -gt 0 ] || die "the array wrote no frames"
check_pngs "${PRESENT[@]}" || die "a frame file is partial"
for ((f = FIRST; f <= LAST; f++)); do
    if printf '%s\n' "${VICTIM_FRAMES[@]}" | grep -qx "$f"; then
        [ ! -e "$(frame_file "$ARRAY" "$f")" ] || die "frame $f of the killed task $VICTIM exists"
    else
        [ -e "$(frame_file "$ARRAY" "$f")" ] || die "frame $f (not task $VICTIM's) is missing"
    fi
done
STRAY=$(find "$ARRAY" -maxdepth 1 -type f ! -name 'frame_*.png' -printf '%f ')
log "after the kill: ${#PRESENT[@]} complete frames, task $VICTIM's frames ${VICTIM_FRAMES[*]} missing${STRAY:+; leftover temporary files: $STRAY}"

STATUS=$("$BIN" status "$ARRAY" --json) || die "penumbra status failed"
MISSING=$(printf '%s' "$STATUS" | python3 -c 'import json, sys; print(" ".join(map(str, json.load(sys.stdin)["missing"])))')
[ "$MISSING" = "${VICTIM_FRAMES[*]}" ] ||
    die "penumbra status reports missing frames '$MISSING', expected '${VICTIM_FRAMES[*]}'"

# Resubmit task $VICTIM alone. A one-task array has SLURM_ARRAY_TASK_MIN = MAX = $VICTIM, so
# the shard is pinned with --shard (the flag wins over the environment).
BEFORE=$(stat -c '%n %i %y' "${PRESENT[@]}")
T0=$(now)
JOB2=$(submit "$VICTIM" "${SIZE[*]} --split contiguous --shard $VICTIM/$SHARDS")
wait_job "$JOB2" 120
T_RERUN=$(elapsed "$T0" "$(now)")
log "resubmitted task $VICTIM as job $JOB2: done in ${T_RERUN} s"
AFTER=$(stat -c '%n %i %y' "${PRESENT[@]}")
[ "$BEFORE" = "$AFTER" ] || die "the rerun rewrote frames that were already done"

# Every frame byte for byte against the reference, and nothing more or less.
N=0
for ((f = FIRST; f <= LAST; f++)); do
    cmp "$(frame_file "$WORK/single" "$f")" "$(frame_file "$ARRAY" "$f")" ||
        die "frame $f differs from the single-process render"
    N=$((N + 1))
done
FINAL=("$ARRAY"/frame_*.png)
[ ${#FINAL[@]} -eq "$NFRAMES" ] || die "${#FINAL[@]} frame files in $ARRAY, expected $NFRAMES"

STATUS=$("$BIN" status "$ARRAY" --json) || die "penumbra status failed"
COUNTS=$(printf '%s' "$STATUS" | python3 -c 'import json, sys; s = json.load(sys.stdin); print(len(s["done"]), len(s["missing"]), len(s["stale"]))')
[ "$COUNTS" = "$NFRAMES 0 0" ] || die "penumbra status: done/missing/stale = $COUNTS, expected $NFRAMES 0 0"

T_TOTAL=$(awk -v a="$T_ARRAY" -v b="$T_RERUN" 'BEGIN { printf "%.1f", a + b }')
log "OK: $N frames (${WIDTH}x${HEIGHT}) byte-identical; single process (${CPUS} threads) ${T_SINGLE} s;" \
    "${SHARDS}-task array (1 CPU each, $CPUS CPUs) ${T_ARRAY} s submit-to-last-task-end with task $VICTIM killed" \
    "+ ${T_RERUN} s rerun of task $VICTIM = ${T_TOTAL} s; Slurm bring-up ${T_UP} s"
