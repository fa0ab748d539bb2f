#!/usr/bin/env bash
# Submits the whole render-calibrate-analyze-merge workflow of one dataset to Slurm as dependent jobs
# (docs/analysis.md, "Slurm: render, calibrate, analyze, merge"). tests/slurm/slurm_workflow_test.sh runs it
# on a one-node cluster and checks that the merged outputs equal a single-process run's.
set -euo pipefail

prog=slurm-submit.sh

usage() {
  cat <<'EOF'
Usage: scripts/slurm-submit.sh [OPTIONS] DATASET

Submits, with sbatch, the render, calibration and analysis of DATASET as six
steps, each started when the one before it has succeeded (--dependency=afterok):

  calib      aar-render calib DATASET                  one job        } together, into
  render     aar-render render DATASET                 array 0..N-1   } one dataset
  finalize   aar-render finalize DATASET               one job
  calibrate  aar-analyze calibrate DATASET --out RESULTS/NAME-calibration
  run        aar-analyze run DATASET --calibration RESULTS/NAME-calibration/calibration.yaml
                 --out RESULTS/NAME-MODEL-shardKofN    array 0..N-1
  merge      aar-analyze merge RESULTS/NAME-MODEL-shard*ofN --out RESULTS/NAME-MODEL

The array tasks take their shard K/N from Slurm's array variables. Prints one
line per step: its name, its job id and what it writes. A failed step leaves
the later ones pending (reason DependencyNeverSatisfied) unless the cluster
sets DependencyParameters=kill_invalid_depend; re-submitting resumes the
render (complete frames are skipped) and replaces the analysis outputs.

Options:
  --tasks N            array tasks of the render and of the analysis (default 8)
  --msaa N             samples per pixel, calib and render: 1, 4, 8, 16 or 32 (default 16)
  --flight-path CSV    flight path of the render (default: aar-render's, flightpaths/conops.csv)
  --rig JSON           camera rig of calib and render (default: aar-render's, scenes/rig.json)
  --model M            reference model of the analysis: shelled or full (default shelled)
  --results DIR        folder of the analysis outputs (default results)
  --name NAME          their base name (default: DATASET's folder name)
  --render-arg ARG     one more argument for `aar-render render` (repeat it: --render-arg --depth); not
                       --frames: a partial dataset fails finalize (exit 3), so give a shorter --flight-path
  --calib-arg ARG      one more argument for `aar-render calib` (--calib-arg --far-boards=none)
  --run-arg ARG        one more argument for `aar-analyze run` (--run-arg --preset=thesis)
  --cpus-per-task N    CPUs of each render task (default 2)
  --sbatch-arg ARG     one more argument for every sbatch (--sbatch-arg --partition=gpu)
  --logs DIR           job output files DIR/aar-STEP-JOBID[_TASK].out (default: sbatch's, slurm-JOBID.out
                       in the current folder)
  --render PATH        aar-render (default: build/renderer/aar-render beside this script, else the one on PATH)
  --analyze PATH       aar-analyze (default: build/analyzer/aar-analyze beside this script, else the one on PATH)
  --dry-run            print the sbatch commands instead of running them (job ids shown as $STEP)
  -h, --help           this text

Paths are made absolute, so the jobs find them from any working folder; the
compute nodes must see them at the same place. Exit status: 0 when every step
was submitted; 1 with one line "slurm-submit.sh: error: ..." on stderr when an
option or path is refused (nothing is submitted) or sbatch refuses a step
(the steps already submitted are cancelled).

Example (4 tasks, then wait for the merge and look at the merged summary):
  scripts/slurm-submit.sh datasets/conops-x16 --msaa 16 --tasks 4
  cat results/conops-x16-shelled/summary.md
EOF
}

die() {
  echo "$prog: error: $*" >&2
  exit 1
}

# quote WORD: REPLY = WORD as one word for /bin/sh (sbatch --wrap): as it is when it holds only safe
# characters, else single-quoted (a ' inside written '\''). No subshell: the merge lists every shard.
quote() {
  if [[ $1 =~ ^[A-Za-z0-9_./:=,%@+-]+$ ]]; then
    REPLY=$1
  else
    REPLY="'${1//\'/\'\\\'\'}'"
  fi
}
# quote_all WORD...: REPLY = the words quoted, space-separated.
quote_all() {
  local out="" a
  for a in "$@"; do
    quote "$a"
    out+="${out:+ }$REPLY"
  done
  REPLY=$out
}

positive_int() { [[ $1 =~ ^[1-9][0-9]{0,5}$ ]]; }

script_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
repo=$(dirname "$script_dir")

tasks=8 msaa=16 model=shelled results=results name="" flight_path="" rig="" cpus=2 logs="" dry_run=0
render="" analyze="" dataset=""
render_args=() calib_args=() run_args=() sbatch_args=()

positionals=()
while [ $# -gt 0 ]; do
  opt=$1 value="" has_value=0
  if [[ $opt == --*=* ]]; then  # --opt=value is --opt value
    value=${opt#*=} opt=${opt%%=*} has_value=1
  fi
  shift
  case $opt in
    -h | --help | --dry-run)
      [ "$has_value" = 0 ] || die "$opt takes no value"
      if [ "$opt" = --dry-run ]; then dry_run=1; else usage; exit 0; fi
      continue ;;
    --tasks | --msaa | --flight-path | --rig | --model | --results | --name | --render-arg | --calib-arg | \
      --run-arg | --cpus-per-task | --sbatch-arg | --logs | --render | --analyze)
      if [ "$has_value" = 0 ]; then
        [ $# -gt 0 ] || die "$opt needs a value (--help)"
        value=$1
        shift
      fi ;;
    --) positionals+=("$@"); break ;;
    -?*) die "unknown option '$opt' (--help)" ;;
    *) positionals+=("$opt"); continue ;;
  esac
  case $opt in
    --tasks) tasks=$value ;;
    --msaa) msaa=$value ;;
    --flight-path) flight_path=$value ;;
    --rig) rig=$value ;;
    --model) model=$value ;;
    --results) results=$value ;;
    --name) name=$value ;;
    --render-arg) render_args+=("$value") ;;
    --calib-arg) calib_args+=("$value") ;;
    --run-arg) run_args+=("$value") ;;
    --cpus-per-task) cpus=$value ;;
    --sbatch-arg) sbatch_args+=("$value") ;;
    --logs) logs=$value ;;
    --render) render=$value ;;
    --analyze) analyze=$value ;;
  esac
