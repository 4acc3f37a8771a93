"""chaindrive: dynamic simulation of roller-chain drives, from Python.

The same Rust library as the ``chaindrive`` command line (after S. L.
Pedersen, *Model of contact between rollers and sprockets in chain-drive
systems*, Arch. Appl. Mech. 74 (2005) 489-508), as a native module: scenes
are validated by the library, runs step in Rust with the GIL released, the
summary comes back as plain Python data and the sampled series as NumPy
arrays. This package adds no physics; its names are the Rust ones.

Quick start::

    import chaindrive as cd

    scene = cd.Scene.l60mc()                      # the paper's drive
    result = cd.run(scene, duration=2.0)          # the summary and the series
    result.summary["segments"][0]["mean_link_force_n"]
    result.series.segment_force_n[:, 0]           # NumPy, one row per sample
    df = result.to_pandas()                       # with pandas installed

- Scenes: ``Scene.from_file``, ``Scene.from_toml``, ``Scene.l60mc()``,
  ``scene.with_({"sprockets.0.speed_rpm": 600})`` (the dotted paths of
  study plans), ``scene.with_designation("ANSI 80")``, ``scene.to_toml()``.
  A bad scene raises ``SceneError``: the command line's message, and the
  field's path in ``.path``.
- Runs: ``run`` (summary, series, recording to MCAP, checkpoints, Ctrl-C).
- The rest of the tool: ``check``, ``sweep``, ``study``, ``life`` (fatigue
  and wear over a duty cycle), ``rate``, ``chains``.

Ctrl-C during ``run``, ``sweep``, ``study`` or ``life`` stops the work at its next
sample (or case) and raises ``Interrupted``, a ``KeyboardInterrupt`` whose
``.result`` holds what was done: the run so far (its summary marked
``interrupted``), the finished speeds, the finished cases.

Co-simulation (a drive inside your own rapier world, stepped at your
frame rate, ``chaindrive::cosim``) stays in Rust: it needs your rapier
bodies and colliders, which Python does not have. See the crate's
documentation, "Using chaindrive in your rapier scene".
"""

from __future__ import annotations

import os
import sys
import warnings as _warnings
from typing import Any, Callable, Dict, Iterable, List, Mapping, Optional, Union

import numpy as np

from ._chaindrive import (
    Scene,
    SceneError,
    SimError,
    StudyError,
    __version__,
    chains,
    check,
    rate,
)
from ._chaindrive import life as _life
from ._chaindrive import run as _run
from ._chaindrive import study as _study
from ._chaindrive import sweep as _sweep

__all__ = [
    "Interrupted",
    "LifeResult",
    "RunResult",
    "RunWarning",
    "Scene",
    "SceneError",
    "Series",
    "SimError",
    "StudyError",
    "StudyResult",
    "SweepResult",
    "Table",
    "chains",
    "check",
    "life",
    "rate",
    "run",
    "study",
    "sweep",
    "__version__",
]

PathLike = Union[str, "os.PathLike[str]"]
Progress = Union[bool, Callable[[float, float], Any], None]


class Interrupted(KeyboardInterrupt):
    """Ctrl-C stopped a run, a sweep or a study.

    A ``KeyboardInterrupt``, so code that does not care stops as usual;
    ``.result`` holds what was done before the stop: a ``RunResult`` of the
    run so far (``result.interrupted`` is true, its summary covers what ran),
    a ``SweepResult`` of the finished speeds, a ``StudyResult`` of the
    finished cases (the study resumes from its directory).
    """

    def __init__(self, message: str, result: Any) -> None:
        super().__init__(message)
        self.result = result


class RunWarning(UserWarning):
    """A run finished, but the summary says a result is suspect (one of its
    ``warnings``: deep penetration, a power balance off by more than 1 %, a
    window that holds a ramp, a sample rate that aliases the tooth
    frequency...)."""


