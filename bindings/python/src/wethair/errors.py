"""Exceptions raised when a C call fails: one class per ``WetHairResult`` code, each carrying
the code and the library's message (``wethair_last_error_message``)."""

from .enums import Result


class WetHairError(Exception):
    """A wethair call failed. ``code`` is the ``Result``; ``message`` the library's words."""

    def __init__(self, code: int, message: str):
        try:
            self.code: "Result | int" = Result(code)
            name = self.code.name
        except ValueError:  # a code from a newer library than this package
            self.code, name = int(code), f"result {code}"
        self.message = message
        super().__init__(f"{name}: {message}")


class NullPointerError(WetHairError):
    pass


class InvalidArgumentError(WetHairError, ValueError):
    """A value was out of range, non-finite, of the wrong shape or count."""


class StructSizeError(WetHairError):
    pass


class CapacityError(WetHairError):
    """More water particles than the simulation's capacity."""


class BufferTooSmallError(WetHairError):
    pass


class WetHairIOError(WetHairError, OSError):
    """A groom file could not be read."""


class ParseError(WetHairError):
    """A groom file is not a groom this library reads."""


class UnstableError(WetHairError):
    """The simulation went non-finite (the vertex buffer keeps the last good state)."""


class PanicError(WetHairError):
    """The library caught an internal panic at its boundary; the handle is still safe to destroy."""


class DeviceError(WetHairError):
    """The GPU device was lost or could not be created."""


class UnsupportedError(WetHairError):
    """The simulation's backend or configuration does not offer what was asked."""


_BY_CODE = {
    Result.ERROR_NULL_POINTER: NullPointerError,
    Result.ERROR_INVALID_ARGUMENT: InvalidArgumentError,
    Result.ERROR_STRUCT_SIZE: StructSizeError,
    Result.ERROR_CAPACITY: CapacityError,
    Result.ERROR_BUFFER_TOO_SMALL: BufferTooSmallError,
    Result.ERROR_IO: WetHairIOError,
    Result.ERROR_PARSE: ParseError,
    Result.ERROR_UNSTABLE: UnstableError,
    Result.ERROR_PANIC: PanicError,
    Result.ERROR_DEVICE: DeviceError,
    Result.ERROR_UNSUPPORTED: UnsupportedError,
}


def error_for(code: int, message: str) -> WetHairError:
    """The exception for a C result code (``WetHairError`` itself for a code this version does not name)."""
    try:
        return _BY_CODE.get(Result(code), WetHairError)(code, message)
    except ValueError:
        return WetHairError(code, message)


def check(code: int) -> None:
    """Raises the exception for ``code`` unless it is ``OK``."""
    if code != 0:
        from ._lib import lib

        raise error_for(code, lib.wethair_last_error_message().decode("utf-8", "replace"))
