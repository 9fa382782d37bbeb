# Type stubs of the asimov package (__init__.py); the C++ core's are in _asimov.pyi.
import os
from typing import Any, Optional, TextIO, Union

from ._asimov import (SCHEMA_VERSION as SCHEMA_VERSION, Cell as Cell, CellSource, Engine as Engine, Robot as Robot,
                      Session as Session, __version__ as __version__, decompose as decompose,
                      default_cell as default_cell, load_cell as load_cell, load_urdf as load_urdf,
                      puma560 as puma560, robot as robot, trans as trans)
from .errors import (BusyError as BusyError, CellError as CellError, CommandError as CommandError, Error as Error,
                     KinematicsError as KinematicsError, LoadError as LoadError, ProgramError as ProgramError,
                     RobotError as RobotError)

def run(file: Union[str, os.PathLike[str]], cell: CellSource = None, main: Optional[str] = None, trace: bool = False,
        stdout: Optional[TextIO] = None, replay: Optional[Union[str, os.PathLike[str]]] = None) -> dict[str, Any]: ...