def _frame(columns: Mapping[str, Any], index: Optional[str] = None):
    try:
        import pandas as pd  # type: ignore[import-untyped]
    except ImportError as e:  # pragma: no cover - depends on the environment
        raise ImportError(
            "to_pandas() needs pandas: pip install pandas"
        ) from e
    df = pd.DataFrame(dict(columns))
    return df.set_index(index) if index is not None else df


class Series:
    """The sampled signals of a run, one row per sample (at ``rate_hz``).

    Each quantity is a NumPy array that owns the memory the run filled (no
    copy was made to hand it over):

    - ``t_s``: time, s, shape ``(n,)``;
    - ``omega_rad_s``: each sprocket's angular speed, rad/s (CCW positive),
      shape ``(n, sprockets)``;
    - ``chain_torque_n_m``: the moment of the chain on each sprocket, N m,
      shape ``(n, sprockets)``;
    - ``segment_force_n``: each segment's link force (the mean over the
      links of its free strand), N, shape ``(n, segments)``; NaN at a sample
      where the strand has no free link (the CSV's empty field);
    - ``transverse_m``: the transverse displacement of each segment's
      middle, m, shape ``(n, segments)``.

    Column ``k`` is sprocket or segment ``k + 1`` of the summary.
    """

    def __init__(self, arrays: Mapping[str, np.ndarray], rate_hz: float) -> None:
        self.t_s: np.ndarray = arrays["t_s"]
        self.omega_rad_s: np.ndarray = arrays["omega_rad_s"]
        self.chain_torque_n_m: np.ndarray = arrays["chain_torque_n_m"]
        self.segment_force_n: np.ndarray = arrays["segment_force_n"]
        self.transverse_m: np.ndarray = arrays["transverse_m"]
        self.rate_hz = rate_hz

    def __len__(self) -> int:
        return len(self.t_s)

    def columns(self) -> Dict[str, np.ndarray]:
        """The series as named 1-D columns, named as ``chaindrive run
        --series`` names them (``omega_1_rad_s``, ``seg1_link_force_n``,
        ``seg1_transverse_m``) plus ``chain_torque_1_n_m``; views, not copies."""
        out: Dict[str, np.ndarray] = {"t_s": self.t_s}
        for i in range(self.omega_rad_s.shape[1]):
            out[f"omega_{i + 1}_rad_s"] = self.omega_rad_s[:, i]
        for i in range(self.chain_torque_n_m.shape[1]):
            out[f"chain_torque_{i + 1}_n_m"] = self.chain_torque_n_m[:, i]
        for k in range(self.segment_force_n.shape[1]):
            out[f"seg{k + 1}_link_force_n"] = self.segment_force_n[:, k]
        for k in range(self.transverse_m.shape[1]):
            out[f"seg{k + 1}_transverse_m"] = self.transverse_m[:, k]
        return out

    def to_pandas(self):
        """The series as a pandas DataFrame indexed by ``t_s`` (needs pandas)."""
        return _frame(self.columns(), index="t_s")

    def __repr__(self) -> str:
        return (
            f"Series({len(self)} samples at {self.rate_hz:g} Hz, "
            f"{self.omega_rad_s.shape[1]} sprockets, {self.segment_force_n.shape[1]} segments)"
        )


class RunResult:
    """What ``run`` returns.

    - ``summary``: the run summary as plain Python data (dicts, lists,
      floats; the public schema of ``chaindrive run --summary``,
      ``tests/data/run-summary.schema.json``); ``summary["warnings"]`` lists
      what is suspect, one sentence each (also issued as ``RunWarning``).
    - ``series``: the sampled signals (``Series``); empty with
      ``series=False``.
    - ``interrupted``: whether Ctrl-C stopped the run before its end.
    """

    def __init__(self, summary: Dict[str, Any], series: Series, interrupted: bool) -> None:
        self.summary = summary
        self.series = series
        self.interrupted = interrupted

    @property
    def warnings(self) -> List[str]:
        """The summary's warnings."""
        return list(self.summary.get("warnings", []))

    def to_pandas(self):
        """The series as a pandas DataFrame indexed by ``t_s`` (needs pandas)."""
        return self.series.to_pandas()

    def __repr__(self) -> str:
        s = self.summary
        return (
            f"RunResult({s.get('scene')!r}, {s.get('duration_s')} s simulated"
            f"{' (interrupted)' if self.interrupted else ''}, {len(self.series)} samples, "
            f"{len(self.warnings)} warnings)"
        )


