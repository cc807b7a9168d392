#!/usr/bin/env bash
# surfcap-align run with its defaults on the synth studio_tiny capture, whose reconstructions are
# open (floor cut, unseen regions removed) and carry a visual hull's phantom volume, outliers and
# blobs: every frame is read (large holes left open), the root's holes are closed by an
# unobserved faired patch, and the alignment holds against the ground truth; phantom volume is
# not counted as uncovered reconstruction (silhouette evidence). Checks the hole,
# merged-region and observation figures of the report and its preview, byte-identical outputs on
# 1 and 2 threads, and that a corrupt frame is still refused (exit 3, naming the file and frame).
set -euo pipefail
build=${1:?build dir}
synth=$build/tools/surfcap-synth
align=$build/tools/surfcap-align
work=$(mktemp -d "${TMPDIR:-/tmp}/align_studio_e2e.XXXXXX")
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

"$synth" --preset studio_tiny --out "$work/capture" --threads 2 --log-level error
"$align" run --capture "$work/capture" --out "$work/db" --threads 2 --log-level warn 2> "$work/run.log" \
  || { cat "$work/run.log"; fail "surfcap-align run failed"; }

for f in database.json template.ply sequences/walk.npy report/alignment.json report/alignment.png \
         report/observation.png report/truth_error.png; do
  [ -s "$work/db/$f" ] || fail "missing $f"
done

perl -MJSON::PP -e '
  local $/; open(my $f, "<", $ARGV[0]) or die; my $r = decode_json(<$f>);
  my $g = $r->{ground_truth} or die "no ground-truth figures\n";
  my $s = $r->{summary};
  printf "RMS %.3f%% of height, worst frame %s %.3f%%, p99 %.3f%%, evaluated %.1f%% of the template\n",
    $g->{rms_percent_height}, $g->{worst_frame}, $g->{worst_frame_rms_percent_height},
    $g->{p99_vertex_error_percent_height}, 100 * $g->{evaluated_fraction};
  printf "template: %.1f%% unobserved (closing surface); frames: up to %.1f%% unobserved\n",
    100 * $s->{template_unobserved_fraction}, 100 * $s->{max_unobserved_fraction};
  # Bounds: the figures measured (docs/align.md: 0.80 %, 1.55 %, p99 2.96 %; with 29 or 31
  # coarsest patches up to 0.80 %, 1.55 %, 3.13 %; other seeds up to 0.83 %, 1.34 %, 3.28 %) with a
  # margin; a frame with its legs swapped (17 % of the height) or turned half round fails them.
  die "RMS error above 2% of the height\n" if $g->{rms_percent_height} > 2;
  die "worst frame above 4% of the height\n" if $g->{worst_frame_rms_percent_height} > 4;
  die "p99 vertex error above 8% of the height\n" if $g->{p99_vertex_error_percent_height} > 8;
  # Phantom volume, outliers and blobs are not evaluated (their truth is only a nearest point).
  die "evaluated fraction $g->{evaluated_fraction} implausible\n"
    unless $g->{evaluated_fraction} > 0.6 && $g->{evaluated_fraction} < 0.99;
  my $frames = $r->{frames};
  die "frame count\n" unless @$frames == 16;
  die "frames with holes: $s->{frames_with_holes}\n" unless $s->{frames_with_holes} == 16;
  # The visual hulls fuse parts that touch (hands held together, legs): some frames show it.
  die "frames with merged regions: $s->{frames_with_merged_regions}\n"
    unless $s->{frames_with_merged_regions} >= 1 && $s->{frames_with_merged_regions} <= 15;
  my $closing = $s->{template_unobserved_fraction};
  die "template closing fraction $closing implausible\n" unless $closing > 0.005 && $closing < 0.2;
  for my $fr (@$frames) {
    my $h = $fr->{holes};
    my $name = "$fr->{sequence}:$fr->{frame}";
    die "$name: no hole figures\n" unless $h->{count} > 0 && $h->{largest_perimeter_m} > 0.1;
    die "$name: largest hole $h->{largest_perimeter_m} m around\n" if $h->{largest_perimeter_m} > 20;
    my $u = $fr->{unobserved_fraction};
    die "$name: unobserved fraction $u below the closing surface\n" if $u < $closing - 1e-12;
    die "$name: unobserved fraction $u\n" if $u > 0.6;
    my $m = $fr->{merged} or die "$name: no merged-region figures\n";
    die "$name: merged regions $m->{regions}, fraction $m->{fraction}\n"
      unless $m->{regions} >= 0 && $m->{fraction} >= 0 && $m->{fraction} < 0.2 && ($m->{regions} > 0) == ($m->{fraction} > 0);
    if ($fr->{parent} < 0) {
      die "root: unobserved fraction is not the closing surface\n" if abs($u - $closing) > 1e-12;
      next;
    }
    die "$name has no dense correspondences\n" unless $fr->{correspondences}{dense} > 0;
    # Phantom volume lies inside the silhouettes of the aligned template: it is not uncovered
    # reconstruction (0.04 % at most measured; counting it gave frames above 1 %).
    die "$name: uncovered fraction $fr->{uncovered_fraction}\n" if $fr->{uncovered_fraction} > 0.005;
    for my $a (@{$fr->{failed_attempts}}) {
      die "$name: an attempt failed as uncovered ($a->{uncovered_fraction})\n" if $a->{failure} =~ /not covered/;
    }
  }
