#!/usr/bin/env bash
# Runs one pipeline step and appends its wall time to a log: step.sh LOG STAGE TARGET command...
# LOG lines are tab-separated: stage, target, start and end (seconds since the epoch), exit code.
# The command's exit code is passed on, so make sees the step fail.
log=$1 stage=$2 target=$3
shift 3
mkdir -p "$(dirname "$log")"
start=$(date +%s.%N)
"$@"
code=$?
printf '%s\t%s\t%s\t%s\t%d\n' "$stage" "$target" "$start" "$(date +%s.%N)" "$code" >> "$log"
exit "$code"