class Table:
    """A table of named columns of equal length: numbers as NumPy arrays,
    text (and booleans with gaps) as lists, ``None``/NaN where a value is
    missing. ``table["rpm"]``, ``table.columns``, ``len(table)``,
    ``table.to_pandas()``."""

    def __init__(self, columns: Mapping[str, Any]) -> None:
        self._columns = dict(columns)

    @property
    def columns(self) -> List[str]:
        """The column names, in order."""
        return list(self._columns)

    def __getitem__(self, name: str) -> Any:
        return self._columns[name]

    def __contains__(self, name: object) -> bool:
        return name in self._columns

    def __len__(self) -> int:
        for v in self._columns.values():
            return len(v)
        return 0

    def to_dict(self) -> Dict[str, Any]:
        """The columns as a dict (the arrays themselves, not copies)."""
        return dict(self._columns)

    def to_pandas(self):
        """The table as a pandas DataFrame (needs pandas)."""
        return _frame(self._columns)

    def __repr__(self) -> str:
        return f"Table({len(self)} rows: {', '.join(self.columns)})"


class SweepResult:
    """What ``sweep`` returns: the long tables ``chaindrive sweep`` writes
    as CSV, and each finished speed's run summary.

    - ``scalars``: ``rpm, statistic, value`` (``sweep.csv``): every scalar
      of each run's summary (``segment1.mean_link_force_n``,
      ``sprocket2.speed_rms_rad_s``, ...), ``failed`` 1 for a speed whose
      run failed, ``warned``, ``warning_count``, ``max_contact_force_n``,
      ``rev_per_s``;
    - ``cases``: ``rpm, status, stationary, warning_count, warnings, error``;
    - ``orders``: ``rpm, signal, order, frequency_hz, amplitude, phase_rad``
      (the order spectra of the window);
    - ``spans``: ``rpm, segment, tension_n, transverse_1_hz`` ...,
      ``axial_hz`` (each span's predicted natural frequencies);
    - ``summaries``: ``{rpm: summary}`` of the finished speeds;
    - ``interrupted``: whether Ctrl-C stopped it (the finished speeds stay).
    """

    def __init__(self, raw: Mapping[str, Any]) -> None:
        self.scalars = Table(raw["scalars"])
        self.cases = Table(raw["cases"])
        self.orders = Table(raw["orders"])
        self.spans = Table(raw["spans"])
        self.summaries: Dict[float, Dict[str, Any]] = {rpm: s for rpm, s in raw["summaries"]}
        self.interrupted: bool = raw["interrupted"]

    def to_pandas(self, wide: bool = False):
        """``scalars`` as a DataFrame: long (``rpm, statistic, value``) or,
        with ``wide=True``, one row per speed and one column per statistic."""
        df = self.scalars.to_pandas()
        if wide:
            return df.pivot(index="rpm", columns="statistic", values="value")
        return df

    def __repr__(self) -> str:
        return f"SweepResult({len(self.cases)} speeds{' (interrupted)' if self.interrupted else ''})"


class StudyResult:
    """What ``study`` returns: ``table`` (one row per case: ``case``, the
    factors as the plan names them, the responses, ``status`` (``ok``,
    ``warned``, ``failed``, ``missing``), the flags, ``case_wall_s``,
    ``error``; the same columns as ``results.csv``), ``dir`` and
    ``interrupted``."""

    def __init__(self, raw: Mapping[str, Any], directory: str) -> None:
        self.table = Table(raw["table"])
        self.interrupted: bool = raw["interrupted"]
        self.dir = directory

    def to_pandas(self):
        """The results table as a DataFrame (needs pandas)."""
        return self.table.to_pandas()

    def __repr__(self) -> str:
        return f"StudyResult({len(self.table)} cases in {self.dir!r}{' (interrupted)' if self.interrupted else ''})"


