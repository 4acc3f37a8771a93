#!/usr/bin/env python3
"""Onset of tip rides against wear elongation and the slack strand's tension.

Two-sprocket drives of equal sprockets (19, 30, 45 teeth), ANSI 80, 111
links, 100 rpm, no gravity, the driven sprocket loaded to 4 kN of effective
pull (tight minus slack strand) over 0.3 s, run 0.6 s. Five installation
tensions T0 (2.5 to 10 kN) set the slack strand's tension under the load,
T0 - 2 kN by hand (equal strands of equal stiffness on fixed centres share
the load's pull half and half), and each run at zero wear measures it (the
slack strand's mean link force over the last 0.2 s). For each tension, two
drives:

- fixed centres, the tension set by the links' rest length (the wear's
  slack, 111 P e, is not taken up): the slack strand goes slack at
  e = T_s / (K P), 0.0142 % per kN for ANSI 80 (K = 2.782e8 N/m);
- a tensioner sprocket that sets the tension at rest for the worn chain
  (the wear taken up): the rollers climb the flanks towards the tips
  quasi-statically, reaching them at about 336/z %.

`chaindrive jump-margin --path chain.elongation_pct` brackets the largest
elongation that ran clean (no tooth jump, no roller riding a tip; fixed
centres 0 to 3 % to 0.02 %, the tensioner 0 to 15 % (the largest allowed) to 0.25 %). Writes the
table (JSON) and docs/figures/slack-tension-onset.svg with 200/z, 336/z and
the fixed centres' T_s / (K P).

    python3 benches/slack_tension_onset.py [BINARY] [OUT.svg]
    python3 benches/slack_tension_onset.py --redraw docs/figures/slack-tension-onset.json   # the figure from its table, no runs
"""
import json
import math
import os
import subprocess
import sys
import tempfile

from elongation_onset import jump_margin, two_sprocket_scene, with_scene

TEETH = (19, 30, 45)
TENSIONS_N = (2500.0, 3000.0, 4000.0, 6000.0, 10000.0)
PULL_N = 4000.0
PITCH_M = 0.0254
STIFFNESS_N_M = 2.782e8
DURATION_S = 0.6
COLOURS = {19: "#1f77b4", 30: "#d62728", 45: "#2ca02c"}


def scene(z, tensioned, pretension_n):
    rp = PITCH_M / (2 * math.sin(math.pi / z))
    return two_sprocket_scene(z, tensioned, f"{z}/{z} ANSI 80, {pretension_n:.0f} N", pretension_n,
                              round(PULL_N * rp, 1), 0.3, DURATION_S)


def strand_tensions(binary, z, pretension_n):
    """The slack and tight strands' mean link forces, N, of the new chain
    over the last 0.2 s."""
    def run(path):
        with tempfile.TemporaryDirectory() as d:
            out = os.path.join(d, "s.json")
            r = subprocess.run([binary, "run", path, "--quiet", "--window", "0.2", "--summary", out],
                               capture_output=True, text=True)
            if r.returncode != 0:
                return None
            with open(out) as f:
                s = json.load(f)
        forces = sorted(seg["mean_link_force_n"] for seg in s["segments"])
        return forces[0], forces[-1]
    return with_scene(scene(z, False, pretension_n), run)


def bracket(binary, z, tensioned, pretension_n):
    top, tolerance = (15.0, 0.25) if tensioned else (3.0, 0.02)
    m = jump_margin(binary, scene(z, tensioned, pretension_n), top, tolerance)
    if "clean" not in m:
        return m
    return {"clean": m["clean"], "jumping": m["jumping"], "monotone": m["monotone"],
            "runs": len(m["probes"])}


