"""The Python module against the command line, on the paper's drive.

1. Speed: a 10 s run of the paper's drive (the scene file's settings:
   velocity Verlet, dt = 10 us, samples at 1 kHz) through `chaindrive run`
   and through `chaindrive.run`, alternating, each in a fresh process; the
   in-process time per step is each summary's `ns_per_step` (the stepping
   loop's wall time over its steps, observers included). Prints each pair
   and the ratio Python / CLI, and whether the two summaries agree.
2. The series: a 60 s run at 1 kHz through `chaindrive.run` with the
   series kept (`series=True`, 60 001 rows x 17 columns) and without,
   alternating: the time per step (the per-sample copy of a row into the
   series' vectors is inside the loop) and the time outside the loop (the
   call's wall time minus the setup and the loop: the summary, its
   conversion to Python data and the series' handover to NumPy).

    cargo build --release && pip install ./python
    python benches/python_vs_cli.py [PAIRS [SERIES_PAIRS [BINARY]]]    # 3, 2, target/release/chaindrive
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile

CHILD = r"""
import json, sys, time
import chaindrive as cd
duration, series = float(sys.argv[1]), sys.argv[2] == "1"
started = time.perf_counter()
r = cd.run(cd.Scene.l60mc(), duration=duration, series=series)
call_s = time.perf_counter() - started
s = r.summary
arrays = [r.series.t_s, r.series.omega_rad_s, r.series.chain_torque_n_m, r.series.segment_force_n, r.series.transverse_m]
print(json.dumps({"summary": s, "call_s": call_s,
                  "series_bytes": sum(a.nbytes for a in arrays), "rows": len(r.series)}))
"""

SKIP = {"wall_s", "ns_per_step", "setup_wall_s"}


def python_run(duration: float, series: bool) -> dict:
    out = subprocess.run(
        [sys.executable, "-c", CHILD, str(duration), "1" if series else "0"],
        check=True, capture_output=True, text=True,
    ).stdout
    return json.loads(out.strip().splitlines()[-1])


def cli_run(binary: str) -> dict:
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, "s.json")
        subprocess.run([binary, "run", "--quiet", "--summary", path],
                       check=True, capture_output=True)
        with open(path) as f:
            return json.load(f)


def physics(summary: dict) -> str:
    return json.dumps({k: v for k, v in summary.items() if k not in SKIP}, sort_keys=True)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("pairs", type=int, nargs="?", default=3)
    ap.add_argument("series_pairs", type=int, nargs="?", default=2)
    ap.add_argument("binary", nargs="?", default="target/release/chaindrive")
    a = ap.parse_args()

    ratios = []
    if a.pairs:
        print("10 s of the paper's drive, ns per step (in-process, the stepping loop):")
    for i in range(a.pairs):
        cli = cli_run(a.binary)
        py = python_run(10.0, True)["summary"]
        ratio = py["ns_per_step"] / cli["ns_per_step"]
        ratios.append(ratio)
        same = "same summary" if physics(py) == physics(cli) else "summaries DIFFER"
        print(f"  pair {i + 1}: CLI {cli['ns_per_step']:8.0f}  Python {py['ns_per_step']:8.0f}"
              f"  ratio {ratio:.3f}  ({same}; load {os.getloadavg()[0]:.1f})")
    ratios.sort()
    if ratios:
        print(f"  ratio Python / CLI: median {ratios[len(ratios) // 2]:.3f}, range {ratios[0]:.3f}-{ratios[-1]:.3f}")

    if a.series_pairs:
        print("60 s at 1 kHz through Python, with and without the series:")
    for i in range(a.series_pairs):
        for series in (True, False):
            r = python_run(60.0, series)
            s = r["summary"]
            outside = r["call_s"] - s["setup_wall_s"] - s["wall_s"]
            print(f"  {'series' if series else 'no series'}: {s['ns_per_step']:7.0f} ns/step,"
                  f" {r['rows']} rows, {r['series_bytes'] / 1e6:.1f} MB,"
                  f" outside the loop {outside * 1e3:.1f} ms (call {r['call_s']:.1f} s;"
                  f" load {os.getloadavg()[0]:.1f})")


if __name__ == "__main__":
    main()