class LifeResult:
    """What ``life`` returns: ``report`` (the dict ``chaindrive life --json``
    prints: ``block_hours``, ``points`` (one dict per point: ``hours``,
    ``time_share``, ``status``, ``damage_per_hour``, ``fatigue_life_h``,
    ``damage_share``, ``elongation_pct_per_1000h``, ``wear_life_h``, ...),
    ``limits`` (one per check: ``check``, ``rate_per_hour``, ``life_h``,
    ``dominated_by``), ``life_h``, ``governed_by``, ``notes``), ``life_h``
    and ``governed_by`` from it, ``dir`` and ``interrupted``. A life is a
    number of hours or the string ``"infinite"``."""

    def __init__(self, raw: Mapping[str, Any], directory: str) -> None:
        self.report: Optional[Dict[str, Any]] = raw["life"]
        self.interrupted: bool = raw["interrupted"]
        self.dir = directory
        report = self.report or {}
        self.life_h: Union[float, str, None] = report.get("life_h")
        self.governed_by: Optional[str] = report.get("governed_by")

    def to_pandas(self):
        """The points as a DataFrame, one row per point (needs pandas)."""
        import pandas as pd  # type: ignore[import-untyped]

        return pd.DataFrame((self.report or {}).get("points", []))

    def __repr__(self) -> str:
        if self.report is None:
            return f"LifeResult(interrupted, in {self.dir!r})"
        return f"LifeResult(life_h={self.life_h!r}, governed by {self.governed_by!r}, in {self.dir!r})"


class _Bar:
    """Progress shown for ``progress=True``: a tqdm bar where tqdm is
    installed, else one line on stderr redrawn in place."""

    def __init__(self, unit: str) -> None:
        self.unit = unit
        self.bar: Any = None
        self.tqdm: Any
        try:
            from tqdm.auto import tqdm  # type: ignore[import-untyped]

            self.tqdm = tqdm
        except ImportError:
            self.tqdm = None

    def __call__(self, done: float, total: float) -> None:
        if self.tqdm is not None:
            if self.bar is None:
                self.bar = self.tqdm(total=total, unit=self.unit)
            self.bar.n = done
            self.bar.refresh()
        else:
            width = 30
            filled = int(width * done / total) if total > 0 else width
            sys.stderr.write(f"\r[{'#' * filled}{'.' * (width - filled)}] {done:.4g}/{total:.4g} {self.unit}")
            sys.stderr.flush()

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()
        elif self.tqdm is None:
            sys.stderr.write("\n")


def _progress(progress: Progress, unit: str):
    if progress is True:
        return _Bar(unit)
    if progress is None or progress is False:
        return None
    if not callable(progress):
        raise TypeError("progress: True, or a callable f(done, total)")
    return progress


def _finish(callback, done: float, total: float) -> None:
    if callback is None:
        return
    callback(done, total)
    if isinstance(callback, _Bar):
        callback.close()


def _concluded(result, callback, done: float, interrupted: str):
    """A batch's ``result``; ``Interrupted`` carrying it (with message
    ``interrupted``) if it was stopped. The progress bar is closed either
    way, and told ``done`` of ``done`` when the batch finished."""
    if result.interrupted:
        if isinstance(callback, _Bar):
            callback.close()
        raise Interrupted(interrupted, result)
    _finish(callback, done, done)
    return result


