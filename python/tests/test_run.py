"""Runs from Python, checked against values that do not come from the code
under test: a sprocket's moment balance, the axially moving string, the
public summary schema."""

from __future__ import annotations

import json
import math
import warnings

import numpy as np
import pytest

import chaindrive as cd


def test_tension_difference_is_the_load_torque_over_the_pitch_radius(data):
    """Two sprockets (19T driver, 38T driven, ISO 606 16B-1, P = 25.4 mm),
    no gravity, a load torque M = -50 N m on the driven sprocket at 100 rpm.

    Over a steady window the driven sprocket does not accelerate on
    average, so the chain's mean moment on it is -M; the chain pulls it by
    its two strands with lever arms between the pitch polygon's R cos(pi/N)
    and R, R = P / (2 sin(pi/N)), so the strands' mean link forces differ
    by |M| / R within (1 - cos(pi/38)) / 2 = 0.09 % (the centrifugal m v^2
    is the same in both strands and cancels). Tolerance 1 % of |M| / R.
    """
    load_n_m, pitch_m, teeth = -50.0, 0.0254, 38
    scene = cd.Scene.from_file(data / "designation_16b.toml").with_(
        {"sprockets.1.load_torque_n_m": load_n_m, "sprockets.0.ramp_s": 0.2}
    )
    result = cd.run(scene, duration=1.5, window=1.0)
    s = result.summary
    radius_m = pitch_m / (2.0 * math.sin(math.pi / teeth))
    expected_n = abs(load_n_m) / radius_m
    tight, slack = sorted(seg["mean_link_force_n"] for seg in s["segments"])[::-1]
    assert tight - slack == pytest.approx(expected_n, rel=0.01)
    # The moment balance itself: the chain's mean moment on the driven
    # sprocket carries the load; the driver's is the reaction at the
    # teeth ratio 19/38.
    assert s["sprockets"][1]["mean_torque_n_m"] == pytest.approx(-load_n_m, rel=0.01)
    assert s["sprockets"][0]["mean_torque_n_m"] == pytest.approx(load_n_m * 19 / 38, rel=0.01)
    # The series says the same: its window means agree with the summary's.
    window = result.series.t_s >= s["window_s"][0]
    seg_means = np.nanmean(result.series.segment_force_n[window], axis=0)
    assert abs(seg_means[0] - seg_means[1]) == pytest.approx(expected_n, rel=0.02)


def test_a_free_strand_vibrates_at_the_moving_strings_frequency(paper_run):
    """Segment 4 of the paper's drive (30T to 60T): the main peak in 1-50 Hz
    of its middle's transverse displacement, from a Hann-windowed FFT of
    the series (1.5 s to the end: after the ramp), against the axially
    moving string f1 = c / (2 L) (1 - v^2 / c^2), c^2 = T / mu, with T the
    strand's mean link force over the same samples, L its length, mu = m_r
    / P = 3.01 kg / 0.0889 m and v = |omega_1| R_1 the chain speed on the
    60T driver (R_1 = P / (2 sin(pi/60))). Tolerance 3 % (the 2.5 s of
    samples resolve 0.4 Hz before interpolation by zero padding); the
    string at rest, c / (2 L), lies 16 % higher and is excluded.
    """
    series, summary = paper_run.series, paper_run.summary
    pitch_m, roller_kg = 0.0889, 3.01
    after = series.t_s >= 1.5
    x = series.transverse_m[after, 3]
    x = (x - x.mean()) * np.hanning(len(x))
    n_fft = 1 << 16
    freq = np.fft.rfftfreq(n_fft, 1.0 / series.rate_hz)
    amp = np.abs(np.fft.rfft(x, n_fft))
    band = (freq >= 1.0) & (freq <= 50.0)
    peak_hz = freq[band][np.argmax(amp[band])]
    tension_n = np.nanmean(series.segment_force_n[after, 3])
    length_m = summary["strands"][3]["length_m"]
    mu = roller_kg / pitch_m
    v = abs(series.omega_rad_s[after, 0].mean()) * pitch_m / (2.0 * math.sin(math.pi / 60))
    c = math.sqrt(tension_n / mu)
    moving_hz = c / (2.0 * length_m) * (1.0 - v * v / (c * c))
    at_rest_hz = c / (2.0 * length_m)
    assert peak_hz == pytest.approx(moving_hz, rel=0.03)
    assert abs(peak_hz - at_rest_hz) > 0.10 * at_rest_hz


