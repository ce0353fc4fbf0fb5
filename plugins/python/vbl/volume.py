"""VDB grids (vbl_volume_load): info, point lookups and transmittance estimates."""

import ctypes
import os

from . import _native as N
from ._handle import Handle
from ._options import encode
from .errors import argument_error, check, decode


class TransmittanceResult(tuple):
    """(mean, std_error, lookups) of vbl_volume_transmittance."""
    __slots__ = ()

    def __new__(cls, mean, std_error, lookups):
        return tuple.__new__(cls, (mean, std_error, lookups))

    mean = property(lambda self: self[0])
    std_error = property(lambda self: self[1])
    lookups = property(lambda self: self[2])

    def __repr__(self):
        return "TransmittanceResult(mean=%r, std_error=%r, lookups=%r)" % self


def _vec3(values, what):
    try:
        items = [float(v) for v in values]
    except TypeError:
        raise argument_error("%s must be 3 numbers" % what) from None
    if len(items) != 3:
        raise argument_error("%s must be 3 numbers, got %d" % (what, len(items)))
    return (ctypes.c_double * 3)(*items)


class Volume(Handle):
    """A float grid of an OpenVDB (.vdb) or NanoVDB (.nvdb) file (vbl_volume_load). A context
    manager; close() frees it at once. A missing file raises vbl.FileNotFound (a FileNotFoundError),
    a missing grid vbl.GridNotFound (a LookupError)."""

    _release = staticmethod(lambda handle: N._volume_release(handle))

    def __init__(self, path, grid=None, grid_index=-1, sanitize=False, majorant_block_size=0):
        options = N._VolumeLoadOptions(ctypes.sizeof(N._VolumeLoadOptions), encode(grid), int(grid_index),
                                       1 if sanitize else 0, int(majorant_block_size))
        handle = N._P()
        self._handle = None
        check(N._volume_load(encode(os.fspath(path)), ctypes.byref(options), ctypes.byref(handle)))
        self._handle = handle

    @property
    def info(self):
        """vbl_volume_info as a dict (paths/names as str, arrays as lists)."""
        info = N._VolumeInfo()
        info.size = ctypes.sizeof(N._VolumeInfo)
        check(N._volume_get_info(self.handle, ctypes.byref(info)))
        out = {}
        for name, _ in N._VolumeInfo._fields_:
            if name == "size":
                continue
            value = getattr(info, name)
            if isinstance(value, bytes):
                value = decode(value)
            elif name == "index_to_world":
                value = [list(row) for row in value]
            elif hasattr(value, "__len__"):
                value = list(value)
            out[name] = value
        return out

    def sample(self, point, filter="trilinear"):
        """Grid value at a world-space point ("nearest" or "trilinear")."""
        mode = {"nearest": 0, "trilinear": 1}.get(filter)
        if mode is None:
            raise argument_error("unknown filter %r (nearest, trilinear)" % (filter,))
        return N._volume_sample(self.handle, _vec3(point, "point"), mode)

    def transmittance(self, origin, direction, tmin, tmax, estimator="ratio", density_scale=1.0,
                      samples=64, seed=0, march_step=0.0, cache_size=0):
        """Estimates T(tmin, tmax) along origin + t * direction with `samples` estimates."""
        options = N._TransmittanceOptions(ctypes.sizeof(N._TransmittanceOptions), _parse_estimator(estimator),
                                          float(density_scale), float(march_step), int(cache_size), int(seed))
        result = N._TransmittanceResult()
        check(N._volume_transmittance(self.handle, _vec3(origin, "origin"), _vec3(direction, "direction"),
                                      float(tmin), float(tmax), ctypes.byref(options), int(samples),
                                      ctypes.byref(result)))
        return TransmittanceResult(result.mean, result.std_error, result.lookups)


def _parse_estimator(value):
    if isinstance(value, int):
        return value
    out = N._R()
    if N._estimator_parse(encode(value), ctypes.byref(out)) != 0:
        raise argument_error("unknown transmittance estimator %r (delta, ratio, residual, march, "
                             "cached-delta, cached-ratio)" % (value,))
    return out.value