def run(
    scene: Scene,
    *,
    duration: Optional[float] = None,
    window: Optional[float] = None,
    rate: float = 1000.0,
    integrator: Optional[str] = None,
    profile: Optional[str] = None,
    dt: Union[float, str, None] = None,
    stepping: Optional[str] = None,
    series: bool = True,
    record: Optional[PathLike] = None,
    record_channels: str = "all",
    checkpoint: Optional[PathLike] = None,
    checkpoint_every: Optional[float] = None,
    resume: Optional[PathLike] = None,
    progress: Progress = None,
) -> RunResult:
    """Simulate ``scene`` as ``chaindrive run`` does and return its summary
    and sampled series.

    The run builds the layout, brings the drive to static equilibrium, then
    steps to ``duration``; the GIL is released meanwhile (other Python
    threads run).

    Args:
        scene: the drive (``Scene``).
        duration: simulated time, s (default: the scene's ``solver.duration_s``).
        window: the statistics window, the last ``window`` seconds (default:
            the last 1 s after the scene's ramps). Longer than the run, or
            not > 0, is a ``ValueError``.
        rate: the sample rate of the series and the sampled statistics, Hz;
            the step must divide its period (``ValueError`` otherwise).
        integrator: ``"symplectic_euler"``, ``"velocity_verlet"``,
            ``"rk4"``, ... (default: the scene's).
        profile: every sprocket's tooth profile, ``"circular"`` or ``"real"``.
        dt: the chain's step, s, ``"auto"``, or ``"speed"`` (the largest
            step the integrator's stability allows; default: the scene's).
        stepping: ``"substepped"`` or ``"rapier"``.
        series: keep every sample (``False``: only the summary's window is
            kept, and ``result.series`` is empty; memory stays flat).
        record: write an MCAP recording here (opens in Foxglove and Rerun).
        record_channels: channels to record, comma-separated, or ``"all"``.
        checkpoint, checkpoint_every: write the run's complete state to
            ``checkpoint`` every ``checkpoint_every`` simulated seconds and
            when it is interrupted (always a whole file).
        resume: continue from this checkpoint; give the same scene and
            settings. The result is that of the run that never stopped,
            series included. ``chaindrive run --resume`` takes up these
            checkpoints too (and this the command line's, its series then
            starting at the checkpoint).
        progress: ``True`` for a progress bar (tqdm if installed), or a
            callable ``f(t_s, duration_s)`` called about every 0.1 s of wall
            time from the calling thread; an exception it raises stops the
            run and propagates.

    Returns:
        ``RunResult``: ``summary`` (dict), ``series`` (NumPy arrays),
        ``interrupted``.

    Raises:
        Interrupted: Ctrl-C (SIGINT) during the run; ``e.result`` is the
            ``RunResult`` of the run so far. A subclass of
            ``KeyboardInterrupt``.
        SceneError: a setting makes the scene invalid (an unknown
            integrator name, a bad ``dt``), with the field's path.
        SimError: no layout or static equilibrium, or the run blew up.
        ValueError: a bad window, rate or checkpoint setting.
        OSError: a recording or checkpoint file cannot be written or read.
    """
    callback = _progress(progress, "s")
    summary, arrays, interrupted = _run(
        scene,
        duration=duration,
        window=window,
        rate=rate,
        integrator=integrator,
        profile=profile,
        dt=dt,
        stepping=stepping,
        series=series,
        record=None if record is None else os.fspath(record),
        record_channels=record_channels,
        checkpoint=None if checkpoint is None else os.fspath(checkpoint),
        checkpoint_every=checkpoint_every,
        resume=None if resume is None else os.fspath(resume),
        progress=callback,
    )
    result = RunResult(summary, Series(arrays, rate), interrupted)
    if interrupted:
        if isinstance(callback, _Bar):
            callback.close()
        raise Interrupted("the run was interrupted; e.result holds it so far", result)
    _finish(callback, summary["duration_s"], summary["duration_s"])
    for w in result.warnings:
        _warnings.warn(w, RunWarning, stacklevel=2)
    return result


