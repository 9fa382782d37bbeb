"""asimov: VAL II / V+ programs in simulation, halted the instant anything touches anything.

The module wraps the C++ libraries (docs/python.md): cells, programs and their reports, monitor
sessions, traces as NumPy arrays, FK/IK of any arm and the collision engine itself.
"""
from .errors import (Error, LoadError, CellError, ProgramError, CommandError, KinematicsError,
                     RobotError)
from ._asimov import (__version__, SCHEMA_VERSION, Cell, Robot, Session, Engine, load_cell,
                      default_cell, puma560, load_urdf, trans, decompose)


def run(file, cell=None, main=None, trace=False, stdout=None):
    """Loads `file` (.v2) into `cell` (a Cell, a cell file path or a dict; None: the built-in cell)
    and runs `main` (default: the first program). Returns the report as a dict, the same document
    as `asimov run --report`; with trace=True also report["trace"], the checked poses as NumPy
    arrays (Session.trace). What the program prints (TYPE) is written to `stdout` when given.
    Raises LoadError (the file does not load), CellError, ProgramError (a run-time error; the
    report is on the exception); a collision is a result, not an exception."""
    session = Session(cell, trace=trace)
    session.load(file)
    try:
        report = session.run(main)
    finally:
        if stdout is not None:
            stdout.write(session.output())
    if trace:
        report["trace"] = session.trace()
    return report


__all__ = ["Error", "LoadError", "CellError", "ProgramError", "CommandError", "KinematicsError",
           "RobotError", "__version__", "SCHEMA_VERSION", "Cell", "Robot", "Session", "Engine",
           "load_cell", "default_cell", "puma560", "load_urdf", "trans", "decompose", "run"]
