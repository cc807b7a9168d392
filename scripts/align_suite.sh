#!/usr/bin/env bash
# The alignment suite (docs/align.md "Measured figures"): makes each capture once, aligns it with
# `surfcap-align run` and prints a table of the root frame, RMS, worst frame and p99 vertex error (% of the
# height) and register CPU time per capture. Run it before and after a change to the alignment and
# compare the tables: a change that helps one capture and hurts another is not a gain.
#
# usage: scripts/align_suite.sh [--build DIR] [--out DIR] [--threads T] [--spread] [--option ARG]... [CAPTURE...]
#   CAPTURE: tiny demo studio_tiny studio_tiny_noimg studio_tiny_seed2 studio_tiny_seed3
#            dance dance_art dance_art_fine dance_hull studio studio_noimg (default: all but the
#            two studio rows)
#   --option ARG: one more argument for every `surfcap-align run` and `register` (repeat it for
#   each word, e.g. --option --coverage-weight --option off), to measure a candidate setting.
#   The captures are kept in OUT/captures (made when missing), the alignments in OUT/<capture>
#   (made again every run). The dance captures need the dance data (SURFCAP_DANCE_DATA, default
#   ../shared/data/dance); without it they are skipped with a message.
#   --spread: each capture is registered twice more on the same tree with one coarsest patch fewer
#   and one more (--patches 29, 31), and the table gives the lowest and highest of the three
#   figures: a perturbation that only changes rounding moves the discrete decisions of the tree
#   (docs/align.md "Measured figures"), so a difference between two builds within that range is
#   no evidence either way.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
build=$here/build
out=${TMPDIR:-/tmp}/align_suite
threads=2
spread=0
captures=()
extra=()
while [ $# -gt 0 ]; do
  case $1 in
    --build) build=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --threads) threads=$2; shift 2 ;;
    --spread) spread=1; shift ;;
    --option) extra+=("$2"); shift 2 ;;
    -h|--help) sed -n '2,20p' "$0"; exit 0 ;;
    -*) echo "unknown option $1" >&2; exit 2 ;;
    *) captures+=("$1"); shift ;;
  esac
done
[ ${#captures[@]} -gt 0 ] || captures=(tiny demo studio_tiny studio_tiny_noimg studio_tiny_seed2 studio_tiny_seed3
                                       dance dance_art dance_art_fine dance_hull)
synth=$build/tools/surfcap-synth
align=$build/tools/surfcap-align
if [ ! -x "$align" ] || [ ! -x "$synth" ]; then
  echo "no surfcap tools in $build/tools (build first)" >&2
  exit 2
fi
data=${SURFCAP_DANCE_DATA:-$here/../shared/data/dance}
for name in "${captures[@]}"; do
  case $name in
    tiny|demo|studio|studio_noimg|studio_tiny|studio_tiny_noimg|studio_tiny_seed[0-9]*|dance|dance_art|dance_art_fine|\
      dance_hull) ;;
    *) echo "unknown capture $name (see --help)" >&2; exit 2 ;;
  esac
done
mkdir -p "$out/captures"

# make CAPTURE: its capture folder (echoed), made when missing.
make_capture() {
  local name=$1 dir=$out/captures/$1
  case $name in
    tiny|demo|studio) [ -f "$dir/capture.json" ] ||
        "$synth" --preset "$name" --out "$dir" --threads "$threads" --log-level warn >&2 ;;
    studio_tiny) [ -f "$dir/capture.json" ] ||
        "$synth" --preset studio_tiny --out "$dir" --threads "$threads" --log-level warn >&2 ;;
    studio_tiny_seed*) [ -f "$dir/capture.json" ] ||
        "$synth" --preset studio_tiny --seed "${name#studio_tiny_seed}" --out "$dir" --threads "$threads" \
          --log-level warn >&2 ;;
    dance|dance_art|dance_art_fine|dance_hull)
      local options=()
      case $name in
        dance_art) options=(--artefacts) ;;
        dance_art_fine) options=(--artefacts --edge-scale 1.25) ;;
        dance_hull) options=(--artefacts --visual-hull) ;;
      esac
      [ -f "$dir/capture/capture.json" ] ||
        SURFCAP_DANCE_DATA=$data "$here/scripts/make_dance_capture.sh" --build "$build" --out "$dir" --no-align \
          --threads "$threads" ${options[@]+"${options[@]}"} >&2
      dir=$dir/capture ;;
    *) echo "unknown capture $name" >&2; return 2 ;;
  esac
  echo "$dir"
}

