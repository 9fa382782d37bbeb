"""Exceptions of the asimov module. Every one carries the VAL message and where it was found."""


class Error(Exception):
    """A problem asimov reports: `message` is the VAL text ("*Syntax error*", "*Collision*", ...),
    `detail` the short detail after it, `file`/`line`/`column` (1-based; 0 when unknown) where it
    is, `program`/`step` when it is inside a program, `text` the full formatted message."""

    def __init__(self, message, detail="", file="", line=0, column=0, program="", step=0, text=None, **extra):
        self.message = message
        self.detail = detail
        self.file = file
        self.line = line
        self.column = column
        self.program = program
        self.step = step
        self.text = text if text is not None else f"{message}  {detail}".strip()
        for key, value in extra.items():
            setattr(self, key, value)
        super().__init__(self.text)


class LoadError(Error):
    """A .v2 source failed to load or check; `diagnostics` lists every problem (dicts)."""


class CellError(Error):
    """A cell (YAML file or dict) could not be loaded."""


class ProgramError(Error):
    """A program stopped with a run-time error; `report` is the run's report (dict)."""


class CommandError(Error):
    """A monitor command failed; `output` is what the monitor printed for it, `kind` is "command"
    (the command itself failed) or how a program it ran stopped ("collision", "error",
    "interrupted"; then `message`, `detail`, `program`, `step`, `file`, `line` say where, as
    ProgramError does, and `report` is the run's report)."""


class KinematicsError(Error):
    """IK found no solution: "*Location out of reach*" or "*Joint limit exceeded*" (`joint`, `value`)."""


class RobotError(Error):
    """A robot (URDF file) or a mesh could not be loaded."""


class BusyError(Error):
    """A Session or Engine was used from a second thread while another was inside it: use one
    per thread, or a lock around it."""
