# Shared by the bad-input catalogues (bad_inputs.sh, hostile_inputs.sh; sourced, not a test).
# The sourcing script sets $work (scratch) and $valid (pristine inputs); each case runs on a fresh
# copy in $case, and a failing tool must leave no file under a final name in $case/out.

tried=0

py() { python3 - "$@"; }
truncate_half() { local size; size=$(stat -c %s "$1"); truncate -s $((size / 2)) "$1"; }
set_format() {  # file new_format_tag
  py "$1" "$2" << 'PY'
import json, sys
d = json.load(open(sys.argv[1])); d["format"] = sys.argv[2]; json.dump(d, open(sys.argv[1], "w"))
PY
}
# json_set FILE PYTHON_STATEMENT: edits a JSON document in place; the statement sees it as `d`.
json_set() {
  py "$1" "$2" << 'PY'
import json, sys
d = json.load(open(sys.argv[1]))
exec(sys.argv[2])
json.dump(d, open(sys.argv[1], "w"))
PY
}

# expect CODE NEEDLE... -- command: runs it (at most SURFCAP_CASE_TIMEOUT s, default 120: a hang
# fails the case), expects the exit code and every NEEDLE in its stderr; no final file may appear
# under $case/out when it fails.
expect() {
  local code=$1
  shift
  local needles=()
  while [[ $1 != -- ]]; do needles+=("$1"); shift; done
  shift
  local got=0
  local limit=${SURFCAP_CASE_TIMEOUT:-120}
  "$@" > "$work/stdout" 2> "$work/stderr" &
  local pid=$!
  # A watchdog instead of timeout(1): the command may be a shell function.
  ( sleep "$limit"; touch "$work/hung"; pkill -KILL -P "$pid"; kill -KILL "$pid" ) 2> /dev/null &
  local watchdog=$!
  rm -f "$work/hung"
  wait "$pid" || got=$?
  kill "$watchdog" 2> /dev/null || true
  tried=$((tried + 1))
  if [[ -e $work/hung ]]; then
    echo "FAIL [$label]: still running after ${SURFCAP_CASE_TIMEOUT:-120} s (a hang)"; exit 1
  fi
  if [[ $got -ne $code ]]; then
    echo "FAIL [$label]: exit $got, expected $code"; tail -3 "$work/stderr"; exit 1
  fi
  if grep -qE "invalid JSON content|internal error" "$work/stderr"; then
    echo "FAIL [$label]: an internal error or a JSON message without its file:"; tail -3 "$work/stderr"; exit 1
  fi
  local needle
  for needle in "${needles[@]}"; do
    grep -qF -- "$needle" "$work/stderr" || { echo "FAIL [$label]: stderr lacks '$needle':"; tail -3 "$work/stderr"; exit 1; }
  done
  if [[ $code -ne 0 && -d $case/out ]] && [[ -n $(find "$case/out" -type f ! -name '.*') ]]; then
    echo "FAIL [$label]: failed but left $(find "$case/out" -type f ! -name '.*' | head -1)"; exit 1
  fi
  printf '  %-58s exit %d  %s\n' "$label" "$got" "$(grep -o "'[^']*'[^:]*: .*" "$work/stderr" | tail -1 | cut -c1-90 | sed "s|$case/||g")"
}
# fresh LABEL: a pristine copy of the valid inputs in $case.
fresh() {
  label=$1
  case=$work/case
  rm -rf "$case"
  cp -a "$valid" "$case"
}
