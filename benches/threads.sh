#!/usr/bin/env bash
# Two threads against one by drive size: the co-simulated conveyor of
# examples/long_conveyor.rs (real profile, dt 50 µs, 60 Hz world) with
# 100 … 10,000 rollers, each size run on one thread and on two, interleaved,
# REPEAT times. Prints the chain's ns per roller-step (the substeps alone)
# and the frame's real-time factor.
#
#   bash benches/threads.sh [FRAMES] [REPEAT]
set -euo pipefail
frames=${1:-60}
repeat=${2:-2}
cargo build --release --quiet --example long_conveyor
bin=target/release/examples/long_conveyor
printf '%-8s %-7s %-6s %-18s %-12s\n' rollers threads run "ns/roller-step" "real-time"
for rollers in 100 300 1000 3000 10000; do
  for run in $(seq 1 "$repeat"); do
    for threads in 1 2; do
      out=$(CHAINDRIVE_THREADS=$threads "$bin" "$frames" "$rollers")
      ns=$(sed -n 's/.*(\([0-9.]*\) ns per roller-step).*/\1/p' <<<"$out")
      rt=$(sed -n 's/.*real-time factor \([0-9.]*\).*/\1/p' <<<"$out")
      printf '%-8s %-7s %-6s %-18s %-12s\n' "$rollers" "$threads" "$run" "$ns" "$rt"
    done
  done
done
echo "machine: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg)"
