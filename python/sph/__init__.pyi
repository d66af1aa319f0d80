# Type stubs of the `sph` package (python/sph/__init__.py and the native sph._sph).
import os
from pathlib import Path
from typing import Any, Callable, Dict, List, Mapping, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

PathLike = Union[str, os.PathLike[str]]
Table = Dict[str, Union[npt.NDArray[Any], List[str]]]

__version__: str
CUDA_FEATURE: bool

class SphError(Exception): ...
class SceneError(SphError): ...
class SolverError(SphError): ...

class Scene:
    @classmethod
    def load(
        cls,
        path: PathLike,
        overrides: Optional[Mapping[str, Any]] = ...,
        *,
        reference_dir: Optional[PathLike] = ...,
        **keywords: Any,
    ) -> Scene: ...
    @classmethod
    def from_dict(
        cls,
        table: Mapping[str, Any],
        overrides: Optional[Mapping[str, Any]] = ...,
        *,
        base_dir: PathLike = ...,
        reference_dir: Optional[PathLike] = ...,
        **keywords: Any,
    ) -> Scene: ...
    def check(self) -> str: ...
    @property
    def name(self) -> Optional[str]: ...
    @property
    def dimension(self) -> int: ...
    @property
    def end_time(self) -> float: ...
    @property
    def spacing(self) -> float: ...
    @property
    def path(self) -> Optional[Path]: ...
    @property
    def overrides(self) -> List[str]: ...
    @property
    def solids(self) -> List[str]: ...
    @property
    def probes(self) -> List[str]: ...

class Simulation:
    scene: Scene
    def __init__(
        self, scene: Union[Scene, PathLike], threads: Optional[int] = ..., backend: str = ...
    ) -> None: ...
    def step(self, until: Optional[float] = ...) -> Dict[str, Any]: ...
    def run(
        self,
        until: Optional[float] = ...,
        callback: Optional[Callable[[Simulation, Dict[str, Any]], Any]] = ...,
        progress: bool = ...,
    ) -> Simulation: ...
    def fields(self) -> Dict[str, npt.NDArray[Any]]:
        """Read-only arrays over the simulation's memory, no copy: a snapshot of the state now,
        valid for as long as they live. Held across a step they cost one copy of the fields in
        that step; ``fields()`` after a step gives the new state without a copy."""
        ...
    def forces(self) -> Table: ...
    def probes(self) -> Dict[str, npt.NDArray[np.float64]]: ...
    def steps(self) -> Table: ...
    @property
    def time(self) -> float: ...
    @property
    def steps_taken(self) -> int: ...
    @property
    def end_time(self) -> float: ...
    @property
    def dimension(self) -> int: ...
    @property
    def particle_count(self) -> int: ...
    @property
    def backend(self) -> str: ...
    @property
    def threads(self) -> int: ...
    @property
    def solids(self) -> List[str]: ...

class RunResult:
    out: Path
    def __init__(self, out: PathLike, summary: Optional[Dict[str, Any]] = ...) -> None: ...
    @property
    def summary(self) -> Dict[str, Any]: ...
    @property
    def status(self) -> str: ...
    def table(self, name: str) -> Table: ...
    @property
    def forces(self) -> Table: ...
    @property
    def probes(self) -> Table: ...
    @property
    def steps(self) -> Table: ...

class SweepResult:
    out: Path
    keys: List[str]
    variants: List[Dict[str, Any]]
    skipped_figures: List[str]
    @property
    def table(self) -> Table: ...
    @property
    def runs(self) -> List[RunResult]: ...

def read_table(path: PathLike) -> Table: ...
def run(
    path: PathLike,
    out: Optional[PathLike] = ...,
    *,
    overrides: Optional[Mapping[str, Any]] = ...,
    threads: Optional[int] = ...,
    backend: str = ...,
    force: bool = ...,
    checkpoint_every: Optional[int] = ...,
    reference_dir: Optional[PathLike] = ...,
    progress: bool = ...,
    callback: Optional[Callable[[Dict[str, Any]], Any]] = ...,
    **keywords: Any,
) -> RunResult: ...
def sweep(
    path: PathLike,
    sets: Optional[Mapping[str, Sequence[Any]]] = ...,
    out: Optional[PathLike] = ...,
    *,
    solvers: Optional[Mapping[str, Sequence[float]]] = ...,
    overrides: Optional[Mapping[str, Any]] = ...,
    threads: Optional[int] = ...,
    backend: str = ...,
    force: bool = ...,
    reference_dir: Optional[PathLike] = ...,
    progress: bool = ...,
    callback: Optional[Callable[[Dict[str, Any]], Any]] = ...,
    **keywords: Any,
) -> SweepResult: ...
