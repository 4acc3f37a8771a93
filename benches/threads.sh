#!/usr/bin/env bash
# Two threads against one by drive size: the co-simulated conveyor of
# examples/long_conveyor.rs (real profile, dt 50 µs, 60 Hz world, started
# moving) with 100 … 10,000 rollers, each size run on one thread and on
# two, interleaved, REPEAT times. Prints the wall time per frame (mean and
# fastest), the chain's ns per roller-step (the substeps alone) and the
# frame's real-time factor; then the machine and its load.
#
#   bash benches/threads.sh [FRAMES] [REPEAT] [ROLLERS...]
#   bash benches/threads.sh 120 3 10000     # the 10,000-roller conveyor only
set -euo pipefail
frames=${1:-60}
repeat=${2:-2}
shift $(($# < 2 ? $# : 2))
sizes=("$@")
[ ${#sizes[@]} -gt 0 ] || sizes=(100 300 1000 3000 10000)
cargo build --release --quiet --example long_conveyor
bin=target/release/examples/long_conveyor
echo "load before: $(cut -d' ' -f1-3 /proc/loadavg)"
printf '%-8s %-7s %-4s %-10s %-10s %-15s %-9s\n' rollers threads run "ms/frame" "fastest" "ns/roller-step" "real-time"
for rollers in "${sizes[@]}"; do
  for run in $(seq 1 "$repeat"); do
    for threads in 2 1; do
      out=$(CHAINDRIVE_THREADS=$threads "$bin" "$frames" "$rollers")
      ms=$(sed -n 's/.*: \([0-9.]*\) ms wall per frame.*/\1/p' <<<"$out")
      fast=$(sed -n 's/^frames: fastest \([0-9.]*\) ms.*/\1/p' <<<"$out")
      ns=$(sed -n 's/.*(\([0-9.]*\) ns per roller-step).*/\1/p' <<<"$out")
      rt=$(sed -n 's/.*real-time factor \([0-9.]*\).*/\1/p' <<<"$out")
      printf '%-8s %-7s %-4s %-10s %-10s %-15s %-9s\n' "$rollers" "$threads" "$run" "$ms" "$fast" "$ns" "$rt"
    done
  done
done
echo "machine: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores, load after $(cut -d' ' -f1-3 /proc/loadavg)"
