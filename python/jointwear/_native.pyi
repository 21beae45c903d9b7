"""Type stubs of the native module (src/python/): the scene document and the exceptions."""

from os import PathLike
from typing import Any, Dict, List, Optional, Sequence, Tuple

__version__: str

class SceneError(ValueError):
    """A scene that cannot be read, parsed, validated or assembled (the program's exit code 2)."""

class SimulationError(RuntimeError):
    """A failure while running (the program's exit code 1)."""

class Document:
    """A scene document (``extends`` resolved) and the path that names it in messages."""

    @staticmethod
    def load(path: str | PathLike[str]) -> Document: ...
    @staticmethod
    def from_dict(table: Dict[str, Any], base_dir: Optional[str] = None) -> Document: ...
    def set(self, key: str, value: Any) -> None: ...
    def to_dict(self) -> Dict[str, Any]: ...
    @property
    def path(self) -> str: ...
    def copy(self) -> Document: ...
    def check(self) -> Dict[str, Any]: ...
    def state(self) -> Tuple[PathLike[str], str, List[Tuple[str, str, bool]]]: ...
    @staticmethod
    def from_state(
        path: str | PathLike[str], loaded: str, asked: List[Tuple[str, str, bool]]
    ) -> Document: ...
    def run(
        self, member: Optional[int], seed: int, perturbation: Optional[str] = None
    ) -> Dict[str, Any]: ...
    def ensemble(
        self, members: int, seed: int, perturbation: Optional[str] = None
    ) -> Dict[str, Any]: ...
    def check_ensemble(
        self, members: int, seed: int, perturbation: Optional[str] = None
    ) -> None: ...
    def member(
        self, member: int, members: int, seed: int, perturbation: Optional[str] = None
    ) -> str: ...
    def ensemble_of(
        self,
        members: int,
        seed: int,
        payloads: List[str],
        wall: float,
        perturbation: Optional[str] = None,
    ) -> Dict[str, Any]: ...
    def sweep(
        self,
        keys: List[str],
        values: List[Sequence[Any]],
        members: Optional[int] = None,
        seed: int = 1,
    ) -> Tuple[List[str], List[Dict[str, Any]]]: ...
    def check_sweep(
        self,
        keys: List[str],
        values: List[Sequence[Any]],
        members: Optional[int] = None,
        seed: int = 1,
    ) -> Tuple[List[str], int, str]: ...
    def sweep_case(
        self,
        keys: List[str],
        values: List[Sequence[Any]],
        case: int,
        members: Optional[int] = None,
        seed: int = 1,
    ) -> Dict[str, Any]: ...

class Folder:
    """A run or an ensemble held to be saved as the program saves it."""

    def save(self, dir: str | PathLike[str]) -> None: ...
