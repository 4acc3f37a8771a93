"""The paper's drive from Python: one run, a small speed sweep, and a figure.

Runs the MAN B&W L60MC camshaft drive (Pedersen 2005) for 3 s, prints its
segments' mean link forces, sweeps the driver speed of a two-sprocket
ISO 606 16B drive over four speeds into a pandas table, and draws both with
matplotlib into OUT/paper_drive.png.

    pip install ./python pandas matplotlib
    python examples/python/paper_drive.py [OUT]        # OUT defaults to python-example
"""

from __future__ import annotations

import pathlib
import sys

import matplotlib

matplotlib.use("Agg")  # files only: no window
import matplotlib.pyplot as plt
import numpy as np

import chaindrive as cd

ROOT = pathlib.Path(__file__).resolve().parents[2]


def main(out: pathlib.Path) -> None:
    out.mkdir(parents=True, exist_ok=True)

    # One run of the paper's drive: 1 s ramp to 120 rpm, then 2 s steady.
    paper = cd.run(cd.Scene.l60mc(), duration=3.0)
    summary = paper.summary
    print(f"{summary['scene']}: {summary['steps']} steps, {summary['ns_per_step']:.0f} ns per step")
    for seg in summary["segments"]:
        print(
            f"  segment {seg['segment']}: mean link force {seg['mean_link_force_n'] / 1e3:.2f} kN "
            f"(peak to peak {seg['link_force_p2p_n'] / 1e3:.2f} kN)"
        )

    # A small sweep: one steady run per driver speed, long tables back.
    drive = cd.Scene.from_file(ROOT / "tests" / "data" / "designation_16b.toml")
    sweep = cd.sweep(drive, [60, 120, 180, 240], settle=0.2, window=1.2)
    wide = sweep.to_pandas(wide=True)
    print(wide[["segment1.mean_link_force_n", "link_force_max_n"]])

    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.2), constrained_layout=True)
    s = paper.series
    last = s.t_s >= summary["duration_s"] - 0.25
    for k, color in ((0, "tab:blue"), (1, "tab:orange")):
        mean_kn = summary["segments"][k]["mean_link_force_n"] / 1e3
        left.plot(s.t_s[last], s.segment_force_n[last, k] / 1e3, lw=0.9, color=color,
                  label=f"segment {k + 1} (mean {mean_kn:.1f} kN)")
        left.axhline(mean_kn, color=color, ls="--", lw=0.8)
    left.set_xlabel("time, s")
    left.set_ylabel("link force, kN (mean over the free strand)")
    left.set_title("Paper's drive at 120 rpm: the last 0.25 s")
    left.legend(loc="lower right", fontsize=8)
    left.grid(alpha=0.3)

    rpm = wide.index.to_numpy()
    right.plot(rpm, wide["segment1.mean_link_force_n"], "o-", label="segment 1, mean")
    right.plot(rpm, wide["link_force_max_n"], "s-", label="largest link force")
    right.set_xlabel("driver speed, rpm")
    right.set_ylabel("link force, N")
    right.set_title("16B-1 19T/38T over the last 1.2 s of each speed")
    right.legend(fontsize=8)
    right.grid(alpha=0.3)

    path = out / "paper_drive.png"
    fig.savefig(path, dpi=110)
    print(f"figure: {path}")


if __name__ == "__main__":
    main(pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "python-example"))
