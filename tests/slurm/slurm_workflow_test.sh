#!/usr/bin/env bash
# Slurm for real: brings up a one-node Slurm cluster (Debian's munge and slurm-wlm; munged, slurmctld and
# slurmd started here, as root, on a private key, socket, ports and state folder), runs the documented
# workflow scripts/slurm-submit.sh on 8 frames (render array, calib, finalize, calibrate, analysis array, merge),
# runs the same workflow in single processes, and compares:
#   - the two datasets, every file byte for byte (manifest, SHA256SUMS, frames, sidecars, boards);
#   - the two calibration folders, byte for byte;
#   - the merged run with the single run, byte for byte but for timings (tests/slurm/compare_outputs.py).
# Then bad input: refused options submit nothing, and a step sbatch refuses cancels the steps before it.
# The daemons and anything they started are stopped and the temporary folder removed on every exit.
#
# Usage: tests/slurm/slurm_workflow_test.sh --build BUILD_DIR [--keep]
# Exit status: 0 passed, 1 failed, 77 skipped (not root, or munge / slurm-wlm not installed:
# scripts/install-deps.sh installs them).
set -euo pipefail

SKIP=77
repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
build=$repo/build keep=0
while [ $# -gt 0 ]; do
  case $1 in
    --build) build=$(cd "$2" && pwd); shift 2 ;;
    --keep) keep=1; shift ;;
    *) echo "usage: $0 --build BUILD_DIR [--keep]" >&2; exit 1 ;;
  esac
done
render=$build/renderer/aar-render analyze=$build/analyzer/aar-analyze
export PATH=$PATH:/usr/sbin:/sbin

log() { printf '[slurm-test %3ds] %s\n' "$SECONDS" "$*"; }
fail() { log "FAIL: $*" >&2; exit 1; }

if [ "$(id -u)" != 0 ]; then log "skipped: starts munged, slurmctld and slurmd as root"; exit "$SKIP"; fi
for b in munged mungekey munge slurmctld slurmd sbatch squeue sinfo scontrol scancel python3; do
  command -v "$b" >/dev/null || { log "skipped: $b not installed (scripts/install-deps.sh: munge, slurm-wlm)"; exit "$SKIP"; }
done
for t in "$render" "$analyze"; do [ -x "$t" ] || fail "$t not built"; done

# Short paths: slurmd and munged put sockets in here.
tmp=$(mktemp -d /tmp/aar-slurm.XXXXXX)
chmod 0711 "$tmp"  # munged: every folder above its socket must be searchable by all
mkdir -m 0700 "$tmp/key" "$tmp/state" "$tmp/spool"
mkdir -m 0755 "$tmp/run" "$tmp/log"
export SLURM_CONF=$tmp/slurm.conf
unset SLURM_ARRAY_TASK_ID SLURM_ARRAY_TASK_COUNT SLURM_ARRAY_TASK_MIN SLURM_ARRAY_TASK_MAX SLURM_ARRAY_TASK_STEP
munged_pid="" slurmctld_pid="" slurmd_pid=""

