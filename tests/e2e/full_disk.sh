#!/usr/bin/env bash
# Full disk: each stage that writes big files, run against a small tmpfs (when this process may
# mount one: root in a privileged container) and under RLIMIT_FSIZE (ulimit -f, always), must exit
# 4 naming the file and the system error, leave no temporary behind, no report, and no file
# under a final name that differs from a complete run's.
# Usage: bash full_disk.sh <build_dir> <source_dir>
set -euo pipefail
build=$1
source=$2
tools=$build/tools
source "$(dirname "$0")/support/common.bash"
require_tools surfcap-synth surfcap-align surfcap-learn surfcap-precompute
work=$(mktemp -d "${TMPDIR:-/tmp}/full_disk.XXXXXX")
mounted=()
cleanup() {
  for dir in "${mounted[@]}"; do umount "$dir" 2> /dev/null || true; done
  rm -rf "$work"
}
trap cleanup EXIT
faults=0


# check_failed NAME REFERENCE OUT CODE LOG REPORT EXPECTED_ERROR
check_failed() {
  local name=$1 reference=$2 out=$3 code=$4 log=$5 report=$6 expected=$7 file
  [[ $code -eq 4 ]] || { echo "FAIL: $name exited $code, not 4:"; tail -3 "$log"; exit 1; }
  grep -q "$expected" "$log" || { echo "FAIL: $name: the message does not say '$expected':"; tail -3 "$log"; exit 1; }
  grep -q "'$out/" "$log" || { echo "FAIL: $name: the message names no output file:"; tail -3 "$log"; exit 1; }
  [[ -z $(find "$out" -name '.*.tmp-*' 2> /dev/null) ]] || { echo "FAIL: $name left temporaries"; exit 1; }
  [[ ! -e $out/$report ]] || { echo "FAIL: $name wrote its report $report although it failed"; exit 1; }
  while IFS= read -r file; do
    cmp -s "$reference/$file" "$out/$file" || { echo "FAIL: $name: $out/$file is corrupt"; exit 1; }
  done < <(final_files "$out")
  faults=$((faults + 1))
  echo "$name: exit 4, $(final_files "$out" | wc -l) complete files kept: $(grep -o "'$out/[^']*'[^;]*" "$log" | head -1 | sed "s|$out/||")"
}

# Can this process mount a tmpfs?
can_mount=0
mkdir -p "$work/probe"
if mount -t tmpfs -o size=64k tmpfs "$work/probe" 2> /dev/null; then
  umount "$work/probe"
  can_mount=1
fi

# disk_case NAME REPORT -- command with __OUT__...: reference run, then full-disk runs, all at
# the same output path (outputs may record it).
disk_case() {
  local name=$1 report=$2
  shift 3
  local reference=$work/ref/$name out=$work/out/$name
  mkdir -p "$work/ref" "$out"
  "${@//__OUT__/$out}" > /dev/null 2>&1
  mv "$out" "$reference"
  mkdir -p "$out"
  local bytes largest code
  bytes=$(du -sb "$reference" | cut -f1)
  largest=$(find "$reference" -type f -printf '%s\n' | sort -n | tail -1)
  if [[ $can_mount -eq 1 ]]; then
    local share
    for share in 20 60 90; do  # per cent of what the complete run needs
      mount -t tmpfs -o size=$((bytes * share / 100 / 1024 + 4))k tmpfs "$out"
      mounted+=("$out")
      code=0
      "${@//__OUT__/$out}" > "$work/log" 2>&1 || code=$?
      check_failed "$name on a tmpfs of $share% of its $((bytes / 1024)) KiB" "$reference" "$out" $code "$work/log" \
        "$report" "No space left on device"
      umount "$out"
      mounted=()
    done
  fi
  # RLIMIT_FSIZE below the largest output: writes past it fail with EFBIG.
  code=0
  (ulimit -f $((largest / 1024 / 2 + 1)) && "${@//__OUT__/$out}") > "$work/log" 2>&1 || code=$?
  check_failed "$name under RLIMIT_FSIZE of $((largest / 2048 + 1)) KiB" "$reference" "$out" $code "$work/log" \
    "$report" "File too large"
  rm -rf "$out"
}

quiet=(--log-level error --threads 2)
disk_case synth ground_truth/report.json -- "$tools/surfcap-synth" --preset tiny --no-images --out __OUT__ "${quiet[@]}"
capture=$work/ref/synth
database=$capture/ground_truth/database/database.json
disk_case histograms report/histograms.json -- "$tools/surfcap-align" histograms --capture "$capture" --out __OUT__ \
  "${quiet[@]}"
disk_case learn report/learn.json -- "$tools/surfcap-learn" learn --database "$database" \
  --parts "$source/configs/parts/human6.json" --examples 12 --output __OUT__ "${quiet[@]}"
disk_case spaces report/spaces.json -- "$tools/surfcap-precompute" --threads 2 --log-level error spaces \
  --database "$database" --graph "$source/configs/graphs/tiny.json" --output __OUT__ --space jump --sweep-mm 5 20 \
  --validation-samples 4
[[ $can_mount -eq 1 ]] || echo "(no tmpfs: this process may not mount; RLIMIT_FSIZE cases only)"
echo "full_disk: $faults full-disk faults, each exit 4 with no corrupt file: ok"
