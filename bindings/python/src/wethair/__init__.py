"""wethair for Python: real-time wet hair over the library's C ABI (ctypes), NumPy in and out.

>>> import wethair
>>> with wethair.Groom.paper_scene(1000, 6) as groom, \\
...      wethair.Simulation(groom, preset="paper", backend="cpu") as sim:
...     sim.add_water([[0.0, 0.0, 0.15]])
...     sim.step(1 / 60)
...     x = sim.strands()          # (1000, 6, 3) float32

Every call checks its arguments in the library; a failure raises the ``WetHairError``
subclass of its code (``InvalidArgumentError``, ``UnsupportedError``, ...) with the library's
message. Nothing here simulates: the physics is the library's, the same the C API runs.
"""

from ._lib import lib as _lib, library_path
from .desc import PRESETS, sim_desc
from .enums import (
    Backend,
    ColliderShape,
    DampingModel,
    GuideChoice,
    Integrator,
    Readback,
    Result,
    SpringModel,
    UpAxis,
    VertexAttribute,
)
from .errors import (
    BufferTooSmallError,
    CapacityError,
    DeviceError,
    InvalidArgumentError,
    NullPointerError,
    PanicError,
    ParseError,
    StructSizeError,
    UnstableError,
    UnsupportedError,
    WetHairError,
    WetHairIOError,
)
from .groom import Groom
from .sim import WATER_QUANTUM_KG, Advance, BackendInfo, Sdf, Simulation, Stats, VertexLayout, capsule, sphere

__version__ = "0.1.0"


def version() -> str:
    """The loaded library's version string (``wethair_version_string``)."""
    return _lib.wethair_version_string().decode()


__all__ = [
    "Advance", "Backend", "BackendInfo", "BufferTooSmallError", "CapacityError", "ColliderShape",
    "DampingModel", "DeviceError", "Groom", "GuideChoice", "Integrator", "InvalidArgumentError",
    "NullPointerError", "PRESETS", "PanicError", "ParseError", "Readback", "Result", "Sdf",
    "Simulation", "SpringModel", "Stats", "StructSizeError", "UnstableError", "UnsupportedError",
    "UpAxis", "VertexAttribute", "VertexLayout", "WATER_QUANTUM_KG", "WetHairError",
    "WetHairIOError", "NullPointerError", "capsule", "library_path", "sim_desc", "sphere", "version",
]
