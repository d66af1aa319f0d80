"""sph from Python: scenes, simulations, runs and parameter sweeps.

The package follows the library's own path: ``Scene.load`` (or ``Scene.from_dict``) loads and
validates a scene, ``Simulation`` steps it, ``run`` runs a scene file into a run folder as
``sph run`` does and ``sweep`` runs one variant per value as ``sph sweep`` does; both write the
same files as the command line. Tables are dicts of columns (NumPy arrays, or lists of text)
named as the CSV files name them, so ``pandas.DataFrame(table)`` takes them as they are.

docs/python.md is the guide.
"""

from __future__ import annotations

import csv
import json
import math
import os
import sys
import time
from pathlib import Path
from typing import Any, Callable, Dict, List, Mapping, Optional, Sequence, Union

import numpy as np

from . import _sph
from ._sph import CUDA_FEATURE, SceneError, SolverError, SphError, __version__  # noqa: F401

__all__ = [
    "__version__",
    "CUDA_FEATURE",
    "RunResult",
    "Scene",
    "SceneError",
    "Simulation",
    "SolverError",
    "SphError",
    "SweepResult",
    "read_table",
    "run",
    "sweep",
]

PathLike = Union[str, "os.PathLike[str]"]

# Integer columns of the run's CSV files (steps.csv); every other column is a float or text.
_INT_COLUMNS = {
    "step",
    "steps",
    "correction_iterations",
    "removed_particles",
    "created_particles",
    "outflow_particles",
    "variant",
    "index",
}


def _toml_value(value: Any) -> str:
    """``value`` written as a TOML value, the VALUE of a ``KEY=VALUE`` override."""
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    if isinstance(value, str):
        # A JSON string is a TOML basic string (same escapes, \\uXXXX included).
        return json.dumps(value)
    if isinstance(value, Mapping):
        return "{ " + ", ".join(f"{k} = {_toml_value(v)}" for k, v in value.items()) + " }"
    if isinstance(value, (list, tuple, np.ndarray)):
        return "[" + ", ".join(_toml_value(v) for v in value) + "]"
    if isinstance(value, os.PathLike):
        return json.dumps(os.fspath(value))
    raise TypeError(f"cannot write {value!r} ({type(value).__name__}) as a scene value")


def _sets(overrides: Optional[Mapping[str, Any]], keywords: Mapping[str, Any]) -> List[str]:
    """The ``KEY=VALUE`` overrides of a dict (dotted keys) and of keyword arguments (``end_time``
    is ``solver.end_time``, as ``--end-time``; ``__`` stands for a dot: ``solver__dt``)."""
    sets = []
    for key, value in (overrides or {}).items():
        sets.append(f"{key}={_toml_value(value)}")
    for key, value in keywords.items():
        dotted = "solver.end_time" if key == "end_time" else key.replace("__", ".")
        sets.append(f"{dotted}={_toml_value(value)}")
    return sets


def _path(path: Optional[PathLike]) -> Optional[str]:
    return None if path is None else os.fspath(path)


class _Progress:
    """A progress bar over simulated time: tqdm (``tqdm.auto``, so notebooks get a widget) when
    installed, else one line on stderr when it is a terminal, else nothing."""

    def __init__(self, enabled: bool, start: float, end: float, label: str = "") -> None:
        self.start, self.end, self.label = start, end, label
        self.bar = None
        self.line = False
        self.shown = 0.0
        self.last = 0.0
        if not enabled:
            return
        try:
            from tqdm.auto import tqdm
        except ImportError:
            self.line = sys.stderr.isatty()
            return
        total = max(end - start, 0.0)
        self.bar = tqdm(total=total, unit="s", leave=False,
                        bar_format="{percentage:3.0f}%|{bar}| {desc} [{elapsed}<{remaining}]")

    def update(self, t: float, steps: int) -> None:
        if self.bar is not None:
            now = min(t, self.end) - self.start
            self.bar.set_description_str(f"{self.label}t = {t:.4f}/{self.end:g} s, {steps} steps", refresh=False)
            self.bar.update(now - self.shown)
            self.shown = now
        elif self.line:
            wall = time.monotonic()
            if wall - self.last >= 0.1 or t >= self.end:
                self.last = wall
                span = max(self.end - self.start, 1e-300)
                done = int(30 * min(max((t - self.start) / span, 0.0), 1.0))
                sys.stderr.write(f"\r{self.label}[{'#' * done}{'.' * (30 - done)}] t = {t:.4f}/{self.end:g} s, {steps} steps")
                sys.stderr.flush()

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()
        elif self.line:
            sys.stderr.write("\r\033[K")
            sys.stderr.flush()