def test_the_summary_validates_against_the_public_schema(paper_run, root):
    jsonschema = pytest.importorskip("jsonschema")
    schema = json.loads((root / "tests" / "data" / "run-summary.schema.json").read_text())
    jsonschema.validate(paper_run.summary, schema)
    # Plain data all the way down: it is JSON as it is.
    assert json.loads(json.dumps(paper_run.summary)) == paper_run.summary
    assert isinstance(paper_run.summary["warnings"], list)


def test_the_series_are_numpy_arrays_handed_over_without_a_copy(paper_run):
    s, summary = paper_run.series, paper_run.summary
    n = len(s.t_s)
    assert n == round(summary["duration_s"] * 1000) + 1
    assert s.omega_rad_s.shape == (n, 4) and s.chain_torque_n_m.shape == (n, 4)
    assert s.segment_force_n.shape == (n, 4) and s.transverse_m.shape == (n, 4)
    for a in (s.t_s, s.omega_rad_s, s.segment_force_n):
        assert a.dtype == np.float64 and a.flags["C_CONTIGUOUS"]
        # The array's memory is the Rust vector the run filled, kept alive
        # by its container: no copy was made to hand it over.
        assert type(a.base).__name__ == "PySliceContainer"
    assert np.all(np.diff(s.t_s) > 0)
    # Driver at 120 rpm after the ramp: omega_1 = 4 pi rad/s.
    assert s.omega_rad_s[-1, 0] == pytest.approx(4 * math.pi, rel=1e-9)


def test_to_pandas_names_columns_as_the_csv_does(paper_run):
    pd = pytest.importorskip("pandas")
    df = paper_run.to_pandas()
    assert df.index.name == "t_s" and len(df) == len(paper_run.series)
    for name in ("omega_1_rad_s", "chain_torque_4_n_m", "seg1_link_force_n", "seg4_transverse_m"):
        assert name in df.columns
    assert df["seg2_link_force_n"].to_numpy() == pytest.approx(paper_run.series.segment_force_n[:, 1], nan_ok=True)


def test_run_settings_are_the_command_lines(data):
    scene = cd.Scene.from_file(data / "designation_16b.toml")
    r = cd.run(scene, duration=0.2, rate=500.0, integrator="rk4", profile="real", series=False)
    s = r.summary
    assert (s["integrator"], s["profile"], s["duration_s"]) == ("rk4", "real", pytest.approx(0.2))
    assert len(r.series) == 0 and s["window_s"][1] == pytest.approx(0.2)


def test_dt_speed_takes_a_larger_step_than_auto(data):
    # "speed" drops the impact cap that "auto" keeps, so its step is at least
    # as large, and with the one-evaluation scheme it runs without a
    # stability warning.
    scene = cd.Scene.from_file(data / "designation_16b.toml")
    fast = cd.run(scene, duration=0.05, dt="speed", integrator="verlet_implicit_damping", series=False)
    auto = cd.run(scene, duration=0.05, dt="auto", integrator="verlet_implicit_damping", series=False)
    assert fast.summary["dt_s"] >= auto.summary["dt_s"] > 0
    assert not any("stability" in w for w in fast.summary["warnings"])
    with pytest.raises(ValueError, match="speed"):
        cd.run(scene, dt="fastest")


def test_a_bad_setting_raises_with_its_field_path(data):
    scene = cd.Scene.from_file(data / "designation_16b.toml")
    with pytest.raises(cd.SceneError) as e:
        cd.run(scene, integrator="leapfrog")
    assert e.value.path == "solver.integrator" and "velocity_verlet" in str(e.value)
    with pytest.raises(cd.SceneError) as e:
        cd.run(scene, dt=-1.0)
    assert e.value.path == "solver.dt_s"
    with pytest.raises(ValueError, match="window"):
        cd.run(scene, duration=0.1, window=1.0)
    with pytest.raises(ValueError, match="rate"):
        cd.run(scene, duration=0.1, rate=-5.0)


def test_a_run_that_cannot_start_raises_sim_error(data):
    # A chain far too short for its path: no layout.
    scene = cd.Scene.from_file(data / "designation_16b.toml").with_({"chain.rollers": 60})
    with pytest.raises(cd.SimError, match="cannot start the simulation"):
        cd.run(scene, duration=0.1)


def test_suspect_results_warn(data):
    # A 50 ms run (and window) holds the 0.1 s ramp: the summary says so, and so does Python.
    scene = cd.Scene.from_file(data / "designation_16b.toml")
    with pytest.warns(cd.RunWarning, match="ramp"):
        r = cd.run(scene, duration=0.05, window=0.05)
    assert any("ramp" in w for w in r.warnings)