def svg(rows):
    """Two panels: every onset on a log scale with 200/z and 336/z (top);
    the fixed centres' onsets on a linear scale with the slope of
    T_s / (K P) (bottom)."""
    w, h, l, r = 780, 820, 80, 230
    t1, b1, t2, b2 = 50, 440, 500, 760
    smin, smax, emin, emax = 0.0, 9.0, 0.01, 30.0
    x = lambda s: l + (s - smin) / (smax - smin) * (w - l - r)
    y1 = lambda e: b1 - math.log10(min(max(e, emin), emax) / emin) / math.log10(emax / emin) * (b1 - t1)
    lin_max = 0.6
    y2 = lambda e: b2 - min(max(e, 0.0), lin_max) / lin_max * (b2 - t2)
    s = [f'<svg width="{w}" height="{h}" viewBox="0 0 {w} {h}" xmlns="http://www.w3.org/2000/svg" font-family="sans-serif">',
         f'<rect x="0" y="0" width="{w}" height="{h}" fill="#FFFFFF"/>',
         f'<text x="{(l + w - r) / 2}" y="28" text-anchor="middle" font-size="16">Onset of tip rides: wear against slack-strand tension (ANSI 80)</text>']
    for e in (0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1, 2, 5, 10, 20):
        s.append(f'<line x1="{l}" y1="{y1(e)}" x2="{w - r}" y2="{y1(e)}" stroke="#E0E0E0"/>')
        s.append(f'<text x="{l - 8}" y="{y1(e) + 4}" text-anchor="end" font-size="12">{e}</text>')
    for k in range(7):
        e = 0.1 * k
        s.append(f'<line x1="{l}" y1="{y2(e)}" x2="{w - r}" y2="{y2(e)}" stroke="#E0E0E0"/>')
        s.append(f'<text x="{l - 8}" y="{y2(e) + 4}" text-anchor="end" font-size="12">{e:.1f}</text>')
    for top, bottom in ((t1, b1), (t2, b2)):
        for k in range(0, 10):
            s.append(f'<line x1="{x(k)}" y1="{bottom}" x2="{x(k)}" y2="{bottom + 5}" stroke="#000"/>')
            s.append(f'<text x="{x(k)}" y="{bottom + 20}" text-anchor="middle" font-size="12">{k}</text>')
        s.append(f'<rect x="{l}" y="{top}" width="{w - l - r}" height="{bottom - top}" fill="none" stroke="#000"/>')
    s.append(f'<text x="{(l + w - r) / 2}" y="{b2 + 45}" text-anchor="middle" font-size="13">slack-strand tension under load, kN (measured, new chain)</text>')
    s.append(f'<text x="22" y="{(t1 + b1) / 2}" text-anchor="middle" font-size="13" transform="rotate(270, 22, {(t1 + b1) / 2})">chain elongation (%, log scale)</text>')
    s.append(f'<text x="22" y="{(t2 + b2) / 2}" text-anchor="middle" font-size="13" transform="rotate(270, 22, {(t2 + b2) / 2})">fixed centres: elongation (%)</text>')
    s.append(f'<text x="{l + 8}" y="{t2 + 18}" font-size="12">fixed centres, linear scale</text>')

    def hline(e, colour, dash):
        return f'<line x1="{l}" y1="{y1(e):.1f}" x2="{w - r}" y2="{y1(e):.1f}" stroke="{colour}" stroke-width="1.5" stroke-dasharray="{dash}"/>'
    for z, c in COLOURS.items():
        s.append(hline(200 / z, c, "none"))
        s.append(hline(336 / z, c, "2,3"))
    s.append(hline(3.0, "#555555", "6,4"))
    # Fixed centres: the slack strand goes slack at T_s / (K P) (top); the
    # same slope through each tooth count's onset at its lowest tension
    # (bottom): what the tension alone would add to the wear the drive takes.
    per_pct_n = 100 * 1.0 / (STIFFNESS_N_M * PITCH_M)
    pts = " ".join(f"{x(k / 10):.1f},{y1(k / 10 * 1000 * per_pct_n):.1f}" for k in range(1, 91))
    s.append(f'<polyline points="{pts}" fill="none" stroke="#777777" stroke-width="2" stroke-dasharray="8,3,2,3"/>')
    for z, c in COLOURS.items():
        fixed = sorted((v for v in rows if v["teeth"] == z and not v["tensioned"] and "clean" in v
                        and v.get("slack_n") is not None), key=lambda v: v["slack_n"])
        if not fixed:
            continue
        s0, e0 = fixed[0]["slack_n"], (fixed[0]["clean"] + fixed[0]["jumping"]) / 2
        x_a, x_b = s0 / 1000, smax
        s.append(f'<line x1="{x(x_a):.1f}" y1="{y2(e0):.1f}" x2="{x(x_b):.1f}" y2="{y2(e0 + (x_b * 1000 - s0) * per_pct_n):.1f}" '
                 f'stroke="{c}" stroke-width="1.5" stroke-dasharray="8,3,2,3"/>')
    for v in rows:
        z, tensioned, c = v["teeth"], v["tensioned"], COLOURS[v["teeth"]]
        if v.get("slack_n") is None:
            continue
        sx = x(max(v["slack_n"], 0.0) / 1000 + (0.06 if tensioned else -0.06) * (TEETH.index(z) - 1))
        if "clean_to" in v:
            s.append(f'<line x1="{sx}" y1="{y1(v["clean_to"])}" x2="{sx}" y2="{y1(v["clean_to"]) - 18}" stroke="{c}" stroke-width="3"/>')
            s.append(f'<path d="M {sx - 6} {y1(v["clean_to"]) - 16} l 6 -10 l 6 10 z" fill="{c}"/>')
            continue
        if "clean" not in v:
            continue
        lo, hi = sorted((v["clean"], v["jumping"]))
        panels = [(y1, True)] + ([] if tensioned else [(y2, False)])
        for y, _ in panels:
            s.append(f'<line x1="{sx}" y1="{y(max(lo, emin))}" x2="{sx}" y2="{y(hi)}" stroke="{c}" stroke-width="3"/>')
            mid = y(max((lo + hi) / 2, emin))
            s.append(f'<rect x="{sx - 5}" y="{mid - 5}" width="10" height="10" fill="{c}"/>' if tensioned
                     else f'<circle cx="{sx}" cy="{mid}" r="5" fill="{c}"/>')
    lx, ly = w - r + 15, t1 + 10
    legend = [("line", "#1f77b4", "none", "200/z (19, 30, 45 teeth)"),
              ("line", "#1f77b4", "2,3", "ride-over 336/z"),
              ("line", "#555555", "6,4", "3 % cap"),
              ("line", "#777777", "8,3,2,3", "slack at T_s/(K P)"),
              ("circle", "#000000", None, "fixed centres"),
              ("rect", "#000000", None, "tensioner, wear taken up")]
    for k, (kind, c, dash, text) in enumerate(legend):
        yy = ly + 22 * k
        if kind == "line":
            s.append(f'<line x1="{lx}" y1="{yy}" x2="{lx + 28}" y2="{yy}" stroke="{c}" stroke-width="2" stroke-dasharray="{dash}"/>')
        elif kind == "circle":
            s.append(f'<circle cx="{lx + 14}" cy="{yy}" r="5" fill="{c}"/>')
        else:
            s.append(f'<rect x="{lx + 9}" y="{yy - 5}" width="10" height="10" fill="{c}"/>')
        s.append(f'<text x="{lx + 36}" y="{yy + 4}" font-size="12">{text}</text>')
    yy = ly + 22 * len(legend) + 4
    for k, (z, c) in enumerate(COLOURS.items()):
        s.append(f'<rect x="{lx + 9}" y="{yy + 20 * k - 5}" width="10" height="10" fill="{c}"/>')
        s.append(f'<text x="{lx + 36}" y="{yy + 20 * k + 4}" font-size="12">z = {z}</text>')
    yy += 20 * len(COLOURS) + 10
    for k, line in enumerate(["bar: last clean elongation", "to first ride or jump", f"({DURATION_S} s runs, 4 kN pull);",
                              "arrow: clean to 15 %"]):
        s.append(f'<text x="{lx}" y="{yy + 14 * k}" font-size="11">{line}</text>')
    for k, line in enumerate(["dash-dot: the slope of", "T_s/(K P), 0.0142 % per kN,", "through each z's onset",
                              "at its lowest tension"]):
        s.append(f'<text x="{lx}" y="{t2 + 14 + 14 * k}" font-size="11">{line}</text>')
    s.append('</svg>')
    return "\n".join(s) + "\n"


