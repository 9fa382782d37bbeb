"""asimov: VAL II / V+ programs in simulation, halted the instant anything touches anything.

The module wraps the C++ libraries (docs/python.md): cells, programs and their reports, monitor
sessions, traces as NumPy arrays, FK/IK of any arm and the collision engine itself.
"""
try:
    import numpy  # noqa: F401  (poses, joints and traces are NumPy arrays)
except ImportError as _missing:  # say so at import, not at the first array
    raise ImportError("asimov needs NumPy (Debian: apt-get install python3-numpy; pip: numpy)") from _missing

from .errors import (Error, LoadError, CellError, ProgramError, CommandError, KinematicsError,
                     RobotError, BusyError)
from ._asimov import (__version__, SCHEMA_VERSION, Cell, Robot, Session, Engine, load_cell,
                      default_cell, puma560, robot, load_urdf, trans, decompose)


def _replay_dir():
    """The replay page's assets beside the module: BUILD/share/asimov/replay in the build tree
    (BUILD/python/asimov), PREFIX/share/asimov/replay installed (PREFIX/lib/python3/dist-packages/asimov)."""
    import os
    import pathlib
    here = pathlib.Path(__file__).resolve()
    for up in (2, 4):
        if len(here.parents) > up:
            candidate = here.parents[up] / "share" / "asimov" / "replay"
            if candidate.is_dir():
                return str(candidate)
    return os.environ.get("ASIMOV_REPLAY_DIR")


_write_replay = Session.write_replay


def _session_write_replay(self, path):
    """Writes the 3D replay page of the last run (Session(replay=True)), as `asimov run --replay`
    writes it. The viewer's files are found beside the module ($ASIMOV_REPLAY_DIR wins)."""
    import os
    if "ASIMOV_REPLAY_DIR" not in os.environ and _replay_dir():
        os.environ["ASIMOV_REPLAY_DIR"] = _replay_dir()
    _write_replay(self, os.fspath(path))


Session.write_replay = _session_write_replay


def run(file, cell=None, main=None, trace=False, stdout=None, replay=None):
    """Loads `file` (.v2) into `cell` (a Cell, a cell file path or a dict; None: the built-in cell)
    and runs `main` (default: the first program). Returns the report as a dict, the same document
    as `asimov run --report`; with trace=True also report["trace"], the checked poses as NumPy
    arrays (Session.trace); with replay=PATH the 3D replay page is written there. What the program prints (TYPE) is written to `stdout` when given.
    Raises LoadError (the file does not load), CellError, ProgramError (a run-time error; the
    report is on the exception); a collision is a result, not an exception."""
    session = Session(cell, trace=trace, replay=replay is not None)
    session.load(file)
    try:
        report = session.run(main)
    finally:
        if stdout is not None:
            stdout.write(session.output())
    if trace:
        report["trace"] = session.trace()
    if replay is not None:
        session.write_replay(replay)
    return report


__all__ = ["Error", "LoadError", "CellError", "ProgramError", "CommandError", "KinematicsError",
           "RobotError", "BusyError", "__version__", "SCHEMA_VERSION", "Cell", "Robot", "Session",
           "Engine", "load_cell", "default_cell", "puma560", "robot", "load_urdf", "trans", "decompose",
           "run"]
