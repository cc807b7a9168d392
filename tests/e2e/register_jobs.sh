#!/usr/bin/env bash
# surfcap-align register as farm jobs (docs/pipelines.md "Registration jobs") on the synth tiny
# capture, one similarity tree for every variant: the trunk job, K shard jobs and the merge write
# the bytes of the single job (database.json, template.ply, sequences/*.npy) for K = 2, 3 and 4
# and 1 or 2 threads — through pipelines/character.mk (REGISTER_JOBS=3) and the command line, with
# the camera images (SIFT features of parents aligned by another job, appearance flow) and without
# — and the merge refuses a missing shard (exit 4) and parts aligned with other options (exit 3),
# naming the file. A quick alignment (one patch level, few iterations): identity is the point.
# Usage: bash register_jobs.sh <build_dir> <source_dir>
set -euo pipefail
build=$1
source=$2
# shellcheck source=pipeline_lib.bash
. "$source/tests/e2e/pipeline_lib.bash"
align=$build/tools/surfcap-align
[[ -x $align && -x $build/tools/surfcap-synth ]] || { echo "SKIP: surfcap-align or surfcap-synth is not built"; exit 77; }
command -v make >/dev/null && command -v python3 >/dev/null || { echo "SKIP: needs make and python3"; exit 77; }
work=$(mktemp -d "$build/register_jobs.XXXXXX")
trap 'rm -rf "$work"' EXIT
"$build/tools/surfcap-synth" --preset tiny --seed 1 --out "$work/capture" --log-level warn
quick=(--levels 1 --rotation-iterations 1 --dense-iterations 1 --surface-model --no-evaluation --preview-frames 0)
geometry=("${quick[@]}" --no-images)
images=("${quick[@]}" --flow-iterations 1 --flow-stride 4 --feature-max-per-image 300)

# Through the pipeline: histograms, similarity, tree, then trunk + 3 shards + merge as make targets.
pipeline_make "$work/make" BLOCKS=2 THREADS=1 REGISTER_JOBS=3 REGISTER_OPTIONS="${geometry[*]}" -j2 alignment
for stage in align.register.trunk align.register.shard align.register.merge; do
  grep -q "^$stage"$'\t' "$work/make/out/report/steps.tsv" || { echo "no $stage step"; exit 1; }
done
[[ $(grep -c $'^align.register.shard\t' "$work/make/out/report/steps.tsv") -eq 3 ]] || { echo "not 3 shard jobs"; exit 1; }

# register VARIANT THREADS JOBS options...: in VARIANT/out/aligned with the pipeline's tree, paths
# as the pipeline gives them (the same provenance); JOBS 1 is the single job.
register() {
  local dir=$work/$1 threads=$2 jobs=$3
  shift 3
  mkdir -p "$dir/out/aligned"
  cp -r "$work/make/out/aligned/similarity" "$dir/out/aligned/"
  local run=("$align" register --out out/aligned --capture ../capture "$@" --threads "$threads" --log-level warn)
  if [[ $jobs -eq 1 ]]; then (cd "$dir" && "${run[@]}"); return; fi
  (cd "$dir" && "${run[@]}" --trunk)
  for k in $(seq "$jobs"); do (cd "$dir" && "${run[@]}" --shard "$k/$jobs"); done
  (cd "$dir" && "${run[@]}" --merge "$jobs")
}
same() {  # same A B: the aligned database of two variants, byte for byte
  local file
  for file in database.json template.ply $(cd "$work/$1/out/aligned" && ls sequences/*.npy); do
    cmp "$work/$1/out/aligned/$file" "$work/$2/out/aligned/$file" || { echo "$2 differs from $1: $file"; exit 1; }
  done
  echo "$2: the bytes of $1"
}
register single 2 1 "${geometry[@]}"
same single make
register k2 1 2 "${geometry[@]}"
same single k2
register k4 2 4 "${geometry[@]}"
same single k4
for report in register-trunk register-shard-1-of-4 register-shard-4-of-4 alignment; do
  python3 - "$work/k4/out/aligned/report/$report.json" <<'PY'
import json, sys
report = json.load(open(sys.argv[1]))
assert report["peak_rss_mb"] > 0 and report["total_s"] > 0, sys.argv[1]
PY
done

register images_single 2 1 "${images[@]}"
register images_k2 1 2 "${images[@]}"
same images_single images_k2

# The merge refuses parts aligned with other options, and a missing shard, naming the file.
expect_refusal() {  # expect_refusal CODE TEXT command...
  local code=$1 text=$2 got=0
  shift 2
  (cd "$work/k4" && "$@" > "$work/refusal.txt" 2>&1) || got=$?
  [[ $got -eq $code ]] && grep -q -- "$text" "$work/refusal.txt" \
    || { echo "expected exit $code naming $text, got $got:"; cat "$work/refusal.txt"; exit 1; }
  echo "refused (exit $code): $(grep -m1 -- "$text" "$work/refusal.txt")"
}
merge=("$align" register --out out/aligned --capture ../capture --merge 4 --log-level warn)
expect_refusal 3 "register/trunk.json" "${merge[@]}" "${geometry[@]}" --retries 3
rm "$work/k4/out/aligned/register/shard-3-of-4.json"
expect_refusal 4 "register/shard-3-of-4.json" "${merge[@]}" "${geometry[@]}"
expect_refusal 2 "--shard" "$align" register --out out/aligned --shard 5/4
echo "register_jobs: ok"
