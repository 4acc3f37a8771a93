#!/usr/bin/env bash
# A study's results.parquet read with pyarrow: the 4-case
# tests/data/study_small.toml run here with `chaindrive study --jobs 2`,
# collected, and the Parquet table compared with results.csv (same column
# names, same rows, equal values, nulls where the CSV is empty).
#
#   bash tests/study_python.sh [BINARY]
#
# Creates (once) a virtual environment with pyarrow under
# ${XDG_CACHE_HOME:-~/.cache}/chaindrive/pyarrow-venv; needs `python3 -m venv`
# and, the first time, network access for `pip`.
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${1:-target/release/chaindrive}
venv=${XDG_CACHE_HOME:-$HOME/.cache}/chaindrive/pyarrow-venv
if ! "$venv/bin/python" -c 'import pyarrow.parquet' 2>/dev/null; then
  python3 -m venv "$venv"
  "$venv/bin/pip" install --quiet pyarrow
fi
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT

"$bin" study tests/data/study_small.toml --out "$dir/study" --jobs 2 --quiet
"$bin" study collect "$dir/study" 2>/dev/null

"$venv/bin/python" - "$dir/study" <<'PY'
import csv, sys
import pyarrow.parquet as pq

d = sys.argv[1]
t = pq.read_table(f"{d}/results.parquet")
rows = list(csv.reader(open(f"{d}/results.csv")))
header, body = rows[0], rows[1:]
assert t.column_names == header, (t.column_names, header)
assert t.num_rows == len(body) == 4, (t.num_rows, len(body))
assert t.column("case").to_pylist() == [0, 1, 2, 3]
assert t.column("status").to_pylist() == ["ok"] * 4
for i, name in enumerate(header):
    for value, cell in zip(t.column(name).to_pylist(), (r[i] for r in body)):
        if value is None:
            assert cell == "", (name, value, cell)
        elif isinstance(value, float):
            assert value == float(cell), (name, value, cell)  # shortest round-trip text
        else:
            assert str(value) == cell, (name, value, cell)
print(f"study_python: results.parquet: {t.num_rows} rows x {t.num_columns} columns, equal to results.csv")
PY
echo "study_python: ok"