def main():
    if len(sys.argv) > 2 and sys.argv[1] == "--redraw":
        # Draw the figure again from a table this script wrote, without runs.
        with open(sys.argv[2]) as f:
            rows = json.load(f)
        with open(os.path.splitext(sys.argv[2])[0] + ".svg", "w") as f:
            f.write(svg(rows))
        return
    binary = sys.argv[1] if len(sys.argv) > 1 else "target/release/chaindrive"
    out = sys.argv[2] if len(sys.argv) > 2 else "docs/figures/slack-tension-onset.svg"
    rows = []
    for z in TEETH:
        for t0 in TENSIONS_N:
            measured = strand_tensions(binary, z, t0)
            for tensioned in (False, True):
                v = {"teeth": z, "tensioned": tensioned, "pretension_n": t0,
                     "slack_by_hand_n": t0 - PULL_N / 2,
                     "slack_n": measured[0] if measured else None,
                     "tight_n": measured[1] if measured else None,
                     **bracket(binary, z, tensioned, t0)}
                rows.append(v)
                print(json.dumps(v), flush=True)
            with open(os.path.splitext(out)[0] + ".json", "w") as f:
                json.dump(rows, f, indent=1)
    with open(out, "w") as f:
        f.write(svg(rows))


if __name__ == "__main__":
    main()
