"""ergosim: a digital twin of ergonomic human-robot role allocation.

Implements Merlo, Lamon et al., "An Ergonomic Role Allocation Framework for Dynamic Human-Robot
Collaborative Tasks": AND/OR-graph task models with per-agent hyper-arcs, an AO* allocator, RULA and the
Kinematic Wear index (or REBA), in a MuJoCo workcell with collaborative robots from example-robot-data and
a kinematic human.
"""

__version__ = "0.1.0"

from ergosim.blas_kernel import pin as _pin_blas_kernel  # noqa: E402

_pin_blas_kernel()  # before anything imports numpy: the same bits on every x86-64 machine (blas_kernel.py)

import logging  # noqa: E402

logging.getLogger("ergosim").addHandler(logging.NullHandler())  # a library: the application decides

from ergosim.errors import (  # noqa: E402
    ConfigError,
    ErgosimError,
    InfeasiblePlanError,
    ModelError,
    RecordingError,
    TaskFileError,
)

__all__ = [
    "__version__",
    "ErgosimError",
    "TaskFileError",
    "InfeasiblePlanError",
    "ConfigError",
    "ModelError",
    "RecordingError",
]
