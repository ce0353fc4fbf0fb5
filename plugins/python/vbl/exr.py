"""EXR files read back (vbl.ExrFile): the channels and header attributes of a multi-layer EXR,
e.g. one `vbl render` wrote, through the project's reader (plugins/exr) in libvbl_python."""

import ctypes
import os

from . import _native as N
from ._handle import Handle
from ._options import encode
from .errors import Unsupported, argument_error, check, decode

_ready = False


def _prototypes():
    global _ready
    if _ready:
        return
    if N._native is None:
        raise Unsupported("VBL_ERROR_UNSUPPORTED", "ExrFile needs libvbl_python (plugins/python/native)")
    n, P = N._native, N._P
    for name, restype, argtypes in (
            ("vbl_py_exr_open", N._R, [ctypes.c_char_p, ctypes.POINTER(P)]),
            ("vbl_py_exr_close", None, [P]),
            ("vbl_py_exr_width", ctypes.c_int, [P]),
            ("vbl_py_exr_height", ctypes.c_int, [P]),
            ("vbl_py_exr_channel_count", ctypes.c_int, [P]),
            ("vbl_py_exr_channel_name", ctypes.c_char_p, [P, ctypes.c_int]),
            ("vbl_py_exr_channel_pixels", ctypes.POINTER(ctypes.c_float), [P, ctypes.c_int]),
            ("vbl_py_exr_attribute_count", ctypes.c_int, [P]),
            ("vbl_py_exr_attribute_name", ctypes.c_char_p, [P, ctypes.c_int]),
            ("vbl_py_exr_attribute", ctypes.c_char_p, [P, ctypes.c_char_p, ctypes.POINTER(ctypes.c_int)])):
        function = getattr(n, name)
        function.restype = restype
        function.argtypes = argtypes
    _ready = True


class ExrFile(Handle):
    """An EXR file read whole. `channel_names` ("R", "Z", "volume_direct.G", ...), `channel(name)`
    (numpy float32 (H, W), row 0 at the top), `layer(name)` (the layer's channels stacked, "" the
    beauty R, G, B, A), `attributes` (name -> value: str, int or float). A context manager."""

    _release = staticmethod(lambda handle: N._native.vbl_py_exr_close(handle))

    def __init__(self, path):
        _prototypes()
        handle = N._P()
        check(N._native.vbl_py_exr_open(encode(os.fspath(path)), ctypes.byref(handle)))
        self._handle = handle
        self.path = os.fspath(path)

    @property
    def width(self):
        """Width of the data window in pixels."""
        return N._native.vbl_py_exr_width(self.handle)

    @property
    def height(self):
        """Height of the data window in pixels."""
        return N._native.vbl_py_exr_height(self.handle)

    @property
    def channel_names(self):
        """Every channel in file order ("A", "B", "G", "R", "Z", "volume_direct.R", ...)."""
        return [decode(N._native.vbl_py_exr_channel_name(self.handle, i))
                for i in range(N._native.vbl_py_exr_channel_count(self.handle))]

    def channel(self, name):
        """One channel as numpy float32 (height, width), row 0 at the top."""
        import numpy
        names = self.channel_names
        if name not in names:
            raise argument_error("%s has no channel %r (channels: %s)" % (self.path, name, ", ".join(names)))
        pixels = N._native.vbl_py_exr_channel_pixels(self.handle, names.index(name))
        w, h = self.width, self.height
        return numpy.array(numpy.ctypeslib.as_array(pixels, shape=(h * w,)), dtype=numpy.float32).reshape(h, w)

    @property
    def layer_names(self):
        """"" (the beauty R, G, B, A), "Z", and every "name." prefix, in channel order."""
        out = []
        for channel in self.channel_names:
            layer = channel.rsplit(".", 1)[0] if "." in channel else ("Z" if channel == "Z" else "")
            if layer not in out:
                out.append(layer)
        return out

    def layer(self, name):
        """The layer's channels as numpy float32 (H, W, C) in R, G, B, A, Y order."""
        import numpy
        order = ("R", "G", "B", "A", "Y", "Z")
        if name in ("", "beauty"):
            channels = [c for c in order[:4] if c in self.channel_names]
        elif name == "Z":
            channels = ["Z"]
        else:
            channels = ["%s.%s" % (name, c) for c in order if "%s.%s" % (name, c) in self.channel_names]
        if not channels:
            raise argument_error("%s has no layer %r (layers: %s)" % (self.path, name, ", ".join(map(repr, self.layer_names))))
        return numpy.stack([self.channel(c) for c in channels], axis=-1)

    @property
    def attributes(self):
        """The header attributes other than the required ones: name -> str, int or float."""
        out = {}
        for index in range(N._native.vbl_py_exr_attribute_count(self.handle)):
            name = N._native.vbl_py_exr_attribute_name(self.handle, index)
            kind = ctypes.c_int()
            text = decode(N._native.vbl_py_exr_attribute(self.handle, name, ctypes.byref(kind)))
            if kind.value == 1:
                value = int(text)
            elif kind.value in (2, 3):
                value = float(text)
            else:
                value = text
            out[decode(name)] = value
        return out