class Scene:
    """A validated scene (immutable). Load it with :meth:`Scene.load` or :meth:`Scene.from_dict`."""

    def __init__(self, native: "_sph.Scene") -> None:
        self._native = native

    @classmethod
    def load(cls, path: PathLike, overrides: Optional[Mapping[str, Any]] = None, *,
             reference_dir: Optional[PathLike] = None, **keywords: Any) -> "Scene":
        """Loads and validates the scene file at ``path`` with ``overrides`` (``{"solver.dt": 1e-4}``,
        as ``sph run --set``; keyword ``end_time=`` as ``--end-time``). Raises :class:`SceneError`
        with the message ``sph run`` prints."""
        sets = _sets(overrides, keywords)
        return cls(_sph.Scene.load(os.fspath(path), sets, _path(reference_dir)))

    @classmethod
    def from_dict(cls, table: Mapping[str, Any], overrides: Optional[Mapping[str, Any]] = None, *,
                  base_dir: PathLike = ".", reference_dir: Optional[PathLike] = None,
                  **keywords: Any) -> "Scene":
        """A scene from a dict with the keys of a scene file (``tomllib.load`` of one gives such a
        dict); mesh files are read relative to ``base_dir``."""
        text = json.dumps(table, default=_json_default)
        sets = _sets(overrides, keywords)
        return cls(_sph.Scene.from_json(text, sets, os.fspath(base_dir), _path(reference_dir)))

    def check(self) -> str:
        """What ``sph check`` prints: particle counts, memory needed and the stage plan."""
        return self._native.check()

    @property
    def name(self) -> Optional[str]:
        return self._native.name

    @property
    def dimension(self) -> int:
        return self._native.dimension

    @property
    def end_time(self) -> float:
        """End time [s]."""
        return self._native.end_time

    @property
    def spacing(self) -> float:
        """Particle spacing [m]."""
        return self._native.spacing

    @property
    def path(self) -> Optional[Path]:
        """The scene file (``None`` for a scene made from a dict)."""
        p = self._native.path
        return None if p is None else Path(p)

    @property
    def overrides(self) -> List[str]:
        """The overrides applied, each ``KEY=VALUE``."""
        return list(self._native.sets)

    @property
    def solids(self) -> List[str]:
        return list(self._native.solids)

    @property
    def probes(self) -> List[str]:
        return list(self._native.probes)

    def __repr__(self) -> str:
        return repr(self._native)


def _json_default(value: Any) -> Any:
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, os.PathLike):
        return os.fspath(value)
    raise TypeError(f"cannot write {value!r} ({type(value).__name__}) as a scene value")


