# Shared by tests/study_python.sh and tests/slurm_check.sh (sourced, not run):
# a virtual environment with pyarrow, and the check that a collected
# study's results.parquet is the same table as its results.csv.
#
# Sourcing it sets `venv` (created once under
# ${XDG_CACHE_HOME:-~/.cache}/chaindrive/pyarrow-venv; needs
# `python3 -m venv` and, the first time, network access for `pip`) and
# defines `check_results DIR ROWS NAME`: DIR's results.parquet read with
# pyarrow has results.csv's column names (each once) and ROWS rows, cases
# 0 … ROWS−1, every case finished (`ok`, or `warned` exactly where it has a
# warning or a segment that is not stationary), and equal values (nulls
# where the CSV is empty, booleans as `true`/`false`).

venv=${XDG_CACHE_HOME:-$HOME/.cache}/chaindrive/pyarrow-venv
if ! "$venv/bin/python" -c 'import pyarrow.parquet' 2>/dev/null; then
  python3 -m venv "$venv"
  "$venv/bin/pip" install --quiet pyarrow
fi

check_results() {
  "$venv/bin/python" - "$1" "$2" "$3" <<'PY'
import csv, sys
import pyarrow.parquet as pq

d, n, name = sys.argv[1], int(sys.argv[2]), sys.argv[3]
t = pq.read_table(f"{d}/results.parquet")
rows = list(csv.reader(open(f"{d}/results.csv")))
header, body = rows[0], rows[1:]
assert t.column_names == header, (t.column_names, header)
assert len(set(header)) == len(header), [c for c in header if header.count(c) > 1]
assert t.num_rows == len(body) == n, (t.num_rows, len(body))
assert t.column("case").to_pylist() == list(range(n))
status = t.column("status").to_pylist()
assert set(status) <= {"ok", "warned"}, status
stationary = [c for c in header if c.startswith("segments.") and c.endswith(".stationary")]
for k in range(n):
    drifting = any(t.column(c)[k].as_py() is False for c in stationary)
    warned = t.column("warning_count")[k].as_py() > 0 or drifting
    assert status[k] == ("warned" if warned else "ok"), (k, status[k])
for i, col in enumerate(header):
    for value, cell in zip(t.column(col).to_pylist(), (r[i] for r in body)):
        if value is None:
            assert cell == "", (col, value, cell)
        elif isinstance(value, bool):
            assert str(value).lower() == cell, (col, value, cell)
        elif isinstance(value, float):
            assert value == float(cell), (col, value, cell)  # shortest round-trip text
        else:
            assert str(value) == cell, (col, value, cell)
print(f"{name}: results.parquet: {t.num_rows} rows x {t.num_columns} columns, every case finished ({status.count('warned')} warned), equal to results.csv")
PY
}
