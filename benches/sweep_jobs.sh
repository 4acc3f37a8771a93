#!/usr/bin/env bash
# Parallel speed sweep: a 20-point sweep of the paper's drive (60 … 250 rpm,
# 1 s ramp + 0.5 s settle + 1.5 s window per case) with --jobs 1 and --jobs 2;
# prints the wall time of each, per case, and their ratio.
#
#   bash benches/sweep_jobs.sh [BINARY]
set -euo pipefail
bin=${1:-target/release/chaindrive}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
declare -A wall
for jobs in 1 2; do
  start=$(date +%s.%N)
  "$bin" sweep --quiet --rpm 60:250:10 --settle 0.5 --window 1.5 --jobs "$jobs" \
    --out "$dir/j$jobs" >/dev/null
  end=$(date +%s.%N)
  wall[$jobs]=$(python3 -c "print(f'{$end - $start:.2f}')")
  printf 'jobs %s: %s s wall, %s s per case\n' "$jobs" "${wall[$jobs]}" \
    "$(python3 -c "print(f'{${wall[$jobs]} / 20:.3f}')")"
done
python3 -c "print(f'speed-up jobs 2 / jobs 1: {${wall[1]} / ${wall[2]}:.2f}x')"
cmp -s "$dir/j1/orders.csv" "$dir/j2/orders.csv" && echo "orders.csv identical" || echo "orders.csv DIFFERS"