' "$work/db/report/alignment.json"
grep -qF '"evaluated_fraction"' "$work/db/report/alignment.json" || fail "no evaluated fraction"

# Deterministic: registering again on one thread gives the same bytes.
mkdir -p "$work/db1/similarity"
cp "$work/db/similarity/"{histograms.npy,histograms.json,matrix.npy,tree.json} "$work/db1/similarity/"
"$align" register --out "$work/db1" --capture "$work/capture" --threads 1 --preview-frames 0 --no-evaluation \
  --log-level warn
for f in template.ply sequences/walk.npy sequences/walk.root.npy sequences/jump_high.npy sequences/reach_low.npy; do
  cmp "$work/db/$f" "$work/db1/$f" || fail "$f differs between thread counts"
done
# The template is closed: every edge has two faces (binary PLY, int32 indices after a count byte).
perl -e '
  open(my $f, "<:raw", $ARGV[0]) or die; local $/; my $b = <$f>;
  my ($nv) = $b =~ /element vertex (\d+)/; my ($nf) = $b =~ /element face (\d+)/;
  my $header = index($b, "end_header\n") + length("end_header\n");
  my $stride = 0; $stride += $1 eq "float" ? 4 : $1 eq "uchar" ? 1 : 8 while $b =~ /property (float|uchar|double) \w+\n/g;
  my $at = $header + $nv * $stride; my %uses;
  for (1 .. $nf) {
    my ($n, @v) = unpack("C l<3", substr($b, $at, 13)); $at += 13;
    for my $k (0 .. 2) { my ($a, $c) = ($v[$k], $v[($k + 1) % 3]); $uses{$a < $c ? "$a $c" : "$c $a"}++; }
  }
  my @open = grep { $uses{$_} != 2 } keys %uses;
  die "template.ply has " . scalar(@open) . " edges without two faces\n" if @open;
' "$work/db/template.ply"

# Corrupt data is still refused: a frame cut short is bad input (exit 3) naming it.
cp -r "$work/capture" "$work/broken"
truncate -s 2000 "$work/broken/reach_low/mesh/000003.ply"
set +e
"$align" register --out "$work/db1" --capture "$work/broken" --threads 2 --preview-frames 0 --no-evaluation \
  --log-level warn 2> "$work/broken.log"; code=$?
set -e
[ $code -eq 3 ] || fail "a truncated frame gave exit code $code"
grep -q "reach_low/mesh/000003.ply' (frame 3)" "$work/broken.log" || { cat "$work/broken.log"; fail "the error does not name the frame"; }
echo "align studio_tiny e2e ok"
