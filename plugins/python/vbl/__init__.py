"""Python binding of libvbl (ctypes over the shared library; numpy for film layers).

    import vbl
    with vbl.Scene("scene.json") as scene:
        film = vbl.render(scene, method="vrl", passes=4)
        beauty = film.beauty                 # numpy float32 (H, W, 4), a copy
        print(film.layers, film.aovs, film.stats)
        film.write_exr("out.exr", aovs="all")   # the file `vbl render -o out.exr --aov all` writes

Ctrl-C during vbl.render stops the pass in progress and raises vbl.RenderInterrupted (a
KeyboardInterrupt) whose `.film` holds the complete passes. Errors are subclasses of VblError
and of the builtin exception that fits (vbl.FileNotFound is a FileNotFoundError, vbl.SceneError a
ValueError, ...; see vbl.errors). Scenes, films and volumes are context managers with close().

The shared library is found through $VBL_LIBRARY, then next to this package, then where
`cmake --install` put it (vbl/_installed.py), then in the build tree the package was copied into
(vbl/_build_tree.py), then on the system search path. libvbl_python (the package's C side:
cancel flag, OCIO colour management, write_exr) is looked for next to the package.
"""

from ._native import STRUCT_SIZES, library_path, native_available
from ._native import (_FilmStats, _OptionInfo, _RenderProgress, _SceneLoadOptions, _TransmittanceOptions,
                      _TransmittanceResult, _VolumeInfo, _VolumeLoadOptions)
from ._options import RENDER_OPTION_FIELDS, RENDER_OPTIONS
from .errors import (CorruptFile, FileIOError, FileNotFound, GridError, GridNotFound, InvalidArgument, LimitWarning,
                     OutOfMemory, RenderInterrupted, SceneError, Unsupported, VblError)
from .exr import ExrFile
from .film import AOV_LAYERS, LIGHT_GROUP_PREFIX, TOTAL_LAYERS, TRANSPORT_LAYERS, Film
from .rendering import merge, render, render_limits, resume
from .scene import ColorConfig, Scene, default_color_config
from .volume import TransmittanceResult, Volume
from . import _native as _N
from .errors import decode as _decode

__all__ = ["VblError", "FileNotFound", "FileIOError", "InvalidArgument", "SceneError", "CorruptFile", "GridError",
           "GridNotFound", "OutOfMemory", "Unsupported", "RenderInterrupted", "LimitWarning",
           "version", "library_path", "native_available", "Scene", "ColorConfig", "default_color_config", "Volume",
           "Film", "ExrFile", "render", "render_limits", "merge", "resume", "TRANSPORT_LAYERS", "AOV_LAYERS", "TOTAL_LAYERS", "LIGHT_GROUP_PREFIX", "TransmittanceResult",
           "RENDER_OPTION_FIELDS", "RENDER_OPTIONS", "STRUCT_SIZES"]


def version():
    """The runtime version string of the loaded libvbl, e.g. "0.1.0"."""
    return _decode(_N._version_string())
