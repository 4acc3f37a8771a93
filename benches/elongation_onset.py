#!/usr/bin/env python3
"""Onset of tooth jumps and tip rides against wear elongation, per tooth count.

Two-sprocket drives of equal sprockets (19, 30, 45 teeth), ANSI 80, 111
links, 100 rpm, no gravity, the driven sprocket loaded to 12 kN in the tight
strand over 0.5 s, run 1 s: on fixed centres (1 kN pretension by the links'
rest length) and with the driven sprocket a tensioner (2 kN). For each,
`chaindrive jump-margin --path chain.elongation_pct` brackets the largest
elongation run clean (no jump, no roller riding a tip). Writes the bracket
table (JSON) and docs/figures/elongation-onset.svg with the 200/z rule, the
3 % cap and the quasi-static ride-over 336/z.

    python3 benches/elongation_onset.py [BINARY] [OUT.svg]
    python3 benches/elongation_onset.py --redraw docs/figures/elongation-onset.json   # the figure from its table, no runs
"""
import json
import math
import os
import subprocess
import sys
import tempfile

BIN = sys.argv[1] if len(sys.argv) > 1 else "target/release/chaindrive"
OUT = sys.argv[2] if len(sys.argv) > 2 else "docs/figures/elongation-onset.svg"
TEETH = (19, 30, 45)
PITCH_M = 0.0254


def two_sprocket_scene(z, tensioned, name, pretension_n, torque_n_m, load_ramp_s, duration_s):
    """Equal z-tooth sprockets 111 ANSI 80 links apart, no gravity, 100 rpm,
    the driven one loaded with `torque_n_m`: on fixed centres, or the
    driven sprocket a tensioner (shared with slack_tension_onset.py)."""
    centre = (111 - z) / 2 * PITCH_M
    role = 'role = "tensioner"\nadjust_direction = [1.0, 0.0]' if tensioned else 'role = "free"'
    return f'''name = "{name}"
gravity_m_s2 = [0.0, 0.0]
profile = "real"
[chain]
designation = "ANSI 80"
rollers = 111
damping_n_s_m = 50.0
pretension_n = {pretension_n}
pretension_by = "{'tensioner' if tensioned else 'rest_length'}"
joint_friction = 0.1
[contact]
stiffness = 1e9
restitution = 0.5
min_approach_speed_m_s = 0.1
[[sprockets]]
name = "driver"
center_m = [0.0, 0.0]
teeth = {z}
mass_kg = 2.0
inertia_kg_m2 = 0.02
wrap = "ccw"
role = "driver"
speed_rpm = 100.0
ramp_s = 0.2
[[sprockets]]
name = "driven"
center_m = [{centre:.4f}, 0.0]
teeth = {z}
mass_kg = 2.0
inertia_kg_m2 = 0.02
wrap = "ccw"
{role}
load_torque_n_m = {torque_n_m}
load_ramp_s = {load_ramp_s}
[solver]
duration_s = {duration_s}
'''


def scene(z, tensioned):
    rp = PITCH_M / (2 * math.sin(math.pi / z))
    return two_sprocket_scene(z, tensioned, f"{z}/{z} ANSI 80", 2000.0 if tensioned else 1000.0,
                              round(12000 * rp, -1), 0.5, 1.0)


def with_scene(text, f):
    """`f` called with the path of a temporary scene file holding `text`."""
    with tempfile.NamedTemporaryFile("w", suffix=".toml", delete=False) as t:
        t.write(text)
    try:
        return f(t.name)
    finally:
        os.unlink(t.name)


def jump_margin(binary, text, top, tolerance):
    """`jump-margin --path chain.elongation_pct` from 0 to `top` on the
    scene `text`: its margin (JSON), or {"clean_to": top} when both ends
    ran clean, or {"error": the last line of its complaint}."""
    out = with_scene(text, lambda path: subprocess.run(
        [binary, "jump-margin", path, "--path", "chain.elongation_pct", "--from", "0",
         "--to", str(top), "--tolerance", str(tolerance), "--jobs", "2", "--json"],
        capture_output=True, text=True))
    if out.returncode != 0:
        err = out.stderr.strip().splitlines()[-1] if out.stderr else "failed"
        if "ran clean and the run at" in err and err.count("ran clean") == 2:
            return {"clean_to": top}
        return {"error": err}
    return json.loads(out.stdout)["margin"]


def bracket(z, tensioned, top):
    m = jump_margin(BIN, scene(z, tensioned), top, 0.25)
    if "clean" not in m:
        return m
    return {"clean": m["clean"], "jumping": m["jumping"], "probes": m["probes"]}


