#!/usr/bin/env bash
# surfcap-learn + surfcap-edit end to end on a generated bending tube (no external data):
# learn with automatic parts, write an editable parts config, edit with handles/anchors, check
# outputs, reports, determinism and exit codes.
set -euo pipefail
build=$1
learn=$build/tools/surfcap-learn
edit=$build/tools/surfcap-edit
work=$(mktemp -d "${TMPDIR:-/tmp}/learn_e2e.XXXXXX")
trap 'rm -rf "$work"' EXIT

# A closed tube (rings × segments, capped) of height 1 m bending at mid-height over T frames.
perl - "$work" <<'PERL'
use strict; use warnings;
my $dir = shift;
my ($rings, $seg, $T, $r) = (24, 12, 16, 0.08);
my @rest;
for my $i (0..$rings-1) { for my $j (0..$seg-1) {
  my $a = 2*3.14159265358979*$j/$seg; push @rest, [$r*cos($a), $i/($rings-1), $r*sin($a)]; } }
push @rest, [0, 0, 0], [0, 1, 0];
my @faces;
for my $i (0..$rings-2) { for my $j (0..$seg-1) {
  my ($a,$b,$c,$d) = ($i*$seg+$j, $i*$seg+($j+1)%$seg, ($i+1)*$seg+$j, ($i+1)*$seg+($j+1)%$seg);
  push @faces, [$a,$c,$b], [$b,$c,$d]; } }
my ($bot, $top) = ($rings*$seg, $rings*$seg+1);
for my $j (0..$seg-1) { push @faces, [$bot, $j, ($j+1)%$seg];
  push @faces, [$top, ($rings-1)*$seg+($j+1)%$seg, ($rings-1)*$seg+$j]; }
open(my $obj, '>', "$dir/template.obj") or die;
printf $obj "v %.6f %.6f %.6f\n", @$_ for @rest;
printf $obj "f %d %d %d\n", map { $_+1 } @$_ for @faces;
close $obj;
my $V = scalar @rest;
my $data = '';
for my $t (0..$T-1) {
  my $angle = 1.2*sin(6.2831853*$t/$T);   # bend about z at y = 0.5, smooth weight
  for my $p (@rest) {
    my ($x,$y,$z) = @$p;
    my $w = 1/(1+exp(-($y-0.5)/0.04));
    my $ang = $w*$angle; my ($c,$s) = (cos($ang), sin($ang));
    my ($dx,$dy) = ($x, $y-0.5);
    $data .= pack('f<3', $c*$dx - $s*$dy, 0.5 + $s*$dx + $c*$dy, $z);
  }
}
my $header = "{'descr': '<f4', 'fortran_order': False, 'shape': ($T, $V, 3), }";
my $len = 10 + length($header) + 1; my $pad = (64 - $len % 64) % 64;
$header .= ' ' x $pad . "\n";
open(my $npy, '>:raw', "$dir/positions.npy") or die;
print $npy "\x93NUMPY\x01\x00", pack('v', length($header)), $header, $data;
close $npy;
PERL

inputs=(--template "$work/template.obj" --positions "$work/positions.npy")
"$learn" --threads 1 learn "${inputs[@]}" --auto-parts 3 --overlap 0.08 --examples 8 --output "$work/model"
for f in parts.json template.ply parts.png report/learn.json global/parts.json parts/part0.basis.npy parts/part0.vertices.npy; do
  test -s "$work/model/$f" || { echo "missing $f"; exit 1; }
done
grep -q '"surfcap.parts/1"' "$work/model/parts.json"
test "$(find "$work/model" -name '.*' | wc -l)" -eq 0 || { echo "temporary files left"; exit 1; }

# Deterministic: the same run on another thread count gives identical arrays.
sum1=$(cd "$work/model" && cat parts/*.npy | md5sum)
"$learn" --threads 2 learn "${inputs[@]}" --auto-parts 3 --overlap 0.08 --examples 8 --output "$work/model"
sum2=$(cd "$work/model" && cat parts/*.npy | md5sum)
test "$sum1" = "$sum2" || { echo "learn is not deterministic"; exit 1; }

"$learn" parts "${inputs[@]}" --auto-parts 3 --output "$work/config.json" --preview "$work/config.png"
grep -q '"surfcap.part_config/1"' "$work/config.json"
test -s "$work/config.png"

# Edit: lift the top cap vertex ring, anchor the bottom ring (vertex indices of the generator).
cat > "$work/edit.json" <<'JSON'
{"format": "surfcap.edit/1",
 "anchors": [{"vertices": [0,1,2,3,4,5,6,7,8,9,10,11,288]}],
 "handles": [{"vertices": [276,277,278,279,280,281,282,283,284,285,286,287,289], "translate": [0.15, -0.05, 0]}]}
JSON
for method in part global laplacian; do
  "$edit" --model "$work/model/parts.json" --edit "$work/edit.json" --method $method --output "$work/edited_$method.ply"
  test -s "$work/edited_$method.ply"
  residual=$(grep -o '"max_constraint_residual_mm": [0-9.e+-]*' "$work/edited_$method.ply.report.json" | awk '{print $2}')
  awk -v r="$residual" 'BEGIN { exit !(r < 20) }' || { echo "$method: constraint residual $residual mm"; exit 1; }
done

# Exit codes: missing model → 4, bad edit → 3, bad arguments → 2.
set +e
"$edit" --model "$work/nope/parts.json" --edit "$work/edit.json" --output "$work/x.ply"; code=$?
test $code -eq 4 || { echo "missing model: exit $code"; exit 1; }
echo '{"format": "surfcap.edit/1", "handles": [{"region": "tail"}]}' > "$work/bad.json"
"$edit" --model "$work/model/parts.json" --edit "$work/bad.json" --output "$work/x.ply"; code=$?
test $code -eq 3 || { echo "bad edit: exit $code"; exit 1; }
"$learn" learn "${inputs[@]}" --output "$work/m2"; code=$?
test $code -eq 2 || { echo "no parts option: exit $code"; exit 1; }
set -e
echo "learn e2e ok"
