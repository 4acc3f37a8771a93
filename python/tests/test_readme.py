"""The README's three Python uses, run as written.

Each block between `# README: <use>` and `# README end` is the README's
code block of that use, line for line (after dedenting):
`test_the_readme_shows_these_blocks` fails when they drift apart. They run
in a scratch directory holding the scene file they read.
"""

from __future__ import annotations

import re
import shutil
import textwrap

import pytest

import chaindrive as cd


@pytest.fixture()
def scratch(tmp_path, monkeypatch, data):
    (tmp_path / "tests" / "data").mkdir(parents=True)
    shutil.copy(data / "designation_16b.toml", tmp_path / "tests" / "data")
    monkeypatch.chdir(tmp_path)
    return tmp_path


def test_one_run(scratch):
    # README: one run
    import chaindrive as cd

    scene = cd.Scene.l60mc().with_({"sprockets.0.speed_rpm": 90})
    result = cd.run(scene, duration=1.5)
    print(result.summary["segments"][0]["mean_link_force_n"])  # N, over the last 0.5 s
    df = result.to_pandas()  # index t_s; omega_1_rad_s, seg1_link_force_n, ...
    # README end
    assert result.summary["sprockets"][0]["mean_speed_rad_s"] == pytest.approx(90 * 2 * 3.141592653589793 / 60, rel=1e-6)
    assert "seg1_link_force_n" in df.columns


def test_a_sweep_into_pandas(scratch):
    # README: a sweep
    scene = cd.Scene.from_file("tests/data/designation_16b.toml")
    sweep = cd.sweep(scene, [60, 120, 180], settle=0.2, window=1.2)
    table = sweep.to_pandas(wide=True)  # one row per speed, one column per statistic
    print(table[["segment1.mean_link_force_n", "link_force_max_n"]])
    # README end
    assert list(table.index) == [60.0, 120.0, 180.0]


def test_a_study(scratch):
    # README: a study
    plan = {
        "set": {"solver.duration_s": 0.3},
        "responses": ["segments.0.mean_link_force_n"],
        "factors": [{"path": "chain.pretension_n", "levels": [800, 1200]}],
        "design": {"kind": "full_factorial"},
    }
    scene = cd.Scene.from_file("tests/data/designation_16b.toml")
    result = cd.study(plan, "my-study", scene=scene, jobs=2)  # the same call again resumes
    df = result.to_pandas()  # one row per case: factors, responses, status
    # README end
    assert list(df["chain.pretension_n"]) == [800, 1200]
    assert (scratch / "my-study" / "results.csv").exists()


def blocks_in(text: str, start: str, end: str):
    return {
        m.group(1): textwrap.dedent(m.group(2)).strip()
        for m in re.finditer(r"^[ \t]*" + start + r"(.*?)\n(.*?)\n[ \t]*" + end, text, re.S | re.M)
    }


def test_the_readme_shows_these_blocks(root):
    with open(__file__, encoding="utf-8") as f:
        here = blocks_in(f.read(), r"# README: ", r"# README end")
    readme = (root / "README.md").read_text(encoding="utf-8")
    section = readme[readme.index("## Python\n"):]
    section = section[: section.index("\n## ", 1)]
    shown = re.findall(r"```python\n(.*?)```", section, re.S)
    assert len(here) == 3 and len(shown) == 3
    for name, block in here.items():
        assert any(s.strip() == block for s in shown), f"README's {name!r} differs from the test:\n{block}"