# figures JSON NAME: one table row of an alignment report.
figures() {
  perl -MJSON::PP -e '
    local $/; open(my $f, "<", $ARGV[0]) or die; my $r = decode_json(<$f>); my $g = $r->{ground_truth};
    my ($root) = grep { $_->{depth} == 0 } @{$r->{frames}};
    printf "| %s | %s:%d | %.4f | %s %.4f | %.4f | %d | %.0f |\n", $ARGV[1], $root->{sequence}, $root->{frame},
      $g->{rms_percent_height}, $g->{worst_frame},
      $g->{worst_frame_rms_percent_height}, $g->{p99_vertex_error_percent_height},
      $r->{summary}{frames_unrecovered}, $r->{cpu_s};
  ' "$1" "$2"
}

# range NAME JSON...: the lowest and highest RMS, worst frame and p99 of the reports.
range() {
  perl -MJSON::PP -e '
    my $name = shift; my (@rms, @worst, @p99);
    for my $file (@ARGV) {
      local $/; open(my $f, "<", $file) or die; my $g = decode_json(<$f>)->{ground_truth};
      push @rms, $g->{rms_percent_height}; push @worst, $g->{worst_frame_rms_percent_height};
      push @p99, $g->{p99_vertex_error_percent_height};
    }
    my $span = sub { my @v = sort { $a <=> $b } @_; sprintf "%.4f .. %.4f", $v[0], $v[-1] };
    printf "| %s | %s | %s | %s |\n", $name, $span->(@rms), $span->(@worst), $span->(@p99);
  ' "$@"
}

table=$out/suite.md spread_table=$out/spread.md
{
  echo "| capture | root | RMS % | worst frame % | p99 % | unrecovered frames | register CPU s |"
  echo "|---|---|---|---|---|---|---|"
} > "$table"
{
  echo "| capture | RMS % (patches 29, 30, 31) | worst frame % | p99 % |"
  echo "|---|---|---|---|"
} > "$spread_table"
for name in "${captures[@]}"; do
  if [[ $name == dance* ]] && [ ! -f "$data/positions.npy" ]; then
    echo "$name: skipped (no dance data at $data; set SURFCAP_DANCE_DATA)" >&2
    continue
  fi
  source_name=$name options=() register_options=()
  case $name in
    studio_tiny_noimg) source_name=studio_tiny options=(--no-images) register_options=(--no-images) ;;
    studio_noimg) source_name=studio options=(--no-images) register_options=(--no-images) ;;
    tiny|demo) options=(--root walk:0) ;;
  esac
  options+=(${extra[@]+"${extra[@]}"}) register_options+=(${extra[@]+"${extra[@]}"})
  capture=$(make_capture "$source_name")
  rm -rf "${out:?}/${name:?}"
  echo "$name: surfcap-align run --capture $capture ${options[*]:-}" >&2
  "$align" run --capture "$capture" --out "$out/$name" --threads "$threads" --log-level warn \
    ${options[@]+"${options[@]}"} 2> "$out/$name.log" || { echo "$name: surfcap-align failed (see $out/$name.log)" >&2; exit 1; }
  figures "$out/$name/report/alignment.json" "$name" >> "$table"
  [ "$spread" = 1 ] || continue
  reports=("$out/$name/report/alignment.json")
  for patches in 29 31; do
    variant=$out/$name.patches$patches
    rm -rf "${variant:?}"
    mkdir -p "$variant"
    cp -r "$out/$name/similarity" "$variant/"
    echo "$name: surfcap-align register --patches $patches (the same tree)" >&2
    "$align" register --capture "$capture" --out "$variant" --threads "$threads" --log-level warn --patches "$patches" \
      ${register_options[@]+"${register_options[@]}"} 2> "$variant.log" ||
      { echo "$name: surfcap-align register failed (see $variant.log)" >&2; exit 1; }
    reports+=("$variant/report/alignment.json")
  done
  range "$name" "${reports[@]}" >> "$spread_table"
done
cat "$table"
if [ "$spread" = 1 ]; then echo; cat "$spread_table"; fi
