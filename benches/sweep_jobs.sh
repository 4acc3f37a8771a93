#!/usr/bin/env bash
# Parallel speed sweep: a 20-point sweep of the paper's drive (60 … 250 rpm,
# 1 s ramp + 0.5 s settle + 1.5 s window per case) with --jobs 1 and then
# --jobs 2, repeated ROUNDS times (default 3) so that each ratio compares two
# runs made close together on a machine whose load changes. For each run:
# the wall time, the mean wall time of one case (each case's own `wall_s`
# + `setup_wall_s` from sweep.csv) and the rest (wall − Σ case / jobs: the
# setup, the scheduling and the outputs).
#
#   bash benches/sweep_jobs.sh [BINARY] [ROUNDS]
set -euo pipefail
bin=${1:-target/release/chaindrive}
rounds=${2:-3}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
ratios=()
for round in $(seq 1 "$rounds"); do
  declare -A wall=()
  for jobs in 1 2; do
    out="$dir/r$round-j$jobs"
    start=$(date +%s.%N)
    "$bin" sweep --quiet --rpm 60:250:10 --settle 0.5 --window 1.5 --jobs "$jobs" \
      --out "$out" >/dev/null
    end=$(date +%s.%N)
    wall[$jobs]=$(python3 -c "print(f'{$end - $start:.2f}')")
    python3 - "$out/sweep.csv" "${wall[$jobs]}" "$jobs" "$round" <<'EOF'
import csv, sys
path, wall, jobs, rnd = sys.argv[1], float(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
case = {}
for row in csv.DictReader(open(path)):
    if row["statistic"] in ("wall_s", "setup_wall_s"):
        case[row["rpm"]] = case.get(row["rpm"], 0.0) + float(row["value"])
total = sum(case.values())
n = max(len(case), 1)
print(f"round {rnd} jobs {jobs}: {wall:.2f} s wall; per case {total / n:.3f} s "
      f"(min {min(case.values()):.3f}, max {max(case.values()):.3f}); "
      f"rest {wall - total / jobs:.2f} s")
EOF
  done
  ratio=$(python3 -c "print(f'{${wall[1]} / ${wall[2]}:.3f}')")
  ratios+=("$ratio")
  echo "round $round: jobs 1 / jobs 2 = ${ratio}x (load $(cut -d' ' -f1-3 /proc/loadavg))"
  cmp -s "$dir/r$round-j1/orders.csv" "$dir/r$round-j2/orders.csv" \
    && echo "orders.csv identical" || echo "orders.csv DIFFERS"
  unset wall
done
echo "ratios: ${ratios[*]}"
