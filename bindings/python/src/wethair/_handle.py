"""What Groom and Simulation share: one C handle, destroyed once, by ``close()``, a ``with``
block's end, or garbage collection."""

import ctypes as C
from typing import Callable, Optional


class Handle:
    """Owns a C handle; subclasses give the function that destroys it and their name."""

    _destroy: Callable[[C.c_void_p], None]
    _what = "handle"

    def __init__(self, handle: Optional[C.c_void_p] = None):
        self._h = handle

    @property
    def handle(self) -> C.c_void_p:
        """The C handle; ``ValueError`` once closed."""
        if not self._h:
            raise ValueError(f"wethair: this {self._what} is closed")
        return self._h

    def close(self) -> None:
        """Destroys the C object (idempotent)."""
        if self._h:
            type(self)._destroy(self._h)
            self._h = None

    def __enter__(self):
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def __del__(self) -> None:
        self.close()
