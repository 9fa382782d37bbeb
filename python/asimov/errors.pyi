# Type stubs of asimov.errors (errors.py).
from typing import Any

class Error(Exception):
    message: str
    detail: str
    file: str
    line: int
    column: int
    program: str
    step: int
    text: str
    def __init__(self, message: str, detail: str = "", file: str = "", line: int = 0, column: int = 0,
                 program: str = "", step: int = 0, text: str | None = None, **extra: Any) -> None: ...

class LoadError(Error):
    diagnostics: list[dict[str, Any]]

class CellError(Error): ...

class ProgramError(Error):
    report: dict[str, Any]

class CommandError(Error):
    output: str
    kind: str
    report: dict[str, Any]

class KinematicsError(Error):
    joint: int
    value: float

class RobotError(Error): ...
class BusyError(Error): ...
