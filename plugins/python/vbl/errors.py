"""Exceptions of the package. Every failing libvbl call raises a subclass of VblError that also
subclasses the builtin exception a Python user would catch for it:

==========================  ======================================  =============================
result code                 exception                               builtin base
==========================  ======================================  =============================
VBL_ERROR_FILE_NOT_FOUND    FileNotFound                            FileNotFoundError (OSError)
VBL_ERROR_FILE_IO           FileIOError                             OSError
VBL_ERROR_INVALID_ARGUMENT  InvalidArgument                         ValueError
VBL_ERROR_SCENE             SceneError                              ValueError
VBL_ERROR_CORRUPT_FILE      CorruptFile                             ValueError
VBL_ERROR_BAD_VOXELS,       GridError                               ValueError
VBL_ERROR_GRID_TYPE
VBL_ERROR_GRID_NOT_FOUND    GridNotFound                            LookupError
VBL_ERROR_OUT_OF_MEMORY     OutOfMemory                             MemoryError
VBL_ERROR_UNSUPPORTED       Unsupported                             NotImplementedError
VBL_ERROR_INTERNAL          VblError                                Exception
VBL_ERROR_INTERRUPTED       RenderInterrupted                       KeyboardInterrupt
==========================  ======================================  =============================

RenderInterrupted is not a VblError (so ``except Exception`` does not swallow a Ctrl-C); it
carries the same ``result`` and ``message`` and the partial ``film`` (None if no pass completed).
"""

import errno as _errno

from . import _native

__all__ = ["VblError", "FileNotFound", "FileIOError", "InvalidArgument", "SceneError", "CorruptFile",
           "GridError", "GridNotFound", "OutOfMemory", "Unsupported", "RenderInterrupted"]


class VblError(Exception):
    """A failed libvbl call: `result` is the result code's name ("VBL_ERROR_SCENE"), `message`
    the library's message naming the file/field at fault."""

    def __init__(self, result, message):
        super().__init__(result, message)
        self.result = result
        self.message = message

    def __str__(self):
        return "%s: %s" % (self.result, self.message) if self.message else self.result


class _OSErrorMixin(VblError):
    _errno = _errno.EIO

    def __init__(self, result, message):
        OSError.__init__(self, self._errno, message)
        self.result = result
        self.message = message


class FileNotFound(_OSErrorMixin, FileNotFoundError):
    """A file does not exist or cannot be opened."""
    _errno = _errno.ENOENT


class FileIOError(_OSErrorMixin, OSError):
    """A read or write failed (full disk, unwritable folder)."""


class InvalidArgument(VblError, ValueError):
    """A parameter is out of range or of the wrong kind."""


class SceneError(VblError, ValueError):
    """A malformed scene: the message names the file and the field."""


class CorruptFile(VblError, ValueError):
    """Not a VDB/NanoVDB/JSON/EXR file, truncated, or inconsistent."""


class GridError(VblError, ValueError):
    """The grid is not a float grid, or holds NaN/Inf/negative values."""


class GridNotFound(VblError, LookupError):
    """No grid of that name or index; the message lists the grids."""


class OutOfMemory(VblError, MemoryError):
    """An allocation failed."""


class Unsupported(VblError, NotImplementedError):
    """Valid input this build cannot handle."""


class RenderInterrupted(KeyboardInterrupt):
    """A render stopped by Ctrl-C, the cancel argument or the callback before its last pass with
    no film to return, or by Ctrl-C with one. `film` holds the complete passes (None if none)."""

    def __init__(self, result, message, film=None):
        super().__init__(result, message)
        self.result = result
        self.message = message
        self.film = film

    def __str__(self):
        return "%s: %s" % (self.result, self.message) if self.message else self.result


_BY_CODE = {1: InvalidArgument, 2: OutOfMemory, 3: FileNotFound, 4: FileIOError, 5: CorruptFile,
            6: Unsupported, 7: GridNotFound, 8: GridError, 9: GridError, 10: SceneError}
SUCCESS = 0
ERROR_INVALID_ARGUMENT = 1
ERROR_INTERRUPTED = 11


def decode(value):
    return value.decode("utf-8", "replace") if value is not None else None


def error_for(code, fallback=""):
    """The exception for a failed call's result code, with the library's message."""
    message = decode(_native._last_error_message()) or fallback
    name = decode(_native._result_name(code))
    if code == ERROR_INTERRUPTED:
        return RenderInterrupted(name, message)
    return _BY_CODE.get(code, VblError)(name, message)


def check(code):
    if code != SUCCESS:
        raise error_for(code)


def argument_error(message):
    return InvalidArgument(decode(_native._result_name(ERROR_INVALID_ARGUMENT)), message)


class LimitWarning(UserWarning):
    """A render runs into a documented limit of its method at the extremes (vbl_render_limits,
    docs/readme/render.md "Limits at the extremes"): a near-delta phase function with a
    virtual-light method, a kernel radius too large, optically thick media. The render still runs;
    the message is the line `vbl render` prints as a warning (scene file and field)."""