done
[ "${#positionals[@]}" -le 1 ] || die "one DATASET expected, got ${#positionals[@]}: ${positionals[*]}"
[ "${#positionals[@]}" -eq 0 ] || dataset=${positionals[0]}

# Everything is checked before the first sbatch.
[ -n "$dataset" ] || die "no DATASET given (usage: scripts/slurm-submit.sh [OPTIONS] DATASET; --help)"
positive_int "$tasks" || die "--tasks '$tasks': expected a whole number from 1"
positive_int "$cpus" || die "--cpus-per-task '$cpus': expected a whole number from 1"
case $msaa in 1 | 4 | 8 | 16 | 32) ;; *) die "--msaa '$msaa': expected 1, 4, 8, 16 or 32" ;; esac
case $model in shelled | full) ;; *) die "--model '$model': expected shelled or full" ;; esac

absolute() { realpath -m -- "$1"; }
tool() {  # tool OPTION GIVEN RELATIVE_BUILD_PATH NAME
  local path
  if [ -n "$2" ]; then
    path=$2
    [[ $path == */* ]] || path=$(command -v -- "$path") || die "$1 '$2': not found on PATH"
  elif [ -x "$repo/$3" ]; then
    path=$repo/$3
  else
    path=$(command -v "$4") || die "$4 not found: neither $repo/$3 nor $4 on PATH (build it, or pass $1)"
  fi
  if [ ! -f "$path" ] || [ ! -x "$path" ]; then die "$1 '$path': not an executable file"; fi
  "$path" --version >/dev/null 2>&1 || die "$1 '$path': '$path --version' fails"
  absolute "$path"
}
render=$(tool --render "$render" build/renderer/aar-render aar-render)
analyze=$(tool --analyze "$analyze" build/analyzer/aar-analyze aar-analyze)

[ ! -e "$dataset" ] || [ -d "$dataset" ] || die "DATASET '$dataset': exists and is not a folder"
dataset=$(absolute "$dataset")
[ "$dataset" != / ] || die "DATASET '/': not a dataset folder"
[ -n "$name" ] || name=$(basename "$dataset")
[[ $name != */* && $name != . && $name != .. ]] || die "--name '$name': not a folder name"
[ ! -e "$results" ] || [ -d "$results" ] || die "--results '$results': exists and is not a folder"
results=$(absolute "$results")
for pair in "--flight-path:$flight_path" "--rig:$rig"; do
  opt=${pair%%:*} file=${pair#*:}
  [ -z "$file" ] || { [ -f "$file" ] && [ -r "$file" ]; } || die "$opt '$file': not a readable file"
done
[ -z "$flight_path" ] || flight_path=$(absolute "$flight_path")
[ -z "$rig" ] || rig=$(absolute "$rig")
if [ -n "$logs" ]; then
  [ ! -e "$logs" ] || [ -d "$logs" ] || die "--logs '$logs': exists and is not a folder"
  logs=$(absolute "$logs")
fi
if [ "$dry_run" = 0 ]; then
  command -v sbatch >/dev/null || die "sbatch not found on PATH (is this a Slurm login node? --dry-run prints the commands)"
  mkdir -p -- "$results" 2>/dev/null || die "--results '$results': cannot create it"
  [ -z "$logs" ] || mkdir -p -- "$logs" 2>/dev/null || die "--logs '$logs': cannot create it"
fi

# The commands of the six steps.
rig_args=()
[ -z "$rig" ] || rig_args=(--rig "$rig")
path_args=()
[ -z "$flight_path" ] || path_args=(--flight-path "$flight_path")
calibration=$results/$name-calibration
shard_prefix=$results/$name-$model-shard
merged=$results/$name-$model
last=$((tasks - 1))

quote_all "$render" calib "$dataset" --msaa "$msaa" "${rig_args[@]}" "${calib_args[@]}" --no-progress
calib_cmd=$REPLY
quote_all "$render" render "$dataset" --msaa "$msaa" "${rig_args[@]}" "${path_args[@]}" "${render_args[@]}" \
  --no-progress
render_cmd=$REPLY
quote_all "$render" finalize "$dataset"
finalize_cmd=$REPLY
quote_all "$analyze" calibrate "$dataset" --out "$calibration"
calibrate_cmd=$REPLY
# Task K of the array (SLURM_ARRAY_TASK_ID, from 0) analyzes shard K/N, which aar-analyze reads from the array
# variables; its output is named here as aar-analyze would name it in results/.
quote_all "$analyze" run "$dataset" --model "$model" --calibration "$calibration/calibration.yaml" "${run_args[@]}" \
  --no-progress --out
run_cmd=$REPLY
quote "$shard_prefix"
run_cmd+=" $REPLY\"\$SLURM_ARRAY_TASK_ID\""
quote "of$tasks"
run_cmd+=$REPLY
shards=()
for ((k = 0; k < tasks; ++k)); do shards+=("$shard_prefix${k}of$tasks"); done
quote_all "$analyze" merge "${shards[@]}" --out "$merged"
merge_cmd=$REPLY

submitted=()
cancel_submitted() {
  if [ "${#submitted[@]}" -gt 0 ]; then
    echo "$prog: cancelling the steps already submitted (jobs ${submitted[*]})" >&2
    scancel "${submitted[@]}" || echo "$prog: scancel failed: cancel jobs ${submitted[*]} yourself" >&2
  fi
}

# submit STEP [SBATCH OPTIONS...] -- COMMAND: sets job_id (with --dry-run: prints the sbatch command, $STEP).
job_id=""
submit() {
  local step=$1 args=() cmd out
  shift
  while [ "$1" != -- ]; do args+=("$1"); shift; done
  cmd=$2
  args=(--parsable --job-name="aar-$step" "${sbatch_args[@]}" "${args[@]}")
  if [ -n "$logs" ]; then
    case " ${args[*]} " in
      *" --array="*) args+=(--output="$logs/aar-$step-%A_%a.out") ;;
      *) args+=(--output="$logs/aar-$step-%j.out") ;;
    esac
  fi
  if [ "$dry_run" = 1 ]; then
    quote "$cmd"
    local wrap=$REPLY
    quote_all sbatch "${args[@]}"
    printf '%s --wrap %s\n' "$REPLY" "$wrap"
    job_id="\$$step"
    return
  fi
  if ! out=$(sbatch "${args[@]}" --wrap "$cmd"); then
    cancel_submitted
    die "sbatch refused the $step step (its message is above); nothing of this workflow is left queued"
  fi
  out=${out%%;*}  # --parsable prints JOBID[;CLUSTER]
  if ! [[ $out =~ ^[0-9]+$ ]]; then
    submitted+=("$out")
    cancel_submitted
    die "sbatch printed '$out' for the $step step, not a job id"
  fi
  submitted+=("$out")
  job_id=$out
}

submit calib -- "$calib_cmd"
calib_id=$job_id
submit render --array="0-$last" --cpus-per-task="$cpus" -- "$render_cmd"
render_id=$job_id
submit finalize --dependency="afterok:$calib_id:$render_id" -- "$finalize_cmd"
finalize_id=$job_id
submit calibrate --dependency="afterok:$finalize_id" -- "$calibrate_cmd"
calibrate_id=$job_id
submit run --dependency="afterok:$calibrate_id" --array="0-$last" -- "$run_cmd"
run_id=$job_id
submit merge --dependency="afterok:$run_id" -- "$merge_cmd"
merge_id=$job_id

printf '%-10s %-10s %s\n' calib "$calib_id" "$dataset/calib" \
  render "$render_id" "$dataset/frames (array 0-$last)" \
  finalize "$finalize_id" "$dataset/manifest.json" \
  calibrate "$calibrate_id" "$calibration" \
  run "$run_id" "${shard_prefix}Kof$tasks (array 0-$last)" \
  merge "$merge_id" "$merged"
