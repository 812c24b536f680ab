"""Type stubs of nhlab (see the module's docstring)."""

from typing import Any, Iterable, Mapping, Sequence

import numpy as np
import numpy.typing as npt

__version__: str

System = str | Mapping[str, Any]

class Method:
    """A method written in Python: subclass it and write `step` (docs/own-methods.md)."""

    name: str | None
    order: int
    symmetric: bool
    parameters: Sequence[str]
    def step(
        self, system: Any, q: npt.NDArray[np.float64], v: npt.NDArray[np.float64], h: float,
        memory: dict[str, Any],
    ) -> tuple[npt.ArrayLike, npt.ArrayLike]: ...
    def label(self) -> str: ...
    def params(self) -> dict[str, float]: ...
    def composed(self, composition: str) -> dict[str, Any]: ...
    def with_params(self, **values: float) -> Method: ...

class NewtonError(ArithmeticError): ...

def newton(
    residual: Any, jacobian: Any, x0: npt.ArrayLike, tol: float = ..., max_iter: int = ...,
) -> npt.NDArray[np.float64]: ...

MethodSpec = str | Mapping[str, Any] | Method

class InputError(ValueError):
    message: str
    path: str | None
    status: int
    def __init__(self, message: str, path: str | None = ..., status: int = ...) -> None: ...

class ServerBusy(RuntimeError): ...

class Series:
    t: npt.NDArray[np.float64]
    mean: npt.NDArray[np.float64]
    max: npt.NDArray[np.float64]
    verdict: dict[str, Any] | None
    gap: dict[str, Any] | None

class Run:
    method: dict[str, Any]
    label: str
    status: str
    error: str | None
    steps: int
    elapsed_ms: float
    cpu_ms: float | None
    series: dict[str, Series]
    observables: dict[str, npt.NDArray[np.float64]] | None
    section: dict[str, npt.NDArray[np.float64]] | None

class Simulation:
    scene: dict[str, Any]
    runs: list[Run]
    warnings: list[str]
    def run(self, label: str) -> Run: ...

class SweepRows(list[dict[str, Any]]):
    head: dict[str, Any]
    warnings: list[str]
    def to_json(self, path: str | None = ...) -> str: ...
    def to_pandas(self) -> Any: ...

def systems() -> dict[str, Any]: ...
def simulate(
    system: System,
    preset: str | None = ...,
    params: Mapping[str, float] | None = ...,
    q: Sequence[float] | npt.ArrayLike | None = ...,
    v: Sequence[float] | npt.ArrayLike | None = ...,
    step: float | None = ...,
    t_end: float | None = ...,
    methods: Iterable[MethodSpec] | None = ...,
    integrals: Iterable[str] | None = ...,
    points: int | None = ...,
    observables: Mapping[str, str] | None = ...,
    section: Mapping[str, Any] | None = ...,
) -> Simulation: ...
def scorecard(
    methods: Iterable[MethodSpec] | None = ...,
    scenes: Iterable[Mapping[str, Any]] | None = ...,
    points: int | None = ...,
) -> dict[str, Any]: ...
def work_precision(
    system: System,
    preset: str | None = ...,
    params: Mapping[str, float] | None = ...,
    q: Sequence[float] | npt.ArrayLike | None = ...,
    v: Sequence[float] | npt.ArrayLike | None = ...,
    step: float | None = ...,
    t_end: float | None = ...,
    methods: Iterable[MethodSpec] | None = ...,
    integrals: Iterable[str] | None = ...,
    steps: Sequence[float] | None = ...,
    levels: int | None = ...,
    repeats: int | None = ...,
    observables: Mapping[str, str] | None = ...,
) -> dict[str, Any]: ...
def sweep(
    spec: Mapping[str, Any] | None = ...,
    *,
    client: Any = ...,
    shards: int | None = ...,
    **scene: Any,
) -> SweepRows: ...
