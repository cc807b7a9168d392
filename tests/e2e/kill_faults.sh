#!/usr/bin/env bash
# Fault injection: stages killed with SIGKILL at seeded random points on the synth tiny capture:
# at a random time, and (with strace) exactly at a random write or rename call of their outputs. After every kill, each file under a final name
# is complete and byte-identical to a reference run's (no partial file looks finished; a previous
# run's outputs stay intact), a stage's report exists only if every output does, and the next run
# completes with byte-identical outputs (reports aside: they hold timings) and removes the hidden
# temporaries the killed runs left.
# Usage: bash kill_faults.sh <build_dir> <source_dir>
# Environment: SURFCAP_KILLS (kills per stage, default 3), SURFCAP_KILL_SEED (default 1).
set -euo pipefail
build=$1
source=$2
tools=$build/tools
source "$(dirname "$0")/support/common.bash"
require_tools surfcap-synth surfcap-align surfcap-learn surfcap-precompute
work=$(mktemp -d "${TMPDIR:-/tmp}/kill_faults.XXXXXX")
trap 'rm -rf "$work"' EXIT
kills_per_stage=${SURFCAP_KILLS:-3}
RANDOM=${SURFCAP_KILL_SEED:-1}
total_kills=0
total_checked=0
hidden=0
# strace fault injection when ptrace is allowed here; timed kills otherwise.
use_strace=0
# LeakSanitizer cannot run under ptrace: traced runs of a sanitizer build do without it.
traced_asan=${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0
if command -v strace > /dev/null && strace -qq -o /dev/null -e inject=getpid:retval=0 true 2> /dev/null; then use_strace=1; fi


# Every final file in $2 must exist in $1 with the same bytes (reports: only well-formed JSON).
check_complete() {
  local reference=$1 out=$2 file
  while IFS= read -r file; do
    [[ -e $reference/$file ]] || { echo "FAIL: $out/$file is not an output of the reference run"; exit 1; }
    if [[ $file == report/* || $file == report.json || $file == */report.json ]]; then
      python3 -c 'import json,sys; json.load(open(sys.argv[1]))' "$out/$file" \
        || { echo "FAIL: report $out/$file is not complete JSON"; exit 1; }
    else
      cmp -s "$reference/$file" "$out/$file" || { echo "FAIL: $out/$file differs from the reference (partial?)"; exit 1; }
    fi
    total_checked=$((total_checked + 1))
  done < <(final_files "$out")
}

# $1 reference dir, $2 out dir, $3 the stage's report (relative): if it exists, so does every output.
check_report_means_done() {
  [[ -e $2/$3 ]] || return 0
  diff <(final_files "$1") <(final_files "$2") > /dev/null \
    || { echo "FAIL: $2/$3 exists but outputs are missing: $(diff <(final_files "$1") <(final_files "$2") | head -3)"; exit 1; }
}

# run_killed NAME REFERENCE OUT REPORT HOW -- command...: runs the command and kills it with
# SIGKILL, then checks OUT. HOW is "after:SECONDS" (at a random share of SECONDS) or
# "at:SYSCALL:COUNT" (strace fault injection: SIGKILL on the random n-th of COUNT write or
# rename calls, i.e. in the middle of an output or between its completion and its rename).
run_killed() {
  local name=$1 reference=$2 out=$3 report=$4 how=$5
  shift 6
  local point pid
  if [[ $how == after:* ]]; then
    point=$(awk -v r=$RANDOM -v s="${how#after:}" 'BEGIN { printf "%.3f", s * (0.05 + 0.9 * r / 32767) }')
    "$@" > /dev/null 2>&1 &
    pid=$!
    sleep "$point"
    kill -KILL "$pid" 2> /dev/null && total_kills=$((total_kills + 1))
    wait "$pid" 2> /dev/null || true
    point="after ${point}s"
  else
    local call count
    IFS=: read -r _ call count <<< "$how"
    local n=$((1 + RANDOM % count))
    local code=0
    (ASAN_OPTIONS=$traced_asan strace -f -qq -o /dev/null -e trace="$call" -e inject="$call":signal=SIGKILL:when=$n "$@" > /dev/null 2>&1) \
      2> /dev/null || code=$?
    [[ $code -ne 0 ]] && total_kills=$((total_kills + 1))
    point="at $call $n of $count"
  fi
  check_complete "$reference" "$out"
  check_report_means_done "$reference" "$out" "$report"
  echo "$name: killed $point, $(final_files "$out" | wc -l) final files checked"
}

# Calls of `syscall` the reference run made ($1: strace -c summary).
calls() { awk -v c="$2" '$NF == c { print $4 }' "$1"; }

# stage NAME OUT_NAME REPORT -- command with __OUT__ for the output directory...
# Every run of a stage writes to the same path (outputs may record it): a timed reference run,
# moved to ref/; kills into a fresh directory, then a full run there; kills over a copy of the
# reference (a previous complete run).
stage() {
  local name=$1 out_name=$2 report=$3
  shift 4
  local reference=$work/ref/$out_name run=$work/run/$out_name
  local start end seconds
  mkdir -p "$(dirname "$reference")" "$(dirname "$run")"
  start=$(date +%s.%N)
  "${@//__OUT__/$run}" > /dev/null
  end=$(date +%s.%N)
  mv "$run" "$reference"
  seconds=$(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.3f", b - a }')
  local ways=("after:$seconds")
  if [[ $use_strace -eq 1 ]]; then
    ASAN_OPTIONS=$traced_asan strace -f -qq -c -o "$work/calls.txt" -e trace=write,rename "${@//__OUT__/$run}" > /dev/null
    rm -rf "$run"
    ways+=("at:write:$(calls "$work/calls.txt" write)" "at:rename:$(calls "$work/calls.txt" rename)")
  fi
  echo "$name: reference run ${seconds}s, $(final_files "$reference" | wc -l) files"
  for ((k = 0; k < kills_per_stage; ++k)); do
    run_killed "$name (fresh)" "$reference" "$run" "$report" "${ways[k % ${#ways[@]}]}" -- "${@//__OUT__/$run}"
  done
  # The next run completes: same files, same bytes.
  "${@//__OUT__/$run}" > /dev/null
  diff <(final_files "$reference") <(final_files "$run") \
    || { echo "FAIL: the run after the kills does not give the reference's files"; exit 1; }
  check_complete "$reference" "$run"
  # ... and removes the temporaries the killed runs left (core AtomicFile).
  local left
  left=$(find "$run" -name '.*.tmp-*' | wc -l)
  [[ $left -eq 0 ]] || { echo "FAIL: the run after the kills left $left temporaries of killed runs"; exit 1; }
  rm -rf "$run"
  cp -a "$reference" "$run"
  run_killed "$name (over a previous run)" "$reference" "$run" "$report" "${ways[-1]}" -- "${@//__OUT__/$run}"
  diff <(final_files "$reference") <(final_files "$run") > /dev/null \
    || { echo "FAIL: a killed rerun lost outputs of the previous run in $run"; exit 1; }
  hidden=$((hidden + $(find "$run" -name '.*.tmp-*' | wc -l)))
  rm -rf "$run"
}

quiet=(--log-level error --threads 2)
stage synth capture ground_truth/report.json -- "$tools/surfcap-synth" --preset tiny --no-images --out __OUT__ "${quiet[@]}"
capture=$work/ref/capture
database=$capture/ground_truth/database/database.json
[[ -f $database ]] || { echo "FAIL: synth wrote no ground-truth database"; exit 1; }

stage "align histograms" db-histograms report/histograms.json -- \
  "$tools/surfcap-align" histograms --capture "$capture" --out __OUT__ "${quiet[@]}"
stage "learn" model report/learn.json -- \
  "$tools/surfcap-learn" learn --database "$database" --parts "$source/configs/parts/human6.json" --examples 12 \
  --output __OUT__ "${quiet[@]}"
stage "precompute spaces" spaces report/spaces.json -- \
  "$tools/surfcap-precompute" --threads 2 --log-level error spaces --database "$database" \
  --graph "$source/configs/graphs/tiny.json" --output __OUT__ --space jump --sweep-mm 5 20 --validation-samples 4

echo "kill_faults: $total_kills SIGKILLs, $total_checked final files checked complete, $hidden hidden temporaries left by the last kill of each stage (the next run removes them): ok"
