"""Grooms: the strands a simulation is made from (yours, a file's, or the paper scene)."""

from __future__ import annotations

import ctypes as C
import os
from typing import Optional, Sequence, Union

import numpy as np

from . import _structs as S
from ._arrays import as_f32, as_u32, as_u8, ptr
from ._handle import Handle
from ._lib import lib
from .enums import UpAxis, coerce
from .errors import check


class Groom(Handle):
    """A groom handle (``WetHairGroom``). Use as a context manager, or call ``close()``;
    simulations copy what they need, so a groom may be closed once they are made."""

    _destroy = staticmethod(lib.wethair_groom_destroy)
    _what = "groom"

    def __init__(self, handle: C.c_void_p, point_counts: Optional[np.ndarray] = None):
        super().__init__(handle)
        self._point_counts = point_counts

    # -- constructors -------------------------------------------------------------------

    @classmethod
    def from_strands(
        cls,
        strands: Union[Sequence[np.ndarray], np.ndarray],
        point_counts: Optional[Sequence[int]] = None,
        pinned: Optional[np.ndarray] = None,
        masses: Optional[np.ndarray] = None,
        default_mass: float = 1e-3,
    ) -> "Groom":
        """Strands given as arrays, in metres, head space (z up).

        ``strands`` is one of: an array ``(strands, points, 3)``; a list of ``(n_i, 3)``
        arrays; or an array ``(total_points, 3)`` with ``point_counts``. ``pinned`` (bool per
        point; default: each strand's first point) and ``masses`` (kg per point; default
        ``default_mass`` each) are optional. The library checks every value."""
        if point_counts is None:
            if isinstance(strands, np.ndarray) and strands.ndim == 3:
                point_counts = [strands.shape[1]] * strands.shape[0]
                positions = strands.reshape(-1, 3)
            else:
                parts = [np.asarray(s, dtype=np.float32).reshape(-1, 3) for s in strands]
                point_counts = [len(p) for p in parts]
                positions = np.concatenate(parts) if parts else np.zeros((0, 3), np.float32)
        else:
            positions = strands
        pos = as_f32(positions, (-1, 3), "positions")
        counts = as_u32(point_counts, (-1,), "point_counts")
        n = pos.shape[0]
        pin = None if pinned is None else as_u8(np.asarray(pinned).astype(bool), (n,), "pinned")
        mass = None if masses is None else as_f32(masses, (n,), "masses")
        d = S.WetHairGroomDesc(
            struct_size=C.sizeof(S.WetHairGroomDesc),
            strand_count=len(counts),
            strand_point_counts=ptr(counts, C.c_uint32),
            positions=ptr(pos, C.c_float),
            point_count=n,
            pinned=ptr(pin, C.c_uint8),
            masses=ptr(mass, C.c_float),
            default_mass=default_mass,
        )
        h = C.c_void_p()
        check(lib.wethair_groom_create(C.byref(d), C.byref(h)))
        return cls(h, counts.copy())

    @classmethod
    def paper_scene(cls, strands: int = 10000, points: int = 6) -> "Groom":
        """The paper's scene: ``strands`` strands of ``points`` points on a 0.1 m head at the origin."""
        h = C.c_void_p()
        check(lib.wethair_groom_create_paper_scene(strands, points, C.byref(h)))
        return cls(h, np.full(strands, points, dtype=np.uint32))

    @classmethod
    def load(
        cls,
        path: Union[str, os.PathLike],
        *,
        scale: Optional[float] = None,
        up_axis: Union[UpAxis, str, int, None] = None,
        point_mass: Optional[float] = None,
        linear_density: Optional[float] = None,
        strand_stride: Optional[int] = None,
        resample_points: Optional[int] = None,
        weld_length: Optional[float] = None,
    ) -> "Groom":
        """Loads a TressFX ``.tfx``, Cem Yuksel ``.hair`` or USC-HairSalon ``.data`` file; the
        keywords are ``WetHairLoadDesc``'s fields (units to metres, up axis, masses,
        subsampling, resampling); left out, they keep the library's defaults."""
        d = S.WetHairLoadDesc()
        lib.wethair_load_desc_default(C.byref(d))
        given = dict(
            scale=scale,
            point_mass=point_mass,
            linear_density=linear_density,
            strand_stride=strand_stride,
            resample_points=resample_points,
            weld_length=weld_length,
        )
        for k, v in given.items():
            if v is not None:
                setattr(d, k, v)
        if up_axis is not None:
            d.up_axis = coerce(UpAxis, up_axis)
        h = C.c_void_p()
        check(lib.wethair_groom_load_with_desc(os.fsencode(path), C.byref(d), C.byref(h)))
        return cls(h)

    # -- queries --------------------------------------------------------------------------

    @property
    def counts(self) -> tuple:
        """``(strands, points)``."""
        s, p = C.c_uint32(), C.c_uint32()
        check(lib.wethair_groom_get_counts(self.handle, C.byref(s), C.byref(p)))
        return s.value, p.value

    @property
    def point_counts(self) -> Optional[np.ndarray]:
        """Points per strand where this package made the groom (None for a loaded file)."""
        return self._point_counts

    @property
    def load_message(self) -> str:
        """What the loader did to a file's groom (units, fixes), or ""."""
        m = lib.wethair_groom_get_load_message(self.handle)
        return m.decode("utf-8", "replace") if m else ""
