#!/usr/bin/env bash
# The papers' claims on the synthetic tiny capture's ground truth:
#  - tejera2013 leave-out: part-based reconstruction from head/hands/feet beats plain Laplacian
#    and the global basis on average;
#  - casas2011 Table 1: the hybrid blend with one reference has at most a third of the linear
#    blend's error against the exact non-linear blend.
# Usage: bash synth_claims.sh <build_dir> <source_dir>
set -euo pipefail
build=$1
source=$2
for tool in surfcap-synth surfcap-learn surfcap-precompute; do
  [[ -x $build/tools/$tool ]] || { echo "SKIP: $tool is not built"; exit 77; }
done
work=$(mktemp -d "$build/claims_e2e.XXXXXX")
trap 'rm -rf "$work"' EXIT
"$build/tools/surfcap-synth" --preset tiny --seed 2 --no-images --out "$work/capture" --log-level warn
database=$work/capture/ground_truth/database/database.json
"$build/tools/surfcap-learn" evaluate --database "$database" --parts "$source/configs/parts/human6.json" \
  --stride 4 --report "$work/leave_out.json" --log-level warn
"$build/tools/surfcap-precompute" compare --database "$database" --pose walk:7 --pose run:4 \
  -o "$work/table1.json" --log-level warn
python3 - "$work" <<'PY'
import json, sys
work = sys.argv[1]
methods = json.load(open(f"{work}/leave_out.json"))["methods"]
mean = {name: m["mean_error_mm"] for name, m in methods.items()}
print("leave-out mean error (mm):", {k: round(v, 1) for k, v in mean.items()})
assert mean["parts"] < mean["laplacian"] and mean["parts"] < mean["global"], mean
table = {m["method"]: m["max_error_percent"] for m in json.load(open(f"{work}/table1.json"))["comparison"]["methods"]}
print("Table 1 max error (% of height):", {k: round(v, 2) for k, v in table.items()})
assert table["hybrid_1"] <= table["linear"] / 3, table
assert table["hybrid_3"] < table["hybrid_1"], table
PY
echo "synth claims: ok"