class Simulation:
    """A scene's simulation, stepped from Python.

    ``threads`` workers (default: all cores) on ``backend`` ("cpu", or "cuda" in a module built
    with the ``cuda`` feature). The solver runs with the GIL released.
    """

    def __init__(self, scene: Union[Scene, PathLike], threads: Optional[int] = None,
                 backend: str = "cpu") -> None:
        if not isinstance(scene, Scene):
            scene = Scene.load(scene)
        self.scene = scene
        self._native = _sph.Simulation(scene._native, threads, backend)

    def step(self, until: Optional[float] = None) -> Dict[str, Any]:
        """One step towards ``until`` [s] (default: the end time); returns its row of ``steps.csv``."""
        return self._native.step(until)

    def run(self, until: Optional[float] = None, callback: Optional[Callable[["Simulation", Dict[str, Any]], Any]] = None,
            progress: bool = True) -> "Simulation":
        """Steps to ``until`` [s] (default: the scene's end time). ``callback(sim, step)`` is called
        after every step with the step's row; returning ``False`` stops. Ctrl-C raises
        ``KeyboardInterrupt`` after the current step, the simulation consistent at that step."""
        end = self.end_time if until is None else float(until)
        bar = _Progress(progress, self.time, end)
        try:
            while self.time < end:
                row = self._native.step(end)
                bar.update(row["t_s"], row["step"])
                if callback is not None and callback(self, row) is False:
                    break
        finally:
            bar.close()
        return self

    def fields(self) -> Dict[str, np.ndarray]:
        """The particle fields as read-only arrays over the simulation's memory (no copy):
        ``position``, ``velocity`` (N, D) float32; ``density``, ``pressure``, ``mass`` (N,)
        float32; ``kind``, ``id`` (N,) uint32; ``rest_density`` with several fluid phases.

        The arrays are a snapshot of the state now, valid for as long as they live. Holding them
        across a step costs one copy of the fields in that step (the step goes on with the copy);
        call ``fields()`` again after a step for the new state, without a copy."""
        return self._native.fields()

    def forces(self) -> Dict[str, Any]:
        """The forces on the named solids after every step, as ``forces.csv``'s columns."""
        return self._native.forces()

    def probes(self) -> Dict[str, np.ndarray]:
        """The probes' samples, as ``probes.csv``'s columns."""
        return self._native.probes()

    def steps(self) -> Dict[str, Any]:
        """One entry per step taken, as ``steps.csv``'s columns."""
        return self._native.steps()

    @property
    def time(self) -> float:
        """Simulated time [s]."""
        return self._native.time

    @property
    def steps_taken(self) -> int:
        return self._native.steps_taken

    @property
    def end_time(self) -> float:
        return self._native.end_time

    @property
    def dimension(self) -> int:
        return self._native.dimension

    @property
    def particle_count(self) -> int:
        return self._native.particle_count

    @property
    def backend(self) -> str:
        return self._native.backend

    @property
    def threads(self) -> int:
        return self._native.threads

    @property
    def solids(self) -> List[str]:
        return list(self._native.solids)

    def __repr__(self) -> str:
        return repr(self._native)


def read_table(path: PathLike) -> Dict[str, Any]:
    """A CSV file ``sph`` wrote, as a dict of columns: float64 arrays (exactly the values written,
    which are shortest round-trip decimals), int64 arrays for counts, lists for text."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if not rows:
        return {}
    header, body = rows[0], rows[1:]
    table: Dict[str, Any] = {}
    for k, name in enumerate(header):
        values = [r[k] if k < len(r) else "" for r in body]
        if name in _INT_COLUMNS:
            try:
                table[name] = np.array([int(v) for v in values], dtype=np.int64)
                continue
            except ValueError:
                pass
        try:
            table[name] = np.array([float(v) if v != "" else math.nan for v in values], dtype=np.float64)
        except ValueError:
            table[name] = values
    return table


class RunResult:
    """A run folder and its tables, read from the files ``sph run`` wrote."""

    def __init__(self, out: PathLike, summary: Optional[Dict[str, Any]] = None) -> None:
        self.out = Path(out)
        self._summary = summary

    @property
    def summary(self) -> Dict[str, Any]:
        """``summary.json``."""
        if self._summary is None:
            with open(self.out / "summary.json") as f:
                self._summary = json.load(f)
        return self._summary

    @property
    def status(self) -> str:
        return self.summary.get("status", "")

    def table(self, name: str) -> Dict[str, Any]:
        """The run's ``<name>.csv`` (``forces``, ``probes``, ``steps``, ``bodies``) as columns;
        empty when the run wrote no such file."""
        path = self.out / f"{name}.csv"
        return read_table(path) if path.exists() else {}

    @property
    def forces(self) -> Dict[str, Any]:
        return self.table("forces")

    @property
    def probes(self) -> Dict[str, Any]:
        return self.table("probes")

    @property
    def steps(self) -> Dict[str, Any]:
        return self.table("steps")

    def __repr__(self) -> str:
        return f"RunResult({str(self.out)!r}, status={self.status!r})"


class SweepResult:
    """A sweep folder: ``sweep.csv`` as :attr:`table` and one :class:`RunResult` per variant."""

    def __init__(self, out: PathLike, report: Dict[str, Any]) -> None:
        self.out = Path(out)
        self.keys: List[str] = report["keys"]
        self.variants: List[Dict[str, Any]] = report["variants"]
        self.skipped_figures: List[str] = report["skipped_figures"]

    @property
    def table(self) -> Dict[str, Any]:
        """``sweep.csv``: one row per variant."""
        return read_table(self.out / "sweep.csv")

    @property
    def runs(self) -> List[RunResult]:
        """Each variant's run folder, in order."""
        return [RunResult(v["dir"]) for v in self.variants]

    def __repr__(self) -> str:
        return f"SweepResult({str(self.out)!r}, {len(self.variants)} variants)"


