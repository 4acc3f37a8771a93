"""Type stubs of the native module `chaindrive._chaindrive` (Rust, PyO3).

Use it through `chaindrive`: `Scene`, the exceptions, `check`, `rate` and
`chains` are re-exported as they are; `run`, `sweep` and `study` are wrapped
(results with `to_pandas()`, `Interrupted`, progress bars).
"""

import os
from typing import Any, Callable, Dict, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
from typing_extensions import final

__all__ = ["Scene", "SceneError", "SimError", "StudyError", "run", "check", "sweep", "study", "life", "rate", "chains", "_to_toml", "__version__"]

__version__: str

_Path = Union[str, os.PathLike[str]]
_Value = Union[bool, int, float, str, Sequence[Any], Mapping[str, Any]]

class SceneError(ValueError):
    """A scene (or a run's setting of one) is invalid. The message is the
    command line's, one line per problem; `path` is the first problem's
    field path (`'sprockets[2].teeth'`, `''` for a TOML syntax error)."""

    path: str
    paths: List[str]
    problems: List[Dict[str, Any]]

class SimError(RuntimeError):
    """The simulation could not start (no layout, no static equilibrium)
    or blew up; the message names the time, body, detector and causes."""

class StudyError(ValueError):
    """A study's plan, or a case's scene, is invalid."""

@final
class Scene:
    """A chain drive, valid by construction (immutable)."""

    @staticmethod
    def from_file(path: _Path) -> Scene:
        """Reads and validates a TOML scene file. Raises `SceneError`, `OSError`."""
    @staticmethod
    def from_toml(text: str) -> Scene:
        """Parses and validates a TOML scene. Raises `SceneError`."""
    @staticmethod
    def l60mc() -> Scene:
        """The paper's drive (MAN B&W L60MC camshaft chain, Pedersen 2005)."""
    def with_(self, values: Optional[Mapping[str, _Value]] = None, /, **more: _Value) -> Scene:
        """This scene with values set by dotted path (`"sprockets.0.speed_rpm"`).
        Raises `SceneError` naming the path."""
    def with_designation(self, designation: str) -> Scene:
        """This scene with its chain named by a designation (`"ANSI 80"`)."""
    def to_toml(self) -> str:
        """The scene file as TOML."""
    def to_dict(self) -> Dict[str, Any]:
        """The scene file as a dict."""
    def warnings(self) -> List[str]:
        """What is valid but likely unintended, a sentence each."""
    @property
    def name(self) -> str:
        """The scene's name."""
    def __eq__(self, value: object, /) -> bool: ...

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
    record: Optional[_Path] = None,
    record_channels: str = "all",
    checkpoint: Optional[_Path] = None,
    checkpoint_every: Optional[float] = None,
    resume: Optional[_Path] = None,
    progress: Optional[Callable[[float, float], Any]] = None,
    poll_s: float = 0.1,
) -> Tuple[Dict[str, Any], Dict[str, np.ndarray], bool]:
    """Runs a scene: (summary, series arrays, interrupted). See `chaindrive.run`."""

def sweep(
    scene: Scene,
    rpm: Union[Sequence[float], str],
    *,
    settle: float = 1.0,
    window: float = 1.0,
    jobs: Optional[int] = None,
    max_order: Optional[float] = None,
    order_step: float = 1.0,
    progress: Optional[Callable[[float, float], Any]] = None,
) -> Dict[str, Any]:
    """The speed sweep's tables. See `chaindrive.sweep`."""

def study(
    dir: _Path,
    *,
    plan: Optional[_Path] = None,
    plan_toml: Optional[str] = None,
    scene_toml: Optional[str] = None,
    jobs: int = 1,
    retry_failed: bool = False,
    progress: Optional[Callable[[float, float], Any]] = None,
) -> Dict[str, Any]:
    """A design study's table. See `chaindrive.study`."""

def life(
    scene: Scene,
    dir: _Path,
    *,
    duty_toml: Optional[str] = None,
    jobs: int = 1,
    duration: Optional[float] = None,
    window: Optional[float] = None,
    checkpoint_every: Optional[float] = None,
    retry_failed: bool = False,
    progress: Optional[Callable[[float, float], Any]] = None,
) -> Dict[str, Any]:
    """A duty cycle's life. See `chaindrive.life`."""

def check(scene: Scene) -> Dict[str, Any]:
    """The scene laid out and at static equilibrium, as `chaindrive check`
    reports it: strands, sprockets (teeth, pitch radius, wrap), the chain's
    length, the static tension, the step. Raises `SimError`."""

def rate(scene: Scene, *, service_factor: float = 1.0, power_w: Optional[float] = None) -> Dict[str, Any]:
    """The chain's catalogue rating at the scene's speeds (`chaindrive rate
    --json`). Raises `ValueError` when the scene cannot be rated."""

def chains(name: Optional[str] = None) -> List[Dict[str, Any]]:
    """The chains known by designation with their sources; one with `name`
    (`"ANSI 80-2"`: n strands, the derived values saying how). A value no
    source gives (a motorcycle chain's mass, strength) is None. Raises
    `ValueError` naming the nearest designations."""

def _to_toml(value: Mapping[str, Any]) -> str: ...