def sweep(
    scene: Scene,
    rpm: Union[Iterable[float], str],
    *,
    settle: float = 1.0,
    window: float = 1.0,
    jobs: Optional[int] = None,
    max_order: Optional[float] = None,
    order_step: float = 1.0,
    progress: Progress = None,
) -> SweepResult:
    """Sweep the driver's speed as ``chaindrive sweep --rpm`` does: one
    steady run per speed, in parallel, each measured by its run summary
    and the order spectra of its window.

    Each speed runs the scene with the driver at that ``rpm`` (its sense of
    rotation kept) for its ramp + ``settle`` + ``window`` seconds; the
    statistics and order spectra cover the last ``window``. A speed whose
    run blows up is a failed case; the others go on.

    Args:
        scene: the drive; it needs a driver with a ``speed_rpm``.
        rpm: the driver speeds, rpm: a sequence (``numpy.arange(60, 181,
            30)``) or the command line's ``"FROM:TO:STEP"`` (``"60:180:30"``).
        settle: time after the driver's ramp before the window, s.
        window: statistics and order window, s; it must hold whole driver
            revolutions at the slowest speed.
        jobs: runs at once (default: the machine's cores).
        max_order: largest order analysed (default: twice the largest
            tooth count); ``order_step``: step between orders (1, 0.5, ...).
        progress: ``True`` for a bar, or ``f(speeds_done, speeds)``.

    Returns:
        ``SweepResult`` with the long tables (``scalars``, ``cases``,
        ``orders``, ``spans``) and ``to_pandas()``.

    Raises:
        Interrupted: Ctrl-C; ``e.result`` holds the finished speeds.
        ValueError: a bad speed list, window or order setting, a scene
            without a driver, or a speed at which the scene is invalid.
    """
    callback = _progress(progress, "speeds")
    speeds: Union[List[float], str] = rpm if isinstance(rpm, str) else [float(r) for r in rpm]
    raw = _sweep(
        scene,
        speeds,
        settle=settle,
        window=window,
        jobs=jobs,
        max_order=max_order,
        order_step=order_step,
        progress=callback,
    )
    result = SweepResult(raw)
    return _concluded(result, callback, len(result.cases),
                      "the sweep was interrupted; e.result holds the finished speeds")


def study(
    plan: Union[PathLike, Mapping[str, Any]],
    dir: PathLike,
    *,
    scene: Union[Scene, PathLike, None] = None,
    jobs: int = 1,
    retry_failed: bool = False,
    progress: Progress = None,
) -> StudyResult:
    """Run a design study here, as ``chaindrive study PLAN --out DIR`` does,
    and return its results table.

    The plan is a plan file (TOML; its ``scene`` is read relative to it) or
    the same as a dict::

        {"set": {"solver.duration_s": 1.5},
         "responses": ["segments.0.mean_link_force_n"],
         "factors": [{"path": "chain.pretension_n", "levels": [15e3, 21e3]},
                     {"path": "sprockets.0.speed_rpm",
                      "range": {"from": 60, "to": 120, "steps": 2}}],
         "design": {"kind": "full_factorial"}}

    with the base scene given as ``scene`` (a ``Scene`` or a file), or by
    the dict's ``"scene"`` path (relative to the working directory); the
    paper's drive if neither. Every case writes its files into ``dir``
    (``cases/<k>/``) as it finishes: calling ``study`` again with the same
    plan and ``dir`` runs only the cases not finished (an interrupted study
    resumes; with ``checkpoint_every_s`` in the plan a stopped case resumes
    from its checkpoint). ``dir`` also gets ``results.csv`` and
    ``results.parquet`` (``chaindrive study collect DIR`` draws the
    main-effects figures).

    Args:
        jobs: cases run at once.
        retry_failed: run the failed cases again.
        progress: ``True`` for a bar, or ``f(cases_done, cases_to_run)``.

    Returns:
        ``StudyResult``: ``table`` (``Table``) and ``to_pandas()``.

    Raises:
        Interrupted: Ctrl-C; ``e.result`` holds the finished cases.
        StudyError: the plan or a case's scene is invalid (nothing ran).
        OSError: the directory holds another study, or cannot be written.
    """
    callback = _progress(progress, "cases")
    directory = os.fspath(dir)
    if isinstance(plan, Mapping):
        plan = dict(plan)
        if scene is None:
            scene = Scene.from_file(plan["scene"]) if "scene" in plan else Scene.l60mc()
        elif not isinstance(scene, Scene):
            scene = Scene.from_file(os.fspath(scene))
        plan["scene"] = os.fspath(plan.get("scene", "scene.toml"))
        raw = _study(
            directory,
            plan_toml=_plan_toml(plan),
            scene_toml=scene.to_toml(),
            jobs=jobs,
            retry_failed=retry_failed,
            progress=callback,
        )
    else:
        if scene is not None:
            raise TypeError("scene: a plan file names its own scene")
        raw = _study(
            directory,
            plan=os.fspath(plan),
            jobs=jobs,
            retry_failed=retry_failed,
            progress=callback,
        )
    return _concluded(StudyResult(raw, directory), callback, raw["pending"],
                      "the study was interrupted; e.result holds the finished cases")


