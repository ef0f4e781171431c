#!/usr/bin/env bash
# Real-Slurm integration test of `rocklab slurm`: brings up a single-node Slurm on this machine
# (installs slurm-wlm if missing; private config, ports and munge socket; daemons started as
# plain processes, no systemd), then
#   A. `rocklab slurm studies/fig24_records.ron --tasks 4 --submit` runs untouched to its merged
#      results, which must equal a single `rocklab run` of the study;
#   B. on a larger copy of that study (2 tasks), one task is sent SIGTERM mid-run the way Slurm
#      warns a task of its time limit (`--signal=B:TERM@60` = `scancel --batch --signal=TERM`);
#      the task must requeue itself, run again (we make it eligible at once instead of waiting
#      out Slurm's requeue delay) reusing the scenes it had finished (from its journal), the merge
#      job must then run, and the merged results must equal a single run.
# Every wait is bounded. Exit status: 0 passed, 1 failed, 77 skipped (no root, no apt, or the
# scheduler would not start: said loudly, never a silent pass).
# Usage: scripts/slurm-test.sh            (as root; ROCKLAB=path/to/rocklab to skip the build)
set -uo pipefail
cd "$(dirname "$0")/.."
repo=$(pwd)
started=$(date +%s)
SKIPPED=77

say() { echo "[slurm-test $(($(date +%s) - started))s] $*"; }
work=""
dump_logs() {
  [ -n "$work" ] || return 0
  for f in "$work"/log/slurmctld.log "$work"/log/slurmd.log "$work"/munge/munged.log; do
    [ -f "$f" ] && { echo "----- last lines of $f"; tail -n 40 "$f"; }
  done
  for f in "$work"/*/slurm/logs/*.log; do
    [ -f "$f" ] && { echo "----- $f"; tail -n 20 "$f"; }
  done
  return 0
}
skip() {
  echo "=================================================================="
  echo "SLURM TEST SKIPPED: $*"
  echo "(the real-Slurm test did NOT run; this is not a pass)"
  echo "=================================================================="
  dump_logs
  exit "$SKIPPED"
}
fail() {
  echo "=================================================================="
  echo "SLURM TEST FAILED: $*"
  echo "=================================================================="
  dump_logs
  [ -n "$work" ] && echo "(files kept in $work)"
  keep_work=1
  exit 1
}

# ---------------------------------------------------------------- prerequisites
[ "$(id -u)" = 0 ] || skip "needs root to install and run slurmctld/slurmd (uid $(id -u))"
if ! command -v slurmctld >/dev/null || ! command -v slurmd >/dev/null || ! command -v munged >/dev/null; then
  command -v apt-get >/dev/null || skip "slurm-wlm is not installed and there is no apt-get"
  say "installing slurm-wlm (apt-get)"
  installed=0
  for attempt in 1 2; do
    if timeout 300 apt-get update -qq >/dev/null 2>&1 &&
      DEBIAN_FRONTEND=noninteractive timeout 600 apt-get install -y -qq slurm-wlm >/dev/null 2>&1; then
      installed=1
      break
    fi
    say "apt-get failed (attempt $attempt)"
    sleep 5
  done
  [ "$installed" = 1 ] || skip "apt-get install slurm-wlm failed"
fi
id munge >/dev/null 2>&1 || skip "no munge user after installing slurm-wlm"

bin=${ROCKLAB:-$repo/target/release/rocklab}
if [ -z "${ROCKLAB:-}" ]; then
  say "building rocklab (release)"
  cargo build --release --quiet || fail "cargo build --release failed"
fi
[ -x "$bin" ] || fail "no rocklab executable at $bin"

# ---------------------------------------------------------------- a private single-node Slurm
work=$(mktemp -d /tmp/rocklab-slurm-test.XXXXXX)
chmod 755 "$work" # munged wants every directory above its socket searchable
keep_work=0
export SLURM_CONF=$work/slurm.conf
unset SLURM_JOB_ID SLURM_ARRAY_JOB_ID SLURM_ARRAY_TASK_ID

stop_pidfile() { # pid file, name: TERM, then KILL after 10 s
  local pid
  pid=$(cat "$1" 2>/dev/null) || return 0
  [ -n "$pid" ] && kill -0 "$pid" 2>/dev/null || return 0
  kill -TERM "$pid" 2>/dev/null
  for _ in $(seq 20); do kill -0 "$pid" 2>/dev/null || return 0; sleep 0.5; done
  say "$2 (pid $pid) ignored SIGTERM; killing it"
  kill -KILL "$pid" 2>/dev/null
}
stop_daemons() {
  stop_pidfile "$work/slurmd.pid" slurmd
  stop_pidfile "$work/slurmctld.pid" slurmctld
  stop_pidfile "$work/munge/munged.pid" munged
}
cleanup() {
  local status=$?
  trap - EXIT INT TERM
  if [ -n "$work" ] && [ -f "$work/slurmctld.pid" ]; then
    # End our jobs first so that no task outlives its slurmd.
    timeout 20 scancel --quiet --user=root >/dev/null 2>&1
    for _ in $(seq 20); do [ -z "$(timeout 5 squeue -h 2>/dev/null)" ] && break; sleep 1; done
  fi
  [ -n "$work" ] && stop_daemons
  if [ -n "$work" ] && [ "$keep_work" = 0 ]; then rm -rf "$work"; fi
  say "daemons stopped"
  exit "$status"
}
trap cleanup EXIT
trap 'say "interrupted"; exit 1' INT TERM

mkdir -p "$work"/munge "$work"/spool/ctld "$work"/spool/d "$work"/log
chown munge: "$work/munge"
key=/etc/munge/munge.key
if [ ! -s "$key" ]; then
  mkdir -p /etc/munge
  dd if=/dev/urandom of="$key" bs=1 count=1024 2>/dev/null || skip "cannot create $key"
fi
chown munge: "$key" /etc/munge && chmod 0400 "$key" && chmod 0700 /etc/munge
sock=$work/munge/munge.socket

port_busy() { (exec 3<>"/dev/tcp/127.0.0.1/$1") 2>/dev/null; }
host=$(hostname -s)
cpus=$(nproc)
mem=$(awk '/MemTotal/ { print int($2 / 1024 * 0.8) }' /proc/meminfo)

write_conf() { # $1: controller port
  cat >"$SLURM_CONF" <<EOF
# Single-node Slurm for rocklab's integration test (no systemd, no cgroups, no accounting db).
ClusterName=rocklabtest
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$1
SlurmdPort=$(($1 + 1))
AuthType=auth/munge
AuthInfo=socket=$sock
CredType=cred/munge
SlurmUser=root
SlurmdUser=root
StateSaveLocation=$work/spool/ctld
SlurmdSpoolDir=$work/spool/d
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/log/slurmctld.log
SlurmdLogFile=$work/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
# The scheduler's own record of every job's end (sacct needs a database; this needs none).
JobCompType=jobcomp/filetxt
JobCompLoc=$work/log/jobcomp.txt
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
MinJobAge=3600
KillWait=30
NodeName=$host NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=debug Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
}

start_munge() {
  stop_pidfile "$work/munge/munged.pid" munged
  su -s /bin/sh munge -c "/usr/sbin/munged --socket=$sock --pid-file=$work/munge/munged.pid \
    --log-file=$work/munge/munged.log --seed-file=$work/munge/munged.seed" || return 1
  for _ in $(seq 20); do
    munge -S "$sock" -n 2>/dev/null | unmunge -S "$sock" 2>/dev/null | grep -q 'STATUS: *Success' && return 0
    sleep 0.5
  done
  return 1
}

start_slurm() { # returns 0 once the node is idle (within 60 s)
  local port=""
  for p in 16817 17817 18817 19817 20817 21817; do
    port_busy "$p" || port_busy $((p + 1)) || { port=$p; break; }
  done
  [ -n "$port" ] || return 1
  write_conf "$port"
  rm -rf "$work"/spool/ctld/* "$work"/spool/d/*
  /usr/sbin/slurmctld || return 1
  /usr/sbin/slurmd || return 1
  for _ in $(seq 60); do
    state=$(timeout 5 sinfo -h -o %T 2>/dev/null)
    [ "$state" = idle ] && return 0
    sleep 1
  done
  say "node state after 60 s: '${state:-none}'"
  return 1
}

up=0
for attempt in 1 2 3; do
  if start_munge && start_slurm; then
    up=1
    break
  fi
  say "the scheduler did not come up (attempt $attempt of 3); restarting the daemons"
  dump_logs
  stop_daemons
  sleep 2
done
[ "$up" = 1 ] || skip "munged/slurmctld/slurmd would not start on $host (logs above)"
say "Slurm $(sinfo -V | awk '{print $2}') is up: $(sinfo -h -o '%P %D node(s) %T, %c CPUs' | head -1), config $SLURM_CONF"

# ---------------------------------------------------------------- helpers
job_state() { # a job's state as the controller reports it (also finished jobs: MinJobAge=3600)
  timeout 10 scontrol show job "$1" 2>/dev/null | grep -o 'JobState=[A-Z_]*' | head -1 | cut -d= -f2
}
job_field() { # job, field
  timeout 10 scontrol show job "$1" 2>/dev/null | grep -o "$2=[^ ]*" | head -1 | cut -d= -f2
}
wait_for() { # seconds, description, command…: poll every second until the command succeeds
  local limit=$1 what=$2
  shift 2
  for _ in $(seq "$limit"); do
    "$@" && return 0
    sleep 1
  done
  fail "timed out after ${limit} s waiting for $what"
}
job_ended() { case $(job_state "$1") in COMPLETED | FAILED | CANCELLED | TIMEOUT | NODE_FAIL | OUT_OF_MEMORY | BOOT_FAIL | DEADLINE) return 0 ;; *) return 1 ;; esac; }
show_jobs() { # the scheduler's view: squeue (all states) and its job-completion log
  echo "  squeue -t all (JobId, name, state, time, reason):"
  timeout 10 squeue -t all -o '%.12i %.28j %.10T %.10M %.24r' | sed 's/^/    /'
  echo "  the scheduler's job-completion log (jobcomp/filetxt), one line per run of a job:"
  awk '{ for (i = 1; i <= NF; i++) { split($i, kv, "="); f[kv[1]] = kv[2] }
         id = (f["ArrayJobId"] != "") ? f["ArrayJobId"] "_" f["ArrayTaskId"] " (job " f["JobId"] ")" : f["JobId"]
         printf "    %-22s %-26s %-10s %s .. %s exit %s\n", id, f["Name"], f["JobState"], f["StartTime"], f["EndTime"], f["ExitCode"]
         delete f }' "$work/log/jobcomp.txt" 2>/dev/null
}
submit() { # study, out, flags…: run `rocklab slurm … --submit`, set array_id and merge_id
  local study=$1 out=$2
  shift 2
  say "\$ rocklab slurm $study --out $out $* --submit"
  timeout 120 "$bin" slurm "$study" --out "$out" "$@" --submit >"$out.submit.txt" 2>&1 || {
    cat "$out.submit.txt"
    fail "rocklab slurm --submit failed"
  }
  sed 's/^/    /' "$out.submit.txt"
  array_id=$(sed -n 's/^submitted: array job \([0-9]*\), merge job \([0-9]*\)$/\1/p' "$out.submit.txt")
  merge_id=$(sed -n 's/^submitted: array job \([0-9]*\), merge job \([0-9]*\)$/\2/p' "$out.submit.txt")
  [ -n "$array_id" ] && [ -n "$merge_id" ] || fail "no job ids in rocklab slurm's output"
}
normalised_json() { # results.json without what legitimately differs between runs
  sed -E 's/"wall_seconds":[-+0-9.eE]+//g; s/"build":"[0-9a-f]*"//g' "$1"
}
same_results() { # merged dir, single-run dir
  local f
  for f in results.csv summary.txt; do
    cmp -s "$1/$f" "$2/$f" || fail "$f of the merged array differs from a single run: diff $1/$f $2/$f"
  done
  cmp -s <(normalised_json "$1/results.json") <(normalised_json "$2/results.json") ||
    fail "results.json (outcomes, spectra, maps) of the merged array differs from a single run"
  say "identical to a single run: results.csv ($(($(wc -l <"$1/results.csv") - 1)) rows), summary.txt, results.json outcomes/spectra/maps (wall times and build id aside)"
}

# ---------------------------------------------------------------- A: the README's command, untouched
study=studies/fig24_records.ron
say "A. single run of $study for reference"
t0=$(date +%s%N)
"$bin" run "$study" --out "$work/a-single" --quiet 2>&1 | tail -1 | sed 's/^/    /'
single_ms=$((($(date +%s%N) - t0) / 1000000))
[ -f "$work/a-single/results.csv" ] || fail "the single run wrote no results.csv"
submit "$study" "$work/a" --tasks 4
wait_for 600 "merge job $merge_id" job_ended "$merge_id"
show_jobs
[ "$(job_state "$merge_id")" = COMPLETED ] || fail "merge job $merge_id ended $(job_state "$merge_id")"
for t in 0 1 2 3; do
  s=$(job_state "${array_id}_$t")
  [ "$s" = COMPLETED ] || fail "task ${array_id}_$t ended $s"
done
same_results "$work/a" "$work/a-single"

# ---------------------------------------------------------------- B: a task stopped mid-run, resumed
# fig24 with k× the ωn points, k sized from part A's single run so that a task runs about 30 s
# here, long enough to be caught mid-run however fast rocklab gets (a fixed 6× once finished in
# under 6 s and the test raced it).
grow=$(((30000 + single_ms - 1) / (single_ms > 0 ? single_ms : 1)))
grow=$((grow < 6 ? 6 : grow > 400 ? 400 : grow))
big=$work/fig24_big.ron
sed -E "s/(omega_n: *\(from: *[^,]+, *to: *[^,]+, *steps: *)[0-9]+/\1$((40 * grow))/; s/name: *\"fig24_records\"/name: \"fig24_big\"/" \
  "$study" >"$big"
scenes=$("$bin" run "$big" --dry-run | sed -n 's/.*: \([0-9]*\) scenes in.*/\1/p')
[ "${scenes:-0}" -ge 3000 ] || fail "could not enlarge $study for part B (got ${scenes:-no} scenes; its omega_n range changed?)"
say "   part A's single run took $single_ms ms, so part B runs $grow× its ωn points"
say "B. single run of the enlarged study ($scenes scenes) for reference"
t0=$(date +%s)
"$bin" run "$big" --out "$work/b-single" --quiet 2>&1 | tail -1 | sed 's/^/    /'
say "   (single run: $(($(date +%s) - t0)) s on $cpus CPUs)"
submit "$big" "$work/b" --tasks 2
victim="${array_id}_1"
victim_log() { ls "$work"/b/slurm/logs/array-"${array_id}"_1.log 2>/dev/null; }
# Mid-run: the task's journal holds at least 5% of its shard (its first line is the header).
victim_journal=$work/b/results.shard-1-of-2.journal
has_progressed() {
  job_ended "$victim" && fail "task $victim ended ($(job_state "$victim")) before it could be stopped mid-run"
  [ "$(job_state "$victim")" = RUNNING ] && [ -f "$victim_journal" ] &&
    [ $(($(wc -l <"$victim_journal") - 1)) -ge $((scenes / 2 / 20)) ]
}
wait_for 300 "task $victim to be running with 5% of its scenes journalled" has_progressed
say "task $victim is mid-run: $(($(wc -l <"$victim_journal") - 1)) of $((scenes / 2)) scenes journalled"
say "\$ scancel --batch --signal=TERM $victim   (what --signal=B:TERM@60 sends before the time limit)"
timeout 20 scancel --batch --signal=TERM "$victim" || fail "scancel failed"
requeued() {
  job_ended "$victim" && fail "task $victim ended $(job_state "$victim") instead of requeueing itself"
  [ "$(job_field "$victim" Restarts)" -ge 1 ] 2>/dev/null; }
wait_for 120 "task $victim to requeue itself" requeued
say "task $victim requeued itself: state $(job_state "$victim"), Restarts=$(job_field "$victim" Restarts), reason $(job_field "$victim" Reason)"
# What the stopped task kept in its output directory (its journal).
for f in "$work"/b/*shard-1-of-2*; do
  [ -f "$f" ] && say "   kept by the stopped task: $(basename "$f") ($(wc -c <"$f") bytes, $(wc -l <"$f") lines)"
done
"$bin" status "$work/b" 2>&1 | sed 's/^/    /'
# Slurm holds a requeued job back (BeginTime) for about two minutes before it runs it again.
# The test waits for that hold: moving the start forward (`scontrol update StartTime=now`) while
# the stopped run is still completing made Slurm start the task on a revoked credential and
# fail it ("Killing non-startable batch job"), which leaves the merge job unsatisfiable.
say "waiting for Slurm to restart the requeued task $victim after its requeue hold (~2 min)"
# Done when the merge job ends, or at once if the resumed task failed (the merge would wait
# for ever on an unsatisfiable dependency).
merge_or_victim_ended() { job_ended "$merge_id" || [ "$(job_state "$victim")" = FAILED ]; }
wait_for 900 "merge job $merge_id" merge_or_victim_ended
show_jobs
[ "$(job_state "$victim")" = COMPLETED ] || fail "the resumed task $victim ended $(job_state "$victim")"
[ "$(job_state "$merge_id")" = COMPLETED ] || fail "merge job $merge_id ended $(job_state "$merge_id")"
for t in 0 1; do
  s=$(job_state "${array_id}_$t")
  [ "$s" = COMPLETED ] || fail "task ${array_id}_$t ended $s"
done
[ "$(job_field "$victim" Restarts)" = 1 ] || fail "task $victim ran $(job_field "$victim" Restarts) restarts, expected 1"
echo "  log of the stopped and resumed task ($(victim_log)):"
grep -vE '^progress:' "$(victim_log)" | sed 's/^/    /'
reused=$(sed -n 's/.*: \([0-9]*\) finished scenes reused.*/\1/p' "$(victim_log)" | tail -1)
if [ -n "$reused" ]; then
  say "the resumed task reused $reused scenes finished before SIGTERM (of $((scenes / 2)) in its shard)"
else
  fail "the resumed task reused no scene: its log has no 'N finished scenes reused' note"
fi
same_results "$work/b" "$work/b-single"

say "PASSED in $(($(date +%s) - started)) s"
echo "slurm-test: 2 passed, 0 failed"
