"""The rest of the tool from Python: check, sweep, study, rate, recording
to MCAP and checkpoints."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import chaindrive as cd


def test_check_lays_out_the_paper_drive_at_its_pretension():
    report = cd.check(cd.Scene.l60mc())
    # Static equilibrium at the 21 kN pretension (the rest length is tuned to it).
    assert report["static_tension_n"] == pytest.approx(21000.0, rel=0.005)
    assert [s["teeth"] for s in report["sprockets"]] == [60, 30, 28, 30]
    for s in report["sprockets"]:
        # R = P / (2 sin(pi/N))
        assert s["pitch_radius_m"] == pytest.approx(0.0889 / (2 * math.sin(math.pi / s["teeth"])), rel=1e-5)
    # Four free strands, each between consecutive sprockets; the wraps and
    # strands together hold the chain's 122 pitches (the polygon through
    # the seated rollers).
    assert [(st["from"], st["to"]) for st in report["strands"]] == [(1, 2), (2, 3), (3, 4), (4, 1)]
    assert report["polygon_length_m"] == pytest.approx(122 * 0.0889, rel=0.01)
    assert report["chain_length_m"] == pytest.approx(122 * 0.0889)


def test_check_raises_for_a_chain_that_does_not_fit(data):
    scene = cd.Scene.from_file(data / "designation_16b.toml").with_({"chain.rollers": 60})
    with pytest.raises(cd.SimError):
        cd.check(scene)


def test_sweep_returns_long_tables(data):
    pd = pytest.importorskip("pandas")
    scene = cd.Scene.from_file(data / "designation_16b.toml")
    result = cd.sweep(scene, [60, 90, 120], settle=0.2, window=1.2, jobs=2)
    assert list(result.cases["rpm"]) == [60.0, 90.0, 120.0]
    assert all(s in ("ok", "warned") for s in result.cases["status"])
    long = result.to_pandas()
    assert list(long.columns) == ["rpm", "statistic", "value"]
    wide = result.to_pandas(wide=True)
    # The driver's mean speed is the asked one: omega = 2 pi rpm / 60.
    w = wide["sprocket1.mean_speed_rad_s"]
    assert w.to_numpy() == pytest.approx(2 * np.pi * np.array([60, 90, 120]) / 60, rel=1e-6)
    assert set(result.summaries) == {60.0, 90.0, 120.0}
    orders = result.orders.to_pandas()
    assert {"rpm", "signal", "order", "frequency_hz", "amplitude", "phase_rad"} <= set(orders.columns)
    # An order's frequency is the order times the driver's turning frequency.
    row = orders.iloc[0]
    assert row["frequency_hz"] == pytest.approx(row["order"] * row["rpm"] / 60, rel=1e-3)
    assert len(result.spans) == 3 * 2 and "transverse_1_hz" in result.spans


def test_sweep_takes_the_command_lines_range(data):
    scene = cd.Scene.from_file(data / "designation_16b.toml")
    result = cd.sweep(scene, "90:150:60", settle=0.1, window=0.7)
    assert list(result.cases["rpm"]) == [90.0, 150.0]
    with pytest.raises(ValueError, match="rpm"):
        cd.sweep(scene, "90:150")


def test_sweep_refuses_a_window_too_short_for_the_orders(data):
    scene = cd.Scene.from_file(data / "designation_16b.toml")
    with pytest.raises(ValueError) as e:
        cd.sweep(scene, [60], window=0.1)
    assert str(e.value).startswith("window 0.1: at 60 rpm the window turns the driver through 0.10 revolutions")


PLAN = {
    "set": {"solver.duration_s": 0.3},
    "responses": ["segments.0.mean_link_force_n", "static_tension_n"],
    "factors": [{"path": "chain.pretension_n", "levels": [800.0, 1200.0]}],
    "design": {"kind": "full_factorial"},
}


def test_study_from_a_dict_runs_and_resumes(data, tmp_path):
    scene = cd.Scene.from_file(data / "designation_16b.toml")
    out = tmp_path / "study"
    first = cd.study(PLAN, out, scene=scene, jobs=2)
    t = first.table
    assert list(t["case"]) == [0, 1]
    assert list(t["chain.pretension_n"]) == [800.0, 1200.0]
    # Each case's static tension is its pretension.
    assert t["static_tension_n"] == pytest.approx([800.0, 1200.0], rel=0.01)
    assert (out / "cases" / "1" / "summary.json").exists()
    assert (out / "results.csv").exists() and (out / "results.parquet").exists()
    # The same plan again: nothing left to run, the same table.
    again = cd.study(PLAN, out, scene=scene)
    assert list(again.table["static_tension_n"]) == list(t["static_tension_n"])
    assert list(again.table["case_wall_s"]) == list(t["case_wall_s"])


def test_study_from_a_plan_file(root, tmp_path):
    result = cd.study(root / "tests" / "data" / "study_small.toml", tmp_path / "s", jobs=2)
    df = result.to_pandas()
    assert len(df) == 4 and set(df["status"]) <= {"ok", "warned"}


def test_a_bad_plan_names_its_path(data, tmp_path):
    plan = dict(PLAN, factors=[{"path": "chain.colour", "levels": [1, 2]}])
    scene = cd.Scene.from_file(data / "designation_16b.toml")
    with pytest.raises(cd.StudyError, match="chain.colour"):
        cd.study(plan, tmp_path / "bad", scene=scene)


def test_rate_gives_the_chain_speed_of_the_smallest_sprocket():
    r = cd.rate(cd.Scene.l60mc())
    # The chain speed is N P n / 60 on any sprocket: 60 teeth x 0.0889 m at 120 rpm.
    assert r["chain_speed_m_s"] == pytest.approx(60 * 0.0889 * 120 / 60, rel=1e-9)
    assert r["smallest_teeth"] == 28
    with pytest.raises(ValueError, match="service factor"):
        cd.rate(cd.Scene.l60mc(), service_factor=0.0)


def test_record_writes_an_mcap_file(data, tmp_path):
    path = tmp_path / "run.mcap"
    cd.run(cd.Scene.from_file(data / "designation_16b.toml"), duration=0.05, record=path)
    data_bytes = path.read_bytes()
    # MCAP's magic at both ends: a complete, indexed file.
    assert data_bytes[:8] == b"\x89MCAP0\r\n" and data_bytes[-8:] == b"\x89MCAP0\r\n"
    with pytest.raises(ValueError, match="record_channels"):
        cd.run(cd.Scene.from_file(data / "designation_16b.toml"), duration=0.05,
               record=tmp_path / "x.mcap", record_channels="nope")


def test_a_run_resumed_from_its_checkpoint_is_the_run_that_never_stopped(data, tmp_path):
    scene = cd.Scene.from_file(data / "designation_16b.toml")
    settings = dict(duration=0.4, window=0.2)
    whole = cd.run(scene, **settings)
    ck = tmp_path / "run.ckpt"
    # Checkpoints every 0.25 s: one at 0.25 s (none at the end).
    cd.run(scene, checkpoint=ck, checkpoint_every=0.25, **settings)
    assert ck.exists()
    resumed = cd.run(scene, resume=ck, **settings)
    skip = {"wall_s", "ns_per_step", "setup_wall_s"}
    a = {k: v for k, v in whole.summary.items() if k not in skip}
    b = {k: v for k, v in resumed.summary.items() if k not in skip}
    assert json.dumps(a, sort_keys=True) == json.dumps(b, sort_keys=True)
    np.testing.assert_array_equal(resumed.series.t_s, whole.series.t_s)
    np.testing.assert_array_equal(resumed.series.segment_force_n, whole.series.segment_force_n)
    with pytest.raises(ValueError, match="same settings"):
        cd.run(scene, resume=ck, duration=0.4, window=0.1)
    with pytest.raises(ValueError, match="go together"):
        cd.run(scene, checkpoint=ck)


def test_checkpoints_cross_between_python_and_the_command_line(root, tmp_path):
    """A Python run's checkpoint resumed by `chaindrive run --resume`, and the
    command line's by `chaindrive.run(resume=)`: both summaries are the
    uninterrupted run's (but for the wall times)."""
    binary = root / "target" / "release" / "chaindrive"
    if not binary.exists():
        pytest.skip("no target/release/chaindrive (cargo build --release)")
    import subprocess

    scene = cd.Scene.l60mc()
    settings = dict(duration=0.3, window=0.1)
    skip = {"wall_s", "ns_per_step", "setup_wall_s"}
    whole = {k: v for k, v in cd.run(scene, **settings).summary.items() if k not in skip}
    options = ["--quiet", "--duration", "0.3", "--window", "0.1"]
    py_ck, cli_ck, cli_json = tmp_path / "py.ckpt", tmp_path / "cli.ckpt", tmp_path / "cli.json"
    cd.run(scene, checkpoint=py_ck, checkpoint_every=0.2, **settings)
    subprocess.run([binary, "run", *options, "--resume", py_ck, "--summary", cli_json],
                   check=True, capture_output=True)
    by_cli = {k: v for k, v in json.loads(cli_json.read_text()).items() if k not in skip}
    assert by_cli == whole
    subprocess.run([binary, "run", *options, "--checkpoint", cli_ck, "--checkpoint-every", "0.2"],
                   check=True, capture_output=True)
    resumed = cd.run(scene, resume=cli_ck, **settings)
    assert {k: v for k, v in resumed.summary.items() if k not in skip} == whole
    # A finished command-line run leaves its last checkpoint at its end (so
    # that it can be continued): nothing is left to run, and the series,
    # which the command line keeps in its file, has no row here.
    assert len(resumed.series.t_s) == 0
