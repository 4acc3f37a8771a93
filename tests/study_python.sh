#!/usr/bin/env bash
# A study's results.parquet read with pyarrow: the 4-case
# tests/data/study_small.toml run here with `chaindrive study --jobs 2`,
# collected, and the Parquet table compared with results.csv (same column
# names, same rows, equal values, nulls where the CSV is empty).
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
echo "study_python: ok"
