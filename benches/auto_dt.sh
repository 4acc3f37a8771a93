#!/usr/bin/env bash
# Convergence of the statistics a user reads against the step: each scene
# that runs (tests/data/short_60_30.toml is a chain too short by design)
# is run at the automatic step (`--dt auto`), at auto/2, auto/4 and at a
# fine reference (auto/16), and every statistic is compared with the
# reference. The table in benches/README.md ("Automatic step") comes from
# this script.
#
#   bash benches/auto_dt.sh [BINARY]
#
# Statistics: each segment's mean link force and its peak-to-peak, the
# largest link force, the slackest segment's mean, the deepest penetration
# and each free sprocket's speed peak-to-peak (the summary's window: the
# last second, or the whole run after the ramp when shorter).
set -euo pipefail
bin=${1:-target/release/chaindrive}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
# scene file (empty: the paper's drive without its explicit step) and duration, s
scenes=(
  "tests/data/motorcycle_520.toml 0.3"
  "tests/data/flat_30_30_real.toml 1.5"
  "tests/data/conveyor_sag_6m.toml 0.01"
  "tests/data/flat_20_40_1000rpm.toml 0.4"
  "paper 1.5"
)
printf '| scene | auto dt, µs | worst statistic | auto | auto/2 | auto/4 |\n|---|---|---|---|---|---|\n'
for entry in "${scenes[@]}"; do
  read -r scene duration <<<"$entry"
  if [[ $scene == paper ]]; then
    # The paper's drive with `solver.dt_s` left out.
    grep -v '^dt_s' assets/l60mc.toml >"$dir/paper.toml"
    file="$dir/paper.toml"
  else
    file=$scene
  fi
  "$bin" run "$file" --quiet --dt auto --duration "$duration" --summary "$dir/auto.json" >/dev/null
  auto=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["dt_s"])' "$dir/auto.json")
  for k in 2 4 16; do
    dt=$(python3 -c "print(repr($auto / $k))")
    "$bin" run "$file" --quiet --dt "$dt" --duration "$duration" --summary "$dir/d$k.json" >/dev/null
  done
  python3 - "$scene" "$dir" <<'PY'
import json, sys
scene, d = sys.argv[1], sys.argv[2]
def stats(path):
    s = json.load(open(path))
    out = {}
    for g in s["segments"]:
        out[f"seg{g['segment']} mean"] = g["mean_link_force_n"]
        out[f"seg{g['segment']} p2p"] = g["link_force_p2p_n"]
    out["link force max"] = s["link_force_max_n"]
    out["slack mean"] = min(g["mean_link_force_n"] for g in s["segments"])
    out["max penetration"] = s["max_penetration_m"]
    for p in s["sprockets"][1:]:
        out[f"sprocket{p['sprocket']} speed p2p"] = p["speed_p2p_rad_s"]
    return s["dt_s"], out
dt, a = stats(f"{d}/auto.json")
ref = stats(f"{d}/d16.json")[1]
runs = [a, stats(f"{d}/d2.json")[1], stats(f"{d}/d4.json")[1]]
# The relative change against the reference, scaled by the statistic's own
# size (for a peak-to-peak or a speed swing, by the segment mean or the
# mean speed would hide it: each is judged against itself).
def rel(x, r):
    return abs(x - r) / abs(r) if r != 0 else abs(x)
worst = max(ref, key=lambda k: rel(a[k], ref[k]))
cells = " | ".join(f"{100 * rel(x[worst], ref[worst]):.2f} %" for x in runs)
name = scene.split("/")[-1]
print(f"| {name} | {dt * 1e6:.2f} | {worst} | {cells} |")
for k in ref:
    print(f"<!-- {name} {k}: " + " ".join(f"{x[k]:.6g}" for x in runs) + f" ref {ref[k]:.6g} -->", file=sys.stderr)
PY
done
