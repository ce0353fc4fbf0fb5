#!/bin/sh
# `cmake --install` of the build tree into a temporary prefix; the installed package vbl (and its
# dist-info metadata) then imports from that prefix alone and renders, finding the installed
# libvbl by its relative path (vbl/_installed.py), not the build tree.
# usage: test_python_install.sh CMAKE BUILD_DIR PYTHON PYTHON_INSTALL_DIR BOX_VDB
set -eu
cmake=$1 build=$2 python=$3 pydir=$4 box=$5
"$python" -c "import numpy" 2>/dev/null || { echo "SKIPPED: numpy is not installed"; exit 77; }
prefix=$(mktemp -d)
trap 'rm -rf "$prefix"' EXIT
"$cmake" --install "$build" --prefix "$prefix" >"$prefix/install.log" 2>&1 || { cat "$prefix/install.log"; exit 1; }
cd "$prefix"
[ -f "$prefix/share/libvbl/blender/vbl_blender/__init__.py" ] || { echo "the Blender add-on was not installed"; exit 1; }
env -u VBL_LIBRARY -u VBL_PYTHON_NATIVE PYTHONPATH="$prefix/$pydir" VBL_BOX="$box" PREFIX="$prefix" "$python" - <<'PY'
import importlib.metadata, os, sys
import vbl
prefix = os.path.realpath(os.environ["PREFIX"])
assert os.path.realpath(vbl.__file__).startswith(prefix), vbl.__file__
assert os.path.realpath(vbl.library_path()).startswith(prefix), vbl.library_path()
assert not os.path.exists(os.path.join(os.path.dirname(vbl.__file__), "_build_tree.py"))
assert vbl.native_available(), "libvbl_python not installed next to the package"
assert importlib.metadata.version("vbl") == vbl.version(), (importlib.metadata.version("vbl"), vbl.version())
scene = {"camera": {"position": [0.75, -3.0, 0.75], "look_at": [0.75, 0.75, 0.75], "resolution": [8, 6]},
         "lights": [{"type": "distant", "direction": [0, 0, -1], "irradiance": 1.0}],
         "media": [{"vdb": os.environ["VBL_BOX"], "density_scale": 3.0}],
         "render": {"passes": 1, "spp": 1}}
with vbl.Scene.from_dict(scene) as s:
    film = vbl.render(s)
    film.write_exr("installed.exr")
with vbl.ExrFile("installed.exr") as f:
    assert f.attributes["vbl:passes"] == 1
print("installed vbl", vbl.version(), "from", os.path.dirname(vbl.__file__), "library", vbl.library_path())
PY
