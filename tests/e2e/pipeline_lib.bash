# Shared by tests/e2e/pipeline_*.sh (sourced, not a test itself: ctest runs *.sh only).
# Expects $build and $source (the test's two arguments) to be set; makes them absolute.
build=$(cd "$build" && pwd)
source=$(cd "$source" && pwd)

pipeline_require_tools() {  # the stages every pipeline test needs
  local tool
  for tool in surfcap-synth surfcap-align surfcap-learn surfcap-precompute; do
    [[ -x $build/tools/$tool ]] || { echo "SKIP: $tool is not built"; exit 77; }
  done
  if ! command -v make >/dev/null || ! command -v python3 >/dev/null; then echo "SKIP: needs make and python3"; exit 77; fi
}

# The targets the built tools can make: everything once surfcap-precompute has `transitions`
# and surfcap-export/surfcap-play exist; until then the stages that have landed.
pipeline_targets() {
  local targets="parts graph"
  if "$build/tools/surfcap-precompute" --help 2>/dev/null | grep -qE "^ +transitions "; then targets+=" transitions"; fi
  if [[ -x $build/tools/surfcap-export && $targets == *transitions* ]]; then targets+=" character"; fi
  if [[ -x $build/tools/surfcap-play && $targets == *character* ]]; then targets+=" previews"; fi
  echo "$targets"
}

# pipeline_make DIR make-arguments...: runs the pipeline with DIR as working directory and
# relative paths (CAPTURE=../capture, OUT=out), so two runs embed the same paths in provenance.
pipeline_make() {
  local dir=$1
  shift
  mkdir -p "$dir"
  (cd "$dir" && make --no-print-directory -f "$source/pipelines/character.mk" CAPTURE=../capture \
     GRAPH="$source/configs/graphs/tiny.json" OUT=out BIN="$build/tools" LOG_LEVEL=warn "$@")
}

# Every output file of a run, reports (timings) and the registration jobs' parts (as many as
# jobs) excluded.
pipeline_outputs() {
  (cd "$1/out" && find . -type f -not -path '*/report/*' -not -path './previews/report.json' \
     -not -path './aligned/register/*' | sort)
}

# pipeline_same A B: the same output files with the same bytes.
pipeline_same() {
  local a=$1 b=$2 file differ=0
  diff <(pipeline_outputs "$a") <(pipeline_outputs "$b") || { echo "the runs wrote different files"; return 1; }
  while read -r file; do
    cmp -s "$a/out/$file" "$b/out/$file" || { echo "differs: $file"; differ=1; }
  done < <(pipeline_outputs "$a")
  [[ $differ -eq 0 ]] && echo "$(pipeline_outputs "$a" | wc -l) output files byte-identical"
  return $differ
}

# The steps a run executed, from OUT/report/steps.tsv (stage and target), in a stable order.
pipeline_steps() {
  [[ -f $1/out/report/steps.tsv ]] || return 0
  cut -f1,2 "$1/out/report/steps.tsv" | sort
}