def _stem(path: PathLike) -> str:
    return Path(path).stem or "scene"


def run(path: PathLike, out: Optional[PathLike] = None, *, overrides: Optional[Mapping[str, Any]] = None,
        threads: Optional[int] = None, backend: str = "cpu", force: bool = False,
        checkpoint_every: Optional[int] = None, reference_dir: Optional[PathLike] = None,
        progress: bool = True, callback: Optional[Callable[[Dict[str, Any]], Any]] = None,
        **keywords: Any) -> RunResult:
    """``sph run PATH --out OUT``: runs the scene file to its end time and writes the run folder
    (default ``out/<scene stem>``) as the command line does. Keyword overrides as
    :meth:`Scene.load` (``end_time=0.1``, ``solver__dt=1e-4``). ``callback(progress)`` is called
    after every step with a dict (``time``, ``end_time``, ``steps``, ...); an exception it raises,
    or Ctrl-C, ends the run after the current step with a checkpoint and the status
    ``interrupted``, then propagates."""
    sets = _sets(overrides, keywords)
    out = Path("out") / _stem(path) if out is None else Path(out)
    bar: Optional[_Progress] = None

    def report(p: Dict[str, Any]) -> None:
        nonlocal bar
        if bar is None:
            bar = _Progress(progress, 0.0, p["end_time"])
        bar.update(p["time"], p["steps"])
        if callback is not None:
            callback(p)

    try:
        summary = _sph.run_file(os.fspath(path), os.fspath(out), sets, threads, backend, force,
                                checkpoint_every, _path(reference_dir), report)
    finally:
        if bar is not None:
            bar.close()
    return RunResult(out, json.loads(summary))


def sweep(path: PathLike, sets: Optional[Mapping[str, Sequence[Any]]] = None, out: Optional[PathLike] = None, *,
          solvers: Optional[Mapping[str, Sequence[float]]] = None, overrides: Optional[Mapping[str, Any]] = None,
          threads: Optional[int] = None, backend: str = "cpu", force: bool = False,
          reference_dir: Optional[PathLike] = None, progress: bool = True,
          callback: Optional[Callable[[Dict[str, Any]], Any]] = None, **keywords: Any) -> SweepResult:
    """``sph sweep PATH --set KEY=V1,V2,... --out OUT``: one run per combination of the swept
    values (``sets={"solver.delta": [1e-2, 1e-3]}``; several keys give every combination, the
    first varying slowest), or per solver setting (``solvers={"wcsph": [20, 40]}``). Writes
    ``sweep.csv``, the figures and one run folder per variant (default ``out/<stem>-sweep``).
    ``overrides`` and keywords apply to every variant."""
    swept = [f"{k}=" + ",".join(_toml_value(v) for v in values) for k, values in (sets or {}).items()]
    swept += _sets(overrides, keywords)
    solver_sets = [f"{k}=" + ",".join(_toml_value(v) for v in values) for k, values in (solvers or {}).items()]
    out = Path("out") / f"{_stem(path)}-sweep" if out is None else Path(out)
    bar: Optional[_Progress] = None

    def report(event: Dict[str, Any]) -> None:
        nonlocal bar
        kind = event["event"]
        if kind == "step":
            if bar is None:
                bar = _Progress(progress, 0.0, event["end_time"], label=label)
            bar.update(event["time"], event["steps"])
        elif bar is not None:
            bar.close()
            bar = None
        if callback is not None:
            callback(event)

    label = ""

    def labelled(event: Dict[str, Any]) -> None:
        nonlocal label
        if event["event"] == "started":
            label = f"{event['index']}/{event['count']} "
        report(event)

    try:
        result = _sph.sweep_file(os.fspath(path), os.fspath(out), swept, solver_sets, threads, backend,
                                 force, _path(reference_dir), labelled)
    finally:
        if bar is not None:
            bar.close()
    return SweepResult(out, json.loads(result))