def life(
    scene: Union[Scene, PathLike],
    dir: PathLike,
    *,
    duty: Union[PathLike, Iterable[Mapping[str, Any]], None] = None,
    jobs: int = 1,
    duration: Optional[float] = None,
    window: Optional[float] = None,
    checkpoint_every: Optional[float] = None,
    retry_failed: bool = False,
    progress: Progress = None,
) -> LifeResult:
    """The chain's life over a duty cycle, as ``chaindrive life SCENE --out
    DIR`` computes it: each operating point runs as a case of a study in
    ``dir`` (in parallel, resumable: calling ``life`` again with the same
    points runs only those not finished), and the finished points'
    fatigue damage (and wear, where the scene asks for ``checks.wear``)
    are combined by hours.

    The points are ``duty``: a list of dicts, each with ``hours`` (or
    ``fraction``), an optional ``name`` and ``set`` (dotted scene paths, as
    ``Scene.with_`` takes them)::

        [{"name": "cruise", "hours": 800.0, "set": {"sprockets.0.speed_rpm": 3000.0}},
         {"name": "full", "hours": 50.0, "set": {"sprockets.0.speed_rpm": 6000.0}}]

    or a TOML file of ``[[duty]]`` tables; by default the scene's own
    ``[[duty]]`` points.

    Args:
        duration: simulated time of each point, s (default: the scene's).
        window: statistics window of each point, s (default: the last
            second after the ramps).
        checkpoint_every: simulated seconds between a point's checkpoints.
        jobs: points run at once.
        retry_failed: run the failed points again.
        progress: ``True`` for a bar, or ``f(points_done, points_to_run)``.

    Returns:
        ``LifeResult``: ``report``, ``life_h``, ``governed_by``, ``to_pandas()``.

    Raises:
        Interrupted: Ctrl-C; ``e.result`` holds no report, the finished
            points stay in ``dir`` for the next call.
        StudyError: a point is invalid (its path and what is allowed).
        OSError: the directory holds another study, or cannot be written.
    """
    if not isinstance(scene, Scene):
        scene = Scene.from_file(os.fspath(scene))
    if duty is None:
        duty_toml = None
    elif isinstance(duty, (str, bytes, os.PathLike)):
        with open(os.fspath(duty), encoding="utf-8") as f:
            duty_toml = f.read()
    else:
        duty_toml = _plan_toml({"duty": [dict(p) for p in duty]})
    callback = _progress(progress, "points")
    directory = os.fspath(dir)
    raw = _life(
        scene,
        directory,
        duty_toml=duty_toml,
        jobs=jobs,
        duration=duration,
        window=window,
        checkpoint_every=checkpoint_every,
        retry_failed=retry_failed,
        progress=callback,
    )
    return _concluded(LifeResult(raw, directory), callback, raw["pending"],
                      "the duty cycle was interrupted; the finished points are kept in dir")


def _plan_toml(plan: Mapping[str, Any]) -> str:
    from ._chaindrive import _to_toml

    return _to_toml(plan)
