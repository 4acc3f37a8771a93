#!/usr/bin/env bash
# Instructions per step of the paper's drive through the command line and
# through the Python module, counted by cachegrind (no cache simulation):
# repeatable whatever else the machine runs, unlike wall time. Each is run
# for D1 and D2 simulated seconds (the scene file's settings: velocity
# Verlet, dt = 10 us, samples at 1 kHz; Python keeps the series); the
# difference of the totals over the difference of the steps is the
# stepping loop's instructions per step, observers included (process and
# interpreter start, layout, static equilibrium and the summary cancel).
# Then the series' cost: Python with and without the series (`series=False`)
# at 10 kHz (more samples than 1 kHz to count them by), at both durations;
# the difference with and without is a + b n for n
# samples, a the fixed cost (allocating the vectors, handing them to NumPy)
# and b the cost of one sample (a row copied into the vectors), and it is
# extrapolated to a 60 s series at 1 kHz against that run's instructions.
#
#   bash benches/python_instructions.sh [PYTHON] [BINARY] [D1] [D2]
set -euo pipefail
cd "$(dirname "$0")/.."
# The interpreter's start counts the same instructions every time.
export PYTHONHASHSEED=0
# NumPy's BLAS threads spin for a count that varies from run to run.
export OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1
py=${1:-python3}
bin=${2:-target/release/chaindrive}
d1=${3:-0.2}
d2=${4:-0.4}
count() {
  valgrind --tool=cachegrind --cache-sim=no --cachegrind-out-file=/dev/null "$@" 2>&1 >/dev/null \
    | awk '/I *refs:/ { gsub(",", "", $NF); print $NF }'
}
cli1=$(count "$bin" run --quiet --duration "$d1")
cli2=$(count "$bin" run --quiet --duration "$d2")
py1=$(count "$py" -c "import chaindrive as cd; cd.run(cd.Scene.l60mc(), duration=$d1)")
py2=$(count "$py" -c "import chaindrive as cd; cd.run(cd.Scene.l60mc(), duration=$d2)")
fast() { echo "import chaindrive as cd; cd.run(cd.Scene.l60mc(), duration=$1, rate=10000, series=$2)"; }
kept1=$(count "$py" -c "$(fast "$d1" True)")
kept2=$(count "$py" -c "$(fast "$d2" True)")
bare1=$(count "$py" -c "$(fast "$d1" False)")
bare2=$(count "$py" -c "$(fast "$d2" False)")
python3 - "$d1" "$d2" "$cli1" "$cli2" "$py1" "$py2" "$kept1" "$kept2" "$bare1" "$bare2" <<'PY'
import sys
d1, d2 = float(sys.argv[1]), float(sys.argv[2])
cli1, cli2, py1, py2, kept1, kept2, bare1, bare2 = map(int, sys.argv[3:])
steps = round((d2 - d1) / 1e-5)
cli = (cli2 - cli1) / steps
py = (py2 - py1) / steps
print(f"totals: CLI {cli1:,} / {cli2:,}, Python {py1:,} / {py2:,} instructions ({d1} s / {d2} s)")
print(f"per step: CLI {cli:,.0f}, Python {py:,.0f}, ratio Python / CLI {py / cli:.4f}")
n1, n2 = round(d1 * 10000) + 1, round(d2 * 10000) + 1
per_sample = ((kept2 - bare2) - (kept1 - bare1)) / (n2 - n1)
fixed = (kept1 - bare1) - n1 * per_sample
rows = 60 * 1000 + 1
series = fixed + rows * per_sample
run = py * 60 / 1e-5
print(f"series: {per_sample:,.0f} instructions per sample, {fixed:,.0f} fixed; "
      f"a 60 s series at 1 kHz: {series:,.0f} instructions, {100 * series / run:.3f} % of its run's {run:,.0f}")
PY
