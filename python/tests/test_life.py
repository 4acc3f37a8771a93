"""`chaindrive.life`: a duty cycle's points run as a study and combined by
hours. The combination is checked by Miner's rule done here, from the
points' own damages: the cycle's damage per hour is the sum over points of
time share times damage per hour, the life its inverse. The command line's
`chaindrive life --json` on the same points gives the same report."""

from __future__ import annotations

import json
import subprocess

import pytest

import chaindrive as cd

# The motorcycle's three operating points (tests/data/duty_moto_10b.toml):
# engine speed and rear-wheel braking torque, as fractions of the time.
POINTS = [
    {"name": "town", "fraction": 0.3,
     "set": {"sprockets.0.speed_rpm": 2500.0, "sprockets.1.load_torque_n_m": -60.0}},
    {"name": "cruise", "fraction": 0.65,
     "set": {"sprockets.0.speed_rpm": 3500.0, "sprockets.1.load_torque_n_m": -150.0}},
    {"name": "full throttle", "fraction": 0.05,
     "set": {"sprockets.0.speed_rpm": 4000.0, "sprockets.1.load_torque_n_m": -560.0}},
]
SHORT = dict(duration=0.4, window=0.15)


@pytest.fixture(scope="module")
def moto(data) -> cd.Scene:
    return cd.Scene.from_file(data / "moto_10b_15_44_560nm.toml")


@pytest.fixture(scope="module")
def cycle(moto, tmp_path_factory) -> tuple[cd.LifeResult, str]:
    out = tmp_path_factory.mktemp("life") / "moto"
    return cd.life(moto, out, duty=POINTS, jobs=2, **SHORT), str(out)


def test_a_duty_cycle_combines_its_points_by_miner(cycle):
    result, _ = cycle
    report = result.report
    assert report is not None and not result.interrupted
    points = report["points"]
    assert [p["name"] for p in points] == ["town", "cruise", "full throttle"]
    shares = [p["time_share"] for p in points]
    assert shares == pytest.approx([0.3, 0.65, 0.05], rel=1e-12)
    damage = [p["damage_per_hour"] for p in points]
    rate = sum(s * d for s, d in zip(shares, damage))
    assert rate > 0.0
    fatigue = next(limit for limit in report["limits"] if limit["check"] == "fatigue")
    assert fatigue["rate_per_hour"] == pytest.approx(rate, rel=1e-12)
    assert result.life_h == pytest.approx(1.0 / rate, rel=1e-12)
    largest = max(range(3), key=lambda k: shares[k] * damage[k])
    assert fatigue["dominated_by"] == points[largest]["name"]
    assert result.governed_by == "fatigue"
    # Each point's share of the damage, from its own numbers.
    for s, d, p in zip(shares, damage, points):
        assert p["damage_share"] == pytest.approx(s * d / rate, rel=1e-9)


def test_a_second_call_runs_nothing_and_gives_the_same_life(cycle, moto):
    result, out = cycle
    seen = []
    again = cd.life(moto, out, duty=POINTS, jobs=2, progress=lambda d, n: seen.append((d, n)),
                    **SHORT)
    assert again.report == result.report
    assert seen[-1] == (0, 0)


def test_the_command_line_gives_the_same_report(cycle, root, data, tmp_path):
    binary = root / "target" / "release" / "chaindrive"
    if not binary.exists():
        pytest.skip("no target/release/chaindrive (cargo build --release)")
    result, _ = cycle
    out = tmp_path / "cli"
    subprocess.run(
        [binary, "life", data / "moto_10b_15_44_560nm.toml", "--duty", data / "duty_moto_10b.toml",
         "--out", out, "--jobs", "2", "--duration", "0.4", "--window", "0.15", "--json"],
        check=True, capture_output=True,
    )
    by_cli = json.loads((out / "life.json").read_text())
    assert by_cli == result.report


def test_a_bad_point_raises_with_its_path(moto, tmp_path):
    bad = [{"hours": 10.0, "set": {"sprockets.0.speed_rpn": 2500.0}}]
    with pytest.raises(cd.StudyError, match=r"duty\[0\]"):
        cd.life(moto, tmp_path / "bad", duty=bad, **SHORT)
    with pytest.raises(cd.StudyError, match="no \\[\\[duty\\]\\] points"):
        cd.life(moto, tmp_path / "none", **SHORT)
    with pytest.raises(ValueError, match="duration"):
        cd.life(moto, tmp_path / "neg", duty=POINTS, duration=-1.0)


def test_the_points_come_as_a_dataframe(cycle):
    pd = pytest.importorskip("pandas")
    result, _ = cycle
    frame = result.to_pandas()
    assert isinstance(frame, pd.DataFrame)
    assert list(frame["name"]) == ["town", "cruise", "full throttle"]
