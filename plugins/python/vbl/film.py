"""Films: the layers of a render as numpy arrays, transport layers and AOVs apart, and the EXR
`vbl render` writes (Film.write_exr)."""

import ctypes
import os

from . import _native as N
from ._handle import Handle
from ._options import encode
from .errors import Unsupported, argument_error, check, decode

# The AOV layers (not light transport): depth, camera samples per pixel, variance of the mean.
AOV_LAYERS = ("Z", "samples", "variance")
# Colour layers that are sums of transport layers (VBL_FILM_TOTAL_*): not added to the beauty again.
TOTAL_LAYERS = ("volume_indirect", "surface_indirect")
# Prefix of a light group's layer ("lightgroup_<name>": that group's share of the beauty).
LIGHT_GROUP_PREFIX = "lightgroup_"


def _transport_names():
    names = []
    for index in range(64):
        name = N._transport_class_name(index)
        if not name or decode(name) in names or decode(name) in ("", "unknown"):
            break
        names.append(decode(name))
    return tuple(names)


# The transport-class layer names in film order (they sum to the beauty in this order).
TRANSPORT_LAYERS = _transport_names()
_COMPRESSION = {"none": 0, "zip": 1, "piz": 2, "dwaa": 3}


class Film(Handle):
    """The result of a render. `beauty`, `layer(name)`: copies as numpy float32 (H, W, C), row 0 at
    the top. `layers`: the transport layers present (they sum to the beauty's RGB); `totals`: the
    sums of transport layers (volume_indirect, surface_indirect); `light_groups`: the
    lightgroup_<name> layers; `aovs`: the non-colour layers (Z, samples, variance). A context
    manager; close() frees it."""

    _release = staticmethod(lambda handle: N._film_release(handle))

    def __init__(self, handle, scene=None, options=None, passes_requested=0):
        self._handle = handle
        # what write_exr records: the scene and the vbl_render_options rendered with
        self._scene = scene
        self._options = options
        self._passes_requested = passes_requested

    @property
    def width(self):
        """Width in pixels."""
        return N._film_width(self.handle)

    @property
    def height(self):
        """Height in pixels."""
        return N._film_height(self.handle)

    @property
    def layer_names(self):
        """Every layer in film order; "" is the beauty."""
        return [decode(N._film_layer_name(self.handle, i)) for i in range(N._film_layer_count(self.handle))]

    @property
    def layers(self):
        """The light-transport layers present (background, volume_direct, ...: vbl.TRANSPORT_LAYERS,
        the classes that sum to the beauty's RGB), in film order. A transparent render
        (stats["transparent"]) leaves `background` out of the beauty: the others sum to it."""
        return [name for name in self.layer_names if name in TRANSPORT_LAYERS]

    @property
    def totals(self):
        """The total layers present: sums of transport layers (vbl.TOTAL_LAYERS: volume_indirect =
        volume_from_surface + volume_from_volume, surface_indirect likewise), in film order. Colour
        layers, not in `layers` (adding them would count those classes twice)."""
        return [name for name in self.layer_names if name in TOTAL_LAYERS]

    @property
    def light_groups(self):
        """The light-group layers present ("lightgroup_<name>", the scene's lights[].group): each a
        group's share of the beauty; colour layers, in film order, not in `layers`."""
        return [name for name in self.layer_names if name.startswith(LIGHT_GROUP_PREFIX)]

    @property
    def aovs(self):
        """The non-colour layers present: "Z", "samples", "variance" (vbl.AOV_LAYERS) and any
        derived layer a newer library adds (not the beauty, `layers`, `totals` or `light_groups`)."""
        return [name for name in self.layer_names
                if name and name not in TRANSPORT_LAYERS and name not in TOTAL_LAYERS
                and not name.startswith(LIGHT_GROUP_PREFIX)]

    def channels(self, name):
        """Channel names of a layer: "R", "G", "B"[, "A"], or "Z" / "Y"."""
        key = encode("" if name == "beauty" else name)
        return [decode(N._film_layer_channel_name(self.handle, key, c))
                for c in range(N._film_layer_channel_count(self.handle, key))]

    def layer(self, name):
        """A copy of the layer's pixels as numpy float32 (height, width, channels), row 0 at the
        top. "" or "beauty" is the beauty (R, G, B, A)."""
        import numpy
        key = encode("" if name == "beauty" else name)
        channels = ctypes.c_int()
        pixels = N._film_layer(self.handle, key, ctypes.byref(channels))
        if not pixels:
            raise argument_error("the film has no layer %r (layers: %s)" %
                                 (name, ", ".join(repr(n) for n in self.layer_names)))
        w, h, c = self.width, self.height, channels.value
        flat = numpy.ctypeslib.as_array(pixels, shape=(h * w * c,))
        return numpy.array(flat, dtype=numpy.float32, copy=True).reshape(h, w, c)

    @property
    def beauty(self):
        """The beauty (R, G, B, A premultiplied) as numpy float32 (H, W, 4)."""
        return self.layer("")

    @property
    def stats(self):
        """vbl_film_stats as a dict: method (name), passes, spp, light_paths, seed, threads,
        render_seconds, cancelled, time_limited, first_pass, discarded_pass, transparent."""
        stats = N._FilmStats()
        stats.size = ctypes.sizeof(N._FilmStats)
        check(N._film_get_stats(self.handle, ctypes.byref(stats)))
        out = {name: getattr(stats, name) for name, _ in N._FilmStats._fields_ if name != "size"}
        out["method"] = decode(N._method_name(out["method"]))
        return out

    def write_exr(self, path, aovs=(), half=False, half_layers=(), compression="zip", status=None,
                  preset=None, frame=None, scene_label=None, output_space=None):
        """Writes the film as `vbl render -o path` does: the beauty, the transport layers and the
        `aovs` asked for ("z", "samples", "variance" or "all", as --aov), FLOAT unless `half` (every
        colour layer, --half) or named in `half_layers` (--half-layers), `compression` "zip",
        "piz", "dwaa" or "none", and the same header attributes (docs/readme/output.md,
        "Metadata": vbl:scene, vbl:scene_hash, vbl:options_hash, vbl:passes, ...), so `vbl merge`
        and `vbl render --resume` take it. Written to a temporary name and renamed. `status`
        defaults to the film's ("complete", "interrupted", "time_limit"), `frame` (vbl:frame) to
        the scene's. Films from vbl.render,
        vbl.merge and vbl.resume know their scene and options; others raise vbl.InvalidArgument."""
        if N._native is None:
            raise Unsupported("VBL_ERROR_UNSUPPORTED", "write_exr needs libvbl_python (plugins/python/native)")
        if self._scene is None or self._options is None:
            raise argument_error("write_exr: this film has no scene/options (use a film of vbl.render, "
                                 "vbl.merge or vbl.resume)")
        wanted = {a.lower() for a in ([aovs] if isinstance(aovs, str) else aovs)}
        unknown = wanted - {"z", "samples", "variance", "all"}
        if unknown:
            raise argument_error("write_exr: unknown aovs %s (z, samples, variance, all)" % sorted(unknown))
        if compression not in _COMPRESSION:
            raise argument_error("write_exr: compression %r is not one of %s" % (compression, ", ".join(_COMPRESSION)))
        every = "all" in wanted
        o = N._ExrOptions()
        o.size = ctypes.sizeof(N._ExrOptions)
        o.scene = self._scene.handle
        o.scene_label = encode(scene_label)
        o.render_options = self._options.handle
        o.status = encode(status)
        o.passes_requested = int(self._passes_requested)
        o.preset = encode(preset)
        if frame is None:
            frame = self._scene.frame  # vbl:frame of a scene loaded for a sequence frame, as --frames writes
        o.has_frame = frame is not None
        o.frame = int(frame) if frame is not None else 0
        o.compression = _COMPRESSION[compression]
        o.half_all = 1 if half else 0
        o.half_layers = encode(",".join(half_layers))
        o.aov_z, o.aov_samples, o.aov_variance = (every or "z" in wanted, every or "samples" in wanted,
                                                  every or "variance" in wanted)
        config = self._scene.color_config
        o.color = config.handle if config is not None else None
        o.output_space = encode(output_space)
        check(N._native.vbl_py_film_write_exr(self.handle, encode(os.fspath(path)), ctypes.byref(o)))
