"""Lifetime of a library handle: close() (idempotent), a context manager, and release at garbage
collection for what was not closed."""

from .errors import InvalidArgument


class Handle:
    _handle = None
    _release = None  # staticmethod(handle -> None) in subclasses

    @property
    def handle(self):
        """The library handle (ctypes void pointer); raises vbl.InvalidArgument once closed."""
        if not self._handle:
            raise InvalidArgument("VBL_ERROR_INVALID_ARGUMENT", "%s is closed" % type(self).__name__)
        return self._handle

    @property
    def closed(self):
        """True once close() ran."""
        return not self._handle

    def close(self):
        """Frees the library object now; later use raises vbl.InvalidArgument. Idempotent."""
        handle, self._handle = self._handle, None
        if handle and type(self)._release is not None:
            type(self)._release(handle)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False

    def __del__(self):
        try:
            self.close()
        except Exception:  # interpreter shutdown: the library may be gone
            pass
