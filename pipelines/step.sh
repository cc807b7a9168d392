#!/usr/bin/env bash
# Runs one pipeline step and appends its times to a log: step.sh LOG STAGE TARGET command...
# LOG lines are tab-separated: stage, target, start and end (seconds since the epoch), exit code,
# then the CPU seconds (user, system) of the processes the step ran on this machine (with a
# SUBMIT prefix such as srun, only the prefix's own). The command's exit code is passed on.
log=$1 stage=$2 target=$3
shift 3
mkdir -p "$(dirname "$log")"
start=$(date +%s.%N)
"$@"
code=$?
end=$(date +%s.%N)
times_file=$(mktemp)
times > "$times_file"  # line 2: children's user and system time, e.g. 1m2.345s 0m0.012s
cpu=$(sed -n 2p "$times_file" | awk '{ for (i = 1; i <= 2; ++i) { split($i, t, "m"); sub("s", "", t[2]);
                                       printf "\t%.3f", t[1] * 60 + t[2] } }')
rm -f "$times_file"
printf '%s\t%s\t%s\t%s\t%d%s\n' "$stage" "$target" "$start" "$end" "$code" "$cpu" >> "$log"
exit "$code"
