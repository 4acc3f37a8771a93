#!/usr/bin/env bash
# Instructions per step of the paper's drive through the command line and
# through the Python module, counted by cachegrind (no cache simulation):
# repeatable whatever else the machine runs, unlike wall time. Each is run
# for D1 and D2 simulated seconds (the scene file's settings: velocity
# Verlet, dt = 10 us, samples at 1 kHz; Python keeps the series); the
# difference of the totals over the difference of the steps is the
# stepping loop's instructions per step, observers included (process and
# interpreter start, layout, static equilibrium and the summary cancel).
#
#   bash benches/python_instructions.sh [PYTHON] [BINARY] [D1] [D2]
set -euo pipefail
cd "$(dirname "$0")/.."
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
python3 - "$d1" "$d2" "$cli1" "$cli2" "$py1" "$py2" <<'PY'
import sys
d1, d2 = float(sys.argv[1]), float(sys.argv[2])
cli1, cli2, py1, py2 = map(int, sys.argv[3:])
steps = round((d2 - d1) / 1e-5)
cli = (cli2 - cli1) / steps
py = (py2 - py1) / steps
print(f"totals: CLI {cli1:,} / {cli2:,}, Python {py1:,} / {py2:,} instructions ({d1} s / {d2} s)")
print(f"per step: CLI {cli:,.0f}, Python {py:,.0f}, ratio Python / CLI {py / cli:.4f}")
PY
