#!/usr/bin/env bash
# pipelines/character.mk on the synthetic tiny capture (ground-truth database, so alignment's
# accuracy is not the point; the similarity row blocks still run):
#  - make -j1 and make -j4 give byte-identical outputs (reports aside);
#  - re-running an up-to-date build runs nothing;
#  - deleting one output redoes exactly the steps that depend on it, with the same bytes;
#  - a step that fails after writing, or is killed mid-way, leaves none of its targets, and the
#    next make redoes it.
# Usage: bash pipeline_make.sh <build_dir> <source_dir>
set -euo pipefail
build=$1
source=$2
# shellcheck source=pipeline_lib.bash
. "$source/tests/e2e/pipeline_lib.bash"
pipeline_require_tools
work=$(mktemp -d "$build/pipeline_e2e.XXXXXX")
trap 'rm -rf "$work"' EXIT
"$build/tools/surfcap-synth" --preset tiny --seed 1 --no-images --out "$work/capture" --log-level warn
read -r -a targets <<< "$(pipeline_targets) similarity"
echo "targets: ${targets[*]}"
common=(DATABASE=truth BLOCKS=3 SPACES_OPTIONS="--sweep-mm 5 --validation-samples 2")

pipeline_make "$work/j1" "${common[@]}" THREADS=1 -j1 "${targets[@]}"
pipeline_make "$work/j4" "${common[@]}" THREADS=2 -j4 "${targets[@]}"
pipeline_same "$work/j1" "$work/j4"
grep -q $'\tout/aligned/similarity/rows/rows-61-92.npy\t' "$work/j4/out/report/steps.tsv" \
  || { echo "the similarity matrix was not built in 3 row blocks"; exit 1; }

# Up to date: nothing runs, nothing is touched.
stamp() { (cd "$1/out" && find . -type f -not -path '*/report/*' -printf '%p %T@\n' | sort); }
before=$(stamp "$work/j4")
steps_before=$(wc -l < "$work/j4/out/report/steps.tsv")
pipeline_make "$work/j4" "${common[@]}" -q "${targets[@]}" || { echo "make -q: not up to date"; exit 1; }
pipeline_make "$work/j4" "${common[@]}" -j4 "${targets[@]}" > "$work/rerun.txt"
[[ $(wc -l < "$work/j4/out/report/steps.tsv") -eq $steps_before ]] || { echo "an up-to-date re-run ran steps"; exit 1; }
[[ $(stamp "$work/j4") == "$before" ]] || { echo "an up-to-date re-run touched outputs"; exit 1; }

# Deleting one output redoes only what depends on it.
expect_steps() {  # expect_steps DIR expected-stage...: the stages of the steps run since $mark
  local got
  got=$(tail -n +$((mark + 1)) "$1/out/report/steps.tsv" | cut -f1 | sort | tr '\n' ' ')
  shift
  local want
  want=$(printf '%s\n' "$@" | sort | tr '\n' ' ')
  [[ $got == "$want" ]] || { echo "steps run: $got; expected: $want"; exit 1; }
}
mark=$(wc -l < "$work/j4/out/report/steps.tsv")
rm "$work/j4/out/parts/parts.json"
pipeline_make "$work/j4" "${common[@]}" -j4 "${targets[@]}"
downstream_of_parts=(learn)
[[ " ${targets[*]} " == *" character "* ]] && downstream_of_parts+=(export)
[[ " ${targets[*]} " == *" previews "* ]] && downstream_of_parts+=(play)
expect_steps "$work/j4" "${downstream_of_parts[@]}"
mark=$(wc -l < "$work/j4/out/report/steps.tsv")
rm "$work/j4/out/aligned/similarity/rows/rows-30-61.npy"
pipeline_make "$work/j4" "${common[@]}" -j4 "${targets[@]}"
expect_steps "$work/j4" align.similarity align.merge align.tree
pipeline_same "$work/j1" "$work/j4"

# A step that fails after writing its outputs: make removes them and stops.
cat > "$work/fail_jump.sh" <<'SH'
#!/usr/bin/env bash
"$@" || exit
[[ " $* " == *" --space jump "* ]] && { echo "fail_jump.sh: failing the jump space on purpose" >&2; exit 1; }
exit 0
SH
# A step killed mid-way (SIGKILL: no clean-up in the tool) as soon as it has written its first
# file (or after 5 s): nothing that looks finished. The job counts as killed even if the tool
# managed to finish first.
cat > "$work/kill_jump.sh" <<'SH'
#!/usr/bin/env bash
[[ " $* " == *" --space jump "* ]] || exec "$@"
"$@" & pid=$!
for _ in $(seq 1000); do [[ -e out/motion/spaces/jump/references.npy ]] && break; sleep 0.005; done
kill -KILL "$pid"
echo "kill_jump.sh: killed the jump space with $(ls out/motion/spaces/jump 2>/dev/null | wc -l) files written" >&2
wait "$pid" 2>/dev/null
exit 137
SH
chmod +x "$work/fail_jump.sh" "$work/kill_jump.sh"
for wrapper in fail_jump kill_jump; do
  rm -rf "$work/j4/out/motion/spaces/jump" "$work/j4/out/motion/graph.json"
  if pipeline_make "$work/j4" "${common[@]}" -j2 SUBMIT="$work/$wrapper.sh" graph 2> "$work/$wrapper.txt"; then
    echo "$wrapper: make succeeded"; exit 1
  fi
  grep "_jump.sh:" "$work/$wrapper.txt"
  for f in spaces/jump/space.json report/spaces_jump.json graph.json; do
    [[ ! -e $work/j4/out/motion/$f ]] || { echo "$wrapper: $f left behind"; cat "$work/$wrapper.txt"; exit 1; }
  done
  pipeline_make "$work/j4" "${common[@]}" -j4 "${targets[@]}"
  pipeline_same "$work/j1" "$work/j4"
done
echo "pipeline_make: ok"
