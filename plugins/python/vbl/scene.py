"""JSON scenes (vbl_scene_load_ex), from a file or a dict, colour-managed through the OCIO
adapter as `vbl render` loads them."""

import copy
import ctypes
import json
import os
import tempfile
import weakref

from . import _native as N
from ._handle import Handle
from ._options import Options, encode
from .errors import Unsupported, argument_error, check, decode

# Keys of a scene that hold file paths (made absolute by Scene.from_dict).
_PATH_KEYS = (("media", "vdb"), ("media", "emission", "vdb"), ("media", "temperature", "vdb"), ("surfaces", "mesh"))


def _remove_quietly(path):
    try:
        os.unlink(path)
    except OSError:
        pass


class ColorConfig(Handle):
    """An OCIO config through libvbl_python (`vbl render --config`): None reads $OCIO, else the
    config libvbl ships; "" or "libvbl" the shipped one; else a path."""

    _release = staticmethod(lambda handle: N._native.vbl_py_color_release(handle))

    def __init__(self, path=None):
        if N._native is None:
            raise Unsupported("VBL_ERROR_UNSUPPORTED", "colour management needs libvbl_python (built with "
                              "OpenColorIO and OpenEXR next to the package)")
        handle = N._P()
        check(N._native.vbl_py_color_open(encode(path), ctypes.byref(handle)))
        self._handle = handle

    @property
    def scene_linear(self):
        """The name of the config's scene_linear colour space (the film's space)."""
        return decode(N._native.vbl_py_color_scene_space(self.handle))


_default_config = None


def default_color_config():
    """The config `vbl render` uses without --config ($OCIO, else the shipped one), opened once."""
    global _default_config
    if _default_config is None:
        _default_config = ColorConfig(None)
    return _default_config


class Scene(Handle):
    """A JSON scene (vbl_scene_load_ex). A context manager; close() frees it.

    `vdb_overrides`: list replacing media[i].vdb (None keeps the scene's path). `frame`: the frame
    number for VDB sequence patterns ("smoke.####.vdb", "%04d") in media[i].vdb and the
    overrides; None: a pattern fails the load. `camera`: the name of an entry of the scene's
    "cameras", or a JSON file holding a camera (`vbl render --camera`); `width`, `height`: the
    image size instead of the camera's resolution (`--resolution WxH`; both or neither). `color_config`: the scene's `color_space` colours
    are converted to scene_linear through this ColorConfig (default: the one `vbl render` uses);
    False loads without colour management (a scene naming a color_space then fails to load).
    A missing file raises vbl.FileNotFound, a malformed one vbl.SceneError (a ValueError)."""

    _release = staticmethod(lambda handle: N._scene_release(handle))

    def __init__(self, path, vdb_overrides=None, frame=None, color_config=None, camera=None, width=None,
                 height=None):
        self._handle = None
        self._temporary = None
        self.frame = frame
        overrides = [None if p is None else encode(os.fspath(p)) for p in (vdb_overrides or [])]
        array = (ctypes.c_char_p * max(len(overrides), 1))(*overrides)
        options = N._SceneLoadOptions(ctypes.sizeof(N._SceneLoadOptions),
                                      ctypes.cast(array, ctypes.POINTER(ctypes.c_char_p)) if overrides else None,
                                      len(overrides))
        if frame is not None:
            options.frame = int(frame)
            options.use_frame = 1
        if (width is None) != (height is None):
            raise argument_error("Scene: give both width and height, or neither")
        if width is not None:
            if int(width) < 1 or int(height) < 1:
                raise argument_error("Scene: width and height must be >= 1 (got %r, %r)" % (width, height))
            options.width, options.height = int(width), int(height)
        if camera is not None:
            camera = encode(os.fspath(camera))
            options.camera = camera
        if color_config is None and N._native is not None:
            color_config = default_color_config()
        self.color_config = color_config or None
        if self.color_config is not None:
            options.convert_color = N._convert_scene_color
            options.convert_color_user = self.color_config.handle
        handle = N._P()
        check(N._scene_load_ex(encode(os.fspath(path)), ctypes.byref(options), ctypes.byref(handle)))
        self._handle = handle
        if self.color_config is not None:
            check(N._native.vbl_py_color_check_scene(self.color_config.handle, handle))

    @classmethod
    def from_dict(cls, scene, base_dir=None, **kwargs):
        """A scene from a dict in the JSON schema (docs/reference/scene.md). Relative file paths
        (media[].vdb, media[].emission.vdb, media[].temperature.vdb, surfaces[].mesh) resolve
        against `base_dir` (default: the current folder). The JSON is written to a private
        temporary file (the scene's path, removed by close()); errors name it and the field.
        Other keyword arguments are Scene()'s."""
        base = os.path.abspath(base_dir if base_dir is not None else os.getcwd())
        data = copy.deepcopy(scene)
        for keys in _PATH_KEYS:
            for item in data.get(keys[0], []) if isinstance(data, dict) else []:
                holder = item
                for key in keys[1:-1]:
                    holder = holder.get(key) if isinstance(holder, dict) else None
                if isinstance(holder, dict) and isinstance(holder.get(keys[-1]), str):
                    holder[keys[-1]] = os.path.join(base, holder[keys[-1]])
        fd, path = tempfile.mkstemp(prefix="vbl-scene-", suffix=".json")
        try:
            with os.fdopen(fd, "w") as f:
                json.dump(data, f, indent=1)
            self = cls(path, **kwargs)
        except BaseException:
            os.unlink(path)
            raise
        # removed by close(), at garbage collection, or at interpreter exit, whichever comes first
        self._temporary = weakref.finalize(self, _remove_quietly, path)
        return self

    def close(self):
        """Frees the scene and removes a from_dict scene's temporary file. Idempotent."""
        Handle.close(self)
        temporary, self._temporary = getattr(self, "_temporary", None), None
        if temporary is not None:
            temporary()

    @property
    def path(self):
        """The scene file's path (a from_dict scene's temporary file)."""
        return decode(N._scene_path(self.handle))

    @property
    def resolution(self):
        """(width, height) of the camera."""
        w, h = ctypes.c_int(), ctypes.c_int()
        N._scene_resolution(self.handle, ctypes.byref(w), ctypes.byref(h))
        return (w.value, h.value)

    @property
    def light_count(self):
        """Number of lights."""
        return N._scene_light_count(self.handle)

    @property
    def medium_count(self):
        """Number of media."""
        return N._scene_medium_count(self.handle)

    def medium_path(self, index):
        """The VDB path of medium `index` as loaded (overrides and frame applied)."""
        return decode(N._scene_medium_path(self.handle, int(index)))

    def _render_options(self):
        options = Options()
        check(N._scene_render_options(self.handle, options.handle))
        return options

    def render_options(self):
        """The scene's `render` block (defaults for what it leaves out) as a dict keyed by the
        fields of vbl_render_options (RENDER_OPTION_FIELDS); enums as names ("pt", "ratio", "power"),
        bools as bool."""
        return self._render_options().to_dict()
