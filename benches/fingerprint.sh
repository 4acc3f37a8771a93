#!/usr/bin/env bash
# Fingerprints of the paper's drive: one SHA-256 per (profile, integrator) of
# the run summary without its wall-clock fields, and of the sampled series.
# A refactor that must not change results compares these before and after.
#
#   bash benches/fingerprint.sh [BINARY] [DURATION_S] [SCENE] [INTEGRATOR] [DT_S]
#
# SCENE (default: the embedded paper's drive), one INTEGRATOR (default: the
# five below) and DT_S (default: the scene's) narrow the runs, e.g.
#   bash benches/fingerprint.sh BIN 0.3 assets/l60mc-friction.toml velocity_verlet 5e-5
set -euo pipefail
bin=${1:-target/release/chaindrive}
duration=${2:-1.5}
scene=${3:-}
integrators=${4:-symplectic_euler velocity_verlet rk4 dormand_prince45 implicit_damping}
dt=${5:-}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
for profile in circular real; do
  for integrator in $integrators; do
    "$bin" run ${scene:+"$scene"} ${dt:+--dt "$dt"} --quiet --profile "$profile" --integrator "$integrator" --duration "$duration" \
      --summary "$dir/s.json" --series "$dir/s.csv" >/dev/null
    summary=$(python3 -c '
import json, sys
d = json.load(open(sys.argv[1]))
for k in ("wall_s", "setup_wall_s", "ns_per_step"):
    d.pop(k, None)
print(json.dumps(d, sort_keys=True))' "$dir/s.json" | sha256sum | cut -c1-16)
    series=$(sha256sum "$dir/s.csv" | cut -c1-16)
    printf '%-9s %-17s summary %s series %s\n' "$profile" "$integrator" "$summary" "$series"
  done
done
