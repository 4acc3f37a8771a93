#!/usr/bin/env bash
# Static equilibrium of every scene in tests/data and assets: the settle
# time `chaindrive check` prints (wall time of laying out, checking and
# settling the drive), slowest first, with the equilibrium's residual.
# Compare two builds by running it for each, one after the other, on an idle
# machine: the times are wall clock.
#
#   bash benches/settle_times.sh [BINARY]
set -euo pipefail
bin=${1:-target/release/chaindrive}
cd "$(dirname "$0")/.."
for scene in tests/data/*.toml assets/*.toml; do
  case $scene in *study*) continue ;; esac
  line=$("$bin" check "$scene" 2>/dev/null | grep '^static equilibrium:' || true)
  if [ -z "$line" ]; then
    printf '%8s  %-44s %s\n' "-" "$scene" "(no equilibrium: see chaindrive check)"
    continue
  fi
  seconds=$(sed -E 's/.*, ([0-9.]+) s$/\1/' <<<"$line")
  residual=$(sed -E 's/.*residual ([^ ]+) of the pretension.*/\1/' <<<"$line")
  printf '%8s  %-44s residual %s\n' "$seconds" "$scene" "$residual"
done | sort -rn
