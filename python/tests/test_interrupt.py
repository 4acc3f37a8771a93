"""Ctrl-C, the GIL and progress: a run steps with the GIL released, looks
at Python's signals about every 0.1 s, and a SIGINT stops it with the run
so far kept on the exception."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import threading
import time

import pytest

import chaindrive as cd

# The child: the paper's drive for 100 s (a minute of wall time or more). It says
# when it starts; the test sends SIGINT a few seconds later, while the run
# steps (no progress callback: the run itself must look at the signals).
CHILD = r"""
import json, sys
import chaindrive as cd

scene = cd.Scene.l60mc()
print("starting", flush=True)
try:
    cd.run(scene, duration=100.0)
    print(json.dumps({"outcome": "finished"}))
except cd.Interrupted as e:
    r = e.result
    print(json.dumps({
        "outcome": "interrupted",
        "is_keyboard_interrupt": isinstance(e, KeyboardInterrupt),
        "interrupted": r.interrupted,
        "summary_interrupted": r.summary["interrupted"],
        "duration_s": r.summary["duration_s"],
        "samples": len(r.series),
        "last_t_s": float(r.series.t_s[-1]),
        "summary": r.summary,
    }))
"""


def _default_sigint() -> None:
    """In the child, Ctrl-C as a terminal gives it: a shell that starts the
    tests in the background without job control leaves SIGINT ignored, and
    an ignored signal stays ignored across exec (Python then installs no
    KeyboardInterrupt handler)."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


@pytest.mark.skipif(sys.platform == "win32", reason="SIGINT to a child process")
def test_ctrl_c_stops_the_run_and_keeps_it_on_the_exception(root):
    child = subprocess.Popen(
        [sys.executable, "-c", CHILD],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        preexec_fn=_default_sigint,
    )
    try:
        line = child.stdout.readline()
        assert line.strip() == "starting", child.stderr.read()
        # Past the layout and the static equilibrium (under a second).
        time.sleep(3.0)
        sent = time.monotonic()
        child.send_signal(signal.SIGINT)
        out, err = child.communicate(timeout=60)
        stopped_after_s = time.monotonic() - sent
    finally:
        child.kill()
    assert child.returncode == 0, err
    r = json.loads(out.strip().splitlines()[-1])
    assert r["outcome"] == "interrupted"
    assert r["is_keyboard_interrupt"] and r["interrupted"] and r["summary_interrupted"]
    # Stopped well before the end, at a sample: the series ends where the summary does.
    assert 0.0 < r["duration_s"] < 90.0
    assert r["samples"] == round(r["duration_s"] * 1000) + 1
    assert r["last_t_s"] == pytest.approx(r["duration_s"])
    # Within about a poll interval (0.1 s) and a sample of the signal.
    assert stopped_after_s < 10.0
    jsonschema = pytest.importorskip("jsonschema")
    schema = json.loads((root / "tests" / "data" / "run-summary.schema.json").read_text())
    jsonschema.validate(r["summary"], schema)


def test_the_gil_is_released_while_simulating(data):
    """Another Python thread counts while the run steps. Its pace is first
    measured while this thread sleeps (the GIL free); during the run it must
    keep a quarter of that pace. With the GIL held by the run it would count
    only until the run took the GIL (a switch interval, 5 ms)."""
    scene = cd.Scene.from_file(data / "designation_16b.toml")
    count = [0]
    done = threading.Event()

    def counter():
        while not done.is_set():
            count[0] += 1

    thread = threading.Thread(target=counter)
    thread.start()
    try:
        before = count[0]
        time.sleep(0.3)
        pace = (count[0] - before) / 0.3
        before = count[0]
        started = time.perf_counter()
        cd.run(scene, duration=5.0, series=False)
        elapsed = time.perf_counter() - started
        during = count[0] - before
    finally:
        done.set()
        thread.join()
    assert elapsed > 0.2
    assert during > 0.25 * pace * elapsed, (during, pace, elapsed)


def test_the_progress_callback_sees_simulated_time(data):
    seen = []
    scene = cd.Scene.from_file(data / "designation_16b.toml")
    cd.run(scene, duration=0.5, progress=lambda t, total: seen.append((t, total)))
    assert seen and all(total == pytest.approx(0.5) for _, total in seen)
    times = [t for t, _ in seen]
    assert times == sorted(times) and times[-1] == pytest.approx(0.5)


def test_an_exception_in_the_callback_stops_the_run_and_propagates(data):
    scene = cd.Scene.from_file(data / "designation_16b.toml")

    def fail(t, total):
        raise RuntimeError("stop here")

    started = time.perf_counter()
    with pytest.raises(RuntimeError, match="stop here"):
        cd.run(scene, duration=30.0, progress=fail)
    assert time.perf_counter() - started < 10.0


def test_progress_true_draws_a_bar(data, capsys):
    scene = cd.Scene.from_file(data / "designation_16b.toml")
    cd.run(scene, duration=0.3, progress=True)
    err = capsys.readouterr().err
    assert "0.3" in err


# A sweep and a study of the paper's drive long enough to be stopped: each
# case runs 10 s simulated or more (seconds of wall time each, far more than
# the two seconds before the SIGINT), on one thread.
SWEEP_CHILD = r"""
import json
import chaindrive as cd

print("starting", flush=True)
try:
    cd.sweep(cd.Scene.l60mc(), [60, 90, 120, 150], settle=0.5, window=10.0, jobs=1)
    print(json.dumps({"outcome": "finished"}))
except cd.Interrupted as e:
    print(json.dumps({"outcome": "interrupted", "speeds": len(e.result.cases),
                      "flag": e.result.interrupted}))
"""

STUDY_CHILD = r"""
import json, sys
import chaindrive as cd

plan = {"set": {"solver.duration_s": 10.0},
        "factors": [{"path": "chain.pretension_n", "levels": [18000, 21000, 24000]}],
        "design": {"kind": "full_factorial"}}
print("starting", flush=True)
try:
    cd.study(plan, sys.argv[1], jobs=1)
    print(json.dumps({"outcome": "finished"}))
except cd.Interrupted as e:
    print(json.dumps({"outcome": "interrupted", "status": list(e.result.table["status"])}))
"""


def interrupt_child(script: str, *args: str) -> dict:
    child = subprocess.Popen([sys.executable, "-c", script, *args],
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                             preexec_fn=_default_sigint)
    try:
        assert child.stdout.readline().strip() == "starting", child.stderr.read()
        time.sleep(2.0)
        child.send_signal(signal.SIGINT)
        out, err = child.communicate(timeout=120)
    finally:
        child.kill()
    assert child.returncode == 0, err
    return json.loads(out.strip().splitlines()[-1])


@pytest.mark.skipif(sys.platform == "win32", reason="SIGINT to a child process")
def test_ctrl_c_stops_a_sweep_keeping_the_finished_speeds():
    r = interrupt_child(SWEEP_CHILD)
    assert r["outcome"] == "interrupted" and r["flag"]
    assert r["speeds"] < 4


@pytest.mark.skipif(sys.platform == "win32", reason="SIGINT to a child process")
def test_ctrl_c_stops_a_study_that_then_resumes(tmp_path):
    r = interrupt_child(STUDY_CHILD, str(tmp_path / "study"))
    assert r["outcome"] == "interrupted"
    # The case that was running is not written: it runs again next time.
    assert "missing" in r["status"] and len(r["status"]) == 3
