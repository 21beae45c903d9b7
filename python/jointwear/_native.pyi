"""Type stubs of the native module (src/python/): the scene document and the exceptions."""

from os import PathLike
from typing import Any, Dict, List, Optional, Sequence

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
    def from_dict(table: Dict[str, Any], path: str | PathLike[str]) -> Document: ...
    def set(self, key: str, value: Any) -> None: ...
    def to_dict(self) -> Dict[str, Any]: ...
    @property
    def path(self) -> str: ...
    def copy(self) -> Document: ...
    def check(self) -> Dict[str, Any]: ...
    def run(self, member: Optional[int], seed: int) -> Dict[str, Any]: ...
    def ensemble(self, members: int, seed: int) -> Dict[str, Any]: ...
    def sweep(
        self,
        keys: List[str],
        values: List[Sequence[Any]],
        members: Optional[int] = None,
        seed: int = 1,
    ) -> List[Dict[str, Any]]: ...