# Everything this cluster started: the daemons, and every process whose environment names our slurm.conf
# (slurmstepd and the jobs' commands inherit it).
cluster_pids() {
  local f pid
  for f in /proc/[0-9]*/environ; do
    pid=${f#/proc/}
    pid=${pid%/environ}
    if [ "$pid" = $$ ] || [ "$pid" = "$BASHPID" ]; then continue; fi
    if { tr "\0" "\n" <"$f"; } 2>/dev/null | grep -qx "SLURM_CONF=$SLURM_CONF"; then echo "$pid"; fi
  done
}
stop_pid() {  # TERM, then KILL after 10 s
  local pid=$1 i
  kill -0 "$pid" 2>/dev/null || return 0
  kill -TERM "$pid" 2>/dev/null || true
  for ((i = 0; i < 100; ++i)); do kill -0 "$pid" 2>/dev/null || return 0; sleep 0.1; done
  kill -KILL "$pid" 2>/dev/null || true
}
cleanup() {
  local status=$? pid f
  trap - EXIT INT TERM
  set +e
  if [ -n "$slurmctld_pid" ] && kill -0 "$slurmctld_pid" 2>/dev/null; then
    scancel --quiet --user=root 2>/dev/null
    for ((i = 0; i < 50; ++i)); do [ -z "$(squeue -h 2>/dev/null)" ] && break; sleep 0.2; done
  fi
  for pid in $slurmd_pid $slurmctld_pid; do stop_pid "$pid"; done
  for pid in $(cluster_pids); do stop_pid "$pid"; done
  [ -z "$munged_pid" ] || stop_pid "$munged_pid"
  if [ "$status" != 0 ] && [ "$status" != "$SKIP" ]; then
    for f in "$tmp"/log/* "$tmp"/jobs/*; do
      [ -f "$f" ] || continue
      echo "----- $f (last 30 lines)"
      tail -n 30 "$f"
    done
  fi
  if [ "$keep" = 1 ]; then log "kept $tmp"; else rm -rf "$tmp"; fi
  exit "$status"
}
trap cleanup EXIT
trap 'exit 130' INT
trap 'exit 143' TERM

# munge: a key of our own, our own socket.
mungekey --create --keyfile="$tmp/key/munge.key"
munged --foreground --key-file="$tmp/key/munge.key" --socket="$tmp/run/munge.sock" \
  --pid-file="$tmp/run/munged.pid" --seed-file="$tmp/key/munged.seed" --log-file="$tmp/log/munged.log" \
  >"$tmp/log/munged.out" 2>&1 &
munged_pid=$!
for ((i = 0; ; ++i)); do
  munge -n -S "$tmp/run/munge.sock" 2>/dev/null | unmunge -S "$tmp/run/munge.sock" >/dev/null 2>&1 && break
  kill -0 "$munged_pid" 2>/dev/null || fail "munged exited (log above)"
  [ "$i" -lt 100 ] || fail "munged not answering after 10 s"
  sleep 0.1
done

# slurm.conf: one node (this machine as slurmd -C sees it), no cgroups, no accounting, free ports.
node=$(hostname -s)
cpus=$(slurmd -C | sed -n 's/.*\bCPUs=\([0-9]*\).*/\1/p')
read -r ctld_port slurmd_port < <(python3 -c '
import socket
socks = [socket.socket() for _ in range(2)]
for s in socks: s.bind(("127.0.0.1", 0))
print(*(s.getsockname()[1] for s in socks))')
cat >"$SLURM_CONF" <<EOF
ClusterName=aartest
SlurmctldHost=$node(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$tmp/run/munge.sock
CredType=cred/munge
StateSaveLocation=$tmp/state
SlurmdSpoolDir=$tmp/spool
SlurmctldPidFile=$tmp/run/slurmctld.pid
SlurmdPidFile=$tmp/run/slurmd.pid
SlurmctldLogFile=$tmp/log/slurmctld.log
SlurmdLogFile=$tmp/log/slurmd.log
MailProg=/bin/true
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/builtin
DependencyParameters=kill_invalid_depend
ReturnToService=2
MinJobAge=600
NodeName=$node NodeAddr=127.0.0.1 CPUs=$cpus State=UNKNOWN
PartitionName=aar Nodes=$node Default=YES MaxTime=INFINITE State=UP
EOF
slurmctld -D -c -i >"$tmp/log/slurmctld.out" 2>&1 &
slurmctld_pid=$!
slurmd -D -N "$node" >"$tmp/log/slurmd.out" 2>&1 &
slurmd_pid=$!
for ((i = 0; ; ++i)); do
  [ "$(sinfo -h -n "$node" -o %t 2>/dev/null)" = idle ] && break
  kill -0 "$slurmctld_pid" 2>/dev/null || fail "slurmctld exited"
  kill -0 "$slurmd_pid" 2>/dev/null || fail "slurmd exited"
  [ "$i" -lt 300 ] || fail "node $node not idle after 30 s: $(sinfo 2>&1)"
  sleep 0.1
done
log "one-node cluster up: node $node, $cpus CPUs, slurmctld port $ctld_port, slurmd port $slurmd_port"

# A small flight path: 8 samples of conops.csv across its regions.
awk -F, 'NR == 1 || (NR - 2) ~ /^(50|100|150|250|350|400|500|600)$/' "$repo/flightpaths/conops.csv" >"$tmp/path.csv"
[ "$(wc -l <"$tmp/path.csv")" = 9 ] || fail "path.csv: expected 8 samples"
tasks=3 msaa=4

# The workflow on the cluster, as documented.
mkdir -p "$tmp/slurm" "$tmp/single" "$tmp/jobs"
log "scripts/slurm-submit.sh: $tasks render tasks, $tasks analysis tasks, MSAA x$msaa"
# Relative paths (the script makes them absolute), and a results folder whose name needs quoting in --wrap.
results="slurm/it's results"
(cd "$tmp" && "$repo/scripts/slurm-submit.sh" slurm/tiny --flight-path path.csv --msaa "$msaa" --tasks "$tasks" \
  --cpus-per-task 1 --results "$results" --logs jobs --render "$render" --analyze "$analyze") >"$tmp/submitted" ||
  fail "slurm-submit.sh failed"
cat "$tmp/submitted"
mapfile -t jobs < <(awk '{print $2}' "$tmp/submitted")
[ "${#jobs[@]}" = 6 ] || fail "slurm-submit.sh printed ${#jobs[@]} steps, expected 6"
for ((i = 0; ; ++i)); do
  [ -z "$(squeue -h)" ] && break
  [ "$i" -lt 3000 ] || fail "jobs still queued after 300 s: $(squeue)"
  sleep 0.1
done
for j in "${jobs[@]}"; do
  states=$(scontrol -o show job "$j" | grep -o 'JobState=[A-Z_]* .*ExitCode=[0-9:]*' | sed 's/ .*ExitCode=/ /' | sort | uniq -c)
  echo "$states" | grep -qv 'JobState=COMPLETED 0:0' && fail "job $j ($(grep " $j " "$tmp/submitted" | cut -c1-10)): $states"
done
log "all 6 steps completed (render and analysis arrays of $tasks tasks)"

# The same workflow in single processes.
(cd "$tmp/single" && "$render" calib tiny --msaa "$msaa" --no-progress &&
  "$render" render tiny --msaa "$msaa" --flight-path ../path.csv --no-progress &&
  "$analyze" calibrate tiny --out results/tiny-calibration &&
  "$analyze" run tiny --calibration results/tiny-calibration/calibration.yaml --no-progress \
    --out results/tiny-shelled) >"$tmp/log/single.log" 2>&1 || fail "single-process workflow failed"
log "single-process workflow done"

# The comparisons.
grep -q '"complete": true' "$tmp/slurm/tiny/manifest.json" || fail "the Slurm dataset's manifest is not complete"
files=$(cd "$tmp/slurm/tiny" && find . -type f | wc -l)
diff -r "$tmp/slurm/tiny" "$tmp/single/tiny" || fail "datasets differ"
log "datasets identical: $files files, byte for byte"
diff -r "$tmp/$results/tiny-calibration" "$tmp/single/results/tiny-calibration" || fail "calibrations differ"
log "calibrations identical, byte for byte"
for ((k = 0; k < tasks; ++k)); do
  [ -f "$tmp/$results/tiny-shelled-shard${k}of$tasks/run.json" ] || fail "shard $k/$tasks: no run.json"
done
python3 "$repo/tests/slurm/compare_outputs.py" "$tmp/$results/tiny-shelled" "$tmp/single/results/tiny-shelled" \
  "$tasks" || fail "merged run differs from the single run"

# Every command line of the script the documentation shows is accepted (--dry-run: printed, not submitted).
shown=0
while IFS= read -r line; do
  line=${line%%#*}
  eval "set -- ${line#scripts/slurm-submit.sh}"
  (cd "$repo" && scripts/slurm-submit.sh --render "$render" --analyze "$analyze" "$@" --dry-run) >"$tmp/dry.out" ||
    fail "documented command fails with --dry-run: $line"
  [ "$(grep -c '^sbatch ' "$tmp/dry.out")" = 6 ] || fail "documented command does not print 6 sbatch commands: $line"
  shown=$((shown + 1))
done < <(cd "$repo" && cat README.md docs/analysis.md docs/rendering.md | grep '^scripts/slurm-submit.sh ')
[ "$shown" -ge 3 ] || fail "README.md, docs/analysis.md and docs/rendering.md show $shown slurm-submit.sh commands, expected 3 or more"
log "the $shown command lines of the documentation are accepted (--dry-run)"

# Bad input: one line on stderr, exit 1, nothing submitted.
before=$(scontrol -o show jobs | wc -l)
bad() {  # bad EXPECTED_MESSAGE ARGS...
  local expected=$1 rc=0
  shift
  (cd "$tmp" && "$repo/scripts/slurm-submit.sh" --render "$render" --analyze "$analyze" "$@") \
    >"$tmp/bad.out" 2>"$tmp/bad.err" || rc=$?
  [ "$rc" = 1 ] || fail "slurm-submit.sh $*: exit $rc, expected 1"
  if [ "$(wc -l <"$tmp/bad.err")" != 1 ] || ! grep -qF -- "$expected" "$tmp/bad.err" ||
    ! grep -q "^slurm-submit.sh: error: " "$tmp/bad.err"; then
    fail "slurm-submit.sh $*: stderr '$(cat "$tmp/bad.err")', expected one line with '$expected'"
  fi
  [ ! -s "$tmp/bad.out" ] || fail "slurm-submit.sh $*: printed '$(cat "$tmp/bad.out")'"
}
bad "no DATASET" --tasks 2
bad "one DATASET expected" a b
bad "unknown option '--task'" bad --task 2
bad "--tasks '0'" bad --tasks 0
bad "--msaa '3'" bad --msaa 3
bad "--model 'half'" bad --model half
bad "--flight-path 'missing.csv': not a readable file" bad --flight-path missing.csv
bad "--render '/nonexistent'" bad --render /nonexistent
bad "--results 'path.csv': exists and is not a folder" bad --results path.csv
bad "--tasks needs a value" bad --tasks
[ "$(scontrol -o show jobs | wc -l)" = "$before" ] || fail "a refused command submitted jobs"
[ ! -e "$tmp/bad" ] || fail "a refused command created the dataset folder"
# A step that sbatch refuses (an array past MaxArraySize) cancels the step submitted before it.
rc=0
(cd "$tmp" && "$repo/scripts/slurm-submit.sh" refused --tasks 5000 --results refused-results \
  --render "$render" --analyze "$analyze") >"$tmp/bad.out" 2>"$tmp/bad.err" || rc=$?
if [ "$rc" != 1 ] || ! grep -q "^slurm-submit.sh: error: sbatch refused the render step" "$tmp/bad.err"; then
  fail "--tasks 5000: exit $rc, stderr '$(cat "$tmp/bad.err")'"
fi
calib_job=$(grep -o 'cancelling the steps already submitted (jobs [0-9]*)' "$tmp/bad.err" | grep -o '[0-9]*') ||
  fail "--tasks 5000: no cancelled calib job named: $(cat "$tmp/bad.err")"
for ((i = 0; ; ++i)); do
  [ -z "$(squeue -h)" ] && break
  [ "$i" -lt 100 ] || fail "jobs left queued after a refused step: $(squeue)"
  sleep 0.1
done
scontrol -o show job "$calib_job" | grep -q 'JobState=CANCELLED' || fail "job $calib_job not cancelled"
log "bad input refused: 10 options, nothing submitted; a refused step cancelled job $calib_job before it"
log "passed"
