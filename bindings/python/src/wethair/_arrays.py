"""NumPy arrays handed to C: checked for shape, converted only where their dtype or layout
differs (a C-contiguous float32 array goes through as it is, without a copy)."""

import ctypes as C
from typing import Optional, Sequence

import numpy as np

from .enums import Result
from .errors import InvalidArgumentError


def _as(a, dtype, shape: Sequence[int], name: str) -> np.ndarray:
    arr = np.ascontiguousarray(a, dtype=dtype)
    if arr.ndim != len(shape) and not (len(shape) == 2 and arr.ndim == 1 and shape[1] > 0):
        raise InvalidArgumentError(Result.ERROR_INVALID_ARGUMENT, f"{name}: expected shape {tuple(shape)}, got {arr.shape}")
    if arr.ndim == 1 and len(shape) == 2:  # a flat array of rows
        if arr.size % shape[1]:
            raise InvalidArgumentError(
                Result.ERROR_INVALID_ARGUMENT, f"{name}: {arr.size} values are not rows of {shape[1]}"
            )
        arr = arr.reshape(-1, shape[1])
    for want, got in zip(shape, arr.shape):
        if want >= 0 and want != got:
            raise InvalidArgumentError(
                Result.ERROR_INVALID_ARGUMENT, f"{name}: expected shape {tuple(shape)}, got {arr.shape}"
            )
    return arr


def as_f32(a, shape, name) -> np.ndarray:
    return _as(a, np.float32, shape, name)


def as_u32(a, shape, name) -> np.ndarray:
    return _as(a, np.uint32, shape, name)


def as_u8(a, shape, name) -> np.ndarray:
    return _as(a, np.uint8, shape, name)


def ptr(arr: Optional[np.ndarray], ctype):
    """A C pointer to ``arr``'s data (NULL for None); the caller keeps ``arr`` alive."""
    if arr is None:
        return C.POINTER(ctype)()
    return arr.ctypes.data_as(C.POINTER(ctype))
