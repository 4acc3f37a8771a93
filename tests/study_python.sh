#!/usr/bin/env bash
# A study's results.parquet read with pyarrow: the 4-case
# tests/data/study_small.toml run here with `chaindrive study --jobs 2`,
# collected, and the Parquet table compared with results.csv (same column
# names, same rows, equal values, nulls where the CSV is empty); then, with
# pandas (installed into the same environment where pip can), a pivot table
# over the dotted factor `sprockets.0.speed_rpm` and a response, as a user
# would write it.
#
#   bash tests/study_python.sh [BINARY]
#
# pyarrow comes from tests/pyarrow_check.sh's virtual environment (created
# once; network access for `pip` the first time).
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${1:-target/release/chaindrive}
source tests/pyarrow_check.sh
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT

"$bin" study tests/data/study_small.toml --out "$dir/study" --jobs 2 --quiet
"$bin" study collect "$dir/study" 2>/dev/null

check_results "$dir/study" 4 study_python

if ! "$venv/bin/python" -c 'import pandas' 2>/dev/null; then
  "$venv/bin/pip" install --quiet pandas 2>/dev/null || true
fi
if "$venv/bin/python" -c 'import pandas' 2>/dev/null; then
  "$venv/bin/python" - "$dir/study" <<'PY'
import sys
import pandas as pd

d = sys.argv[1]
for df in (pd.read_parquet(f"{d}/results.parquet"), pd.read_csv(f"{d}/results.csv")):
    # The factors keep the names the plan wrote; the responses keep theirs.
    p = df.pivot_table(index="sprockets.0.speed_rpm", columns="chain.pretension_n",
                       values="segments.0.mean_link_force_n")
    assert p.shape == (2, 2), p
    assert list(p.index) == [60.0, 120.0] and list(p.columns) == [15000.0, 21000.0], p
    clean = df[df.status == "ok"]
    assert (clean.warning_count == 0).all(), clean
print("study_python: pandas: pivot_table over sprockets.0.speed_rpm x chain.pretension_n: ok")
PY
else
  echo "study_python: pandas not available: pivot_table check skipped"
fi
echo "study_python: ok"