def svg(rows):
    w, h, l, r, t, b = 760, 470, 80, 200, 50, 60
    zmin, zmax, emin, emax = 15, 50, 0.1, 30.0
    x = lambda z: l + (z - zmin) / (zmax - zmin) * (w - l - r)
    # Logarithmic: the fixed centres' onsets (tenths of a percent) and the
    # tensioned ones (several percent) both readable.
    y = lambda e: h - b - math.log10(max(e, emin) / emin) / math.log10(emax / emin) * (h - t - b)
    s = [f'<svg width="{w}" height="{h}" viewBox="0 0 {w} {h}" xmlns="http://www.w3.org/2000/svg" font-family="sans-serif">',
         f'<rect x="0" y="0" width="{w}" height="{h}" fill="#FFFFFF"/>',
         f'<text x="{(l + w - r) / 2}" y="28" text-anchor="middle" font-size="16">Onset of tip rides and tooth jumps against wear (ANSI 80, 12 kN)</text>']
    for e in (0.1, 0.2, 0.5, 1, 2, 3, 5, 10, 20, 30):
        s.append(f'<line x1="{l}" y1="{y(e)}" x2="{w - r}" y2="{y(e)}" stroke="#E0E0E0"/>')
        s.append(f'<text x="{l - 8}" y="{y(e) + 4}" text-anchor="end" font-size="12">{e}</text>')
    for z in range(15, 51, 5):
        s.append(f'<line x1="{x(z)}" y1="{h - b}" x2="{x(z)}" y2="{h - b + 5}" stroke="#000"/>')
        s.append(f'<text x="{x(z)}" y="{h - b + 20}" text-anchor="middle" font-size="12">{z}</text>')
    s.append(f'<rect x="{l}" y="{t}" width="{w - l - r}" height="{h - t - b}" fill="none" stroke="#000"/>')
    s.append(f'<text x="{(l + w - r) / 2}" y="{h - 15}" text-anchor="middle" font-size="13">teeth z (both sprockets)</text>')
    s.append(f'<text x="22" y="{(t + h - b) / 2}" text-anchor="middle" font-size="13" transform="rotate(270, 22, {(t + h - b) / 2})">chain elongation (%, log scale)</text>')

    def curve(f, colour, dash):
        pts = " ".join(f"{x(z):.1f},{y(min(f(z), emax)):.1f}" for z in range(zmin, zmax + 1))
        return f'<polyline points="{pts}" fill="none" stroke="{colour}" stroke-width="2" stroke-dasharray="{dash}"/>'
    s.append(curve(lambda z: 200 / z, "#1f77b4", "none"))
    s.append(curve(lambda z: 3.0, "#2ca02c", "6,4"))
    s.append(curve(lambda z: 336 / z, "#9467bd", "2,3"))
    colours = {False: "#d62728", True: "#ff7f0e"}
    for (z, tensioned), v in rows.items():
        c, dz = colours[tensioned], (0.6 if tensioned else -0.6)
        if "clean_to" in v:
            # Clean over the whole range searched: an arrow up from its top.
            s.append(f'<line x1="{x(z + dz)}" y1="{y(v["clean_to"])}" x2="{x(z + dz)}" y2="{y(v["clean_to"]) - 18}" stroke="{c}" stroke-width="3"/>')
            s.append(f'<path d="M {x(z + dz) - 6} {y(v["clean_to"]) - 16} l 6 -10 l 6 10 z" fill="{c}"/>')
            continue
        if "clean" not in v:
            continue
        lo, hi = sorted((v["clean"], v["jumping"]))
        s.append(f'<line x1="{x(z + dz)}" y1="{y(lo)}" x2="{x(z + dz)}" y2="{y(hi)}" stroke="{c}" stroke-width="3"/>')
        marker = f'<rect x="{x(z + dz) - 5}" y="{y((lo + hi) / 2) - 5}" width="10" height="10" fill="{c}"/>' if tensioned \
            else f'<circle cx="{x(z + dz)}" cy="{y((lo + hi) / 2)}" r="5" fill="{c}"/>'
        s.append(marker)
    lx, ly = w - r + 15, t + 10
    legend = [("line", "#1f77b4", "none", "200/z rule"), ("line", "#2ca02c", "6,4", "3 % cap"),
              ("line", "#9467bd", "2,3", "ride-over 336/z"),
              ("circle", colours[False], None, "fixed centres, 1 kN"),
              ("rect", colours[True], None, "tensioner, 2 kN")]
    for k, (kind, c, dash, text) in enumerate(legend):
        yy = ly + 22 * k
        if kind == "line":
            s.append(f'<line x1="{lx}" y1="{yy}" x2="{lx + 28}" y2="{yy}" stroke="{c}" stroke-width="2" stroke-dasharray="{dash}"/>')
        elif kind == "circle":
            s.append(f'<circle cx="{lx + 14}" cy="{yy}" r="5" fill="{c}"/>')
        else:
            s.append(f'<rect x="{lx + 9}" y="{yy - 5}" width="10" height="10" fill="{c}"/>')
        s.append(f'<text x="{lx + 36}" y="{yy + 4}" font-size="12">{text}</text>')
    s.append(f'<text x="{lx}" y="{ly + 22 * 5 + 4}" font-size="11">bar: last clean to first</text>')
    s.append(f'<text x="{lx}" y="{ly + 22 * 5 + 18}" font-size="11">ride or jump (1 s runs);</text>')
    s.append(f'<text x="{lx}" y="{ly + 22 * 5 + 32}" font-size="11">arrow: clean up to 15 %</text>')
    s.append('</svg>')
    return "\n".join(s) + "\n"


def main():
    if len(sys.argv) > 2 and sys.argv[1] == "--redraw":
        # Draw the figure again from a table this script wrote, without runs.
        with open(sys.argv[2]) as f:
            table = json.load(f)
        rows = {(v["teeth"], v["tensioned"]): v for v in table}
        with open(os.path.splitext(sys.argv[2])[0] + ".svg", "w") as f:
            f.write(svg(rows))
        return
    rows = {}
    for z in TEETH:
        for tensioned in (False, True):
            rows[(z, tensioned)] = bracket(z, tensioned, 15.0 if tensioned else 4.0)
            print(z, "tensioner" if tensioned else "fixed", {k: v for k, v in rows[(z, tensioned)].items() if k != "probes"}, flush=True)
    with open(OUT, "w") as f:
        f.write(svg(rows))
    with open(os.path.splitext(OUT)[0] + ".json", "w") as f:
        json.dump([{"teeth": z, "tensioned": tz, **v} for (z, tz), v in rows.items()], f, indent=1)


if __name__ == "__main__":
    main()
