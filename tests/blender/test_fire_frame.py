"""A Mantaflow fire frame end to end with every method (issue 15): bakes a small gas domain with
fire and smoke (../shared/tools/cycles-reference/bake_gas.py: density, flame, temperature and
velocity grids in one OpenVDB file per frame), renders its last frame over a floor with no light
but the fire (flame as emission, temperature as blackbody) with pt, vpl, vrl, vbl and beams, and
checks each image: the transport layers sum to the beauty, no NaN, Inf or negative pixel, the
fire is seen (volume_emission) and lights the smoke (volume_direct) and, except for beams (which
shades no surfaces), the floor (surface_direct); the fire's photons carry volume_from_volume. Slow (the bake, ~5 s CPU): label `slow`.
Run: python3 test_fire_frame.py SOURCE_DIR BUILD_DIR [SHARED_DIR]"""

import json
import os
import shutil
import subprocess
import sys
import tempfile

SOURCE, BUILD = sys.argv[1], sys.argv[2]
SHARED = sys.argv[3] if len(sys.argv) > 3 else os.path.join(SOURCE, "..", "shared")
BAKE = os.path.join(SHARED, "tools", "cycles-reference", "bake_gas.py")
sys.path[:0] = [os.path.join(BUILD, "python"), os.path.join(SOURCE, "plugins", "python")]
os.environ.setdefault("VBL_LIBRARY", os.path.join(BUILD, "libvbl", "libvbl.so"))
FRAMES = 12
METHODS = ("pt", "vpl", "vrl", "vbl", "beams")
TRANSPORT = ("background", "volume_emission", "volume_direct", "volume_from_volume", "surface_direct",
             "surface_from_surface", "surface_from_volume", "volume_from_surface")


def skip(why):
    print("test_fire_frame: SKIPPED: " + why)
    sys.exit(77)


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        sys.exit(1)


def main():
    blender = os.environ.get("BLENDER", "blender")
    if shutil.which(blender) is None:
        skip("blender is not installed (./setup.sh test installs it)")
    if not os.path.exists(BAKE):
        skip("%s is absent" % BAKE)
    import numpy
    import vbl
    tmp = tempfile.mkdtemp(prefix="vbl-fire-frame-")
    subprocess.run([blender, "-b", "--factory-startup", "--python-exit-code", "1", "--python", BAKE, "--",
                    "--out", tmp, "--flow", "BOTH", "--frames", str(FRAMES), "--res", "32"],
                   check=True, stdout=subprocess.DEVNULL)
    vdb = os.path.join(tmp, "data", "fluid_data_%04d.vdb" % FRAMES)
    check(os.path.exists(vdb), "baked %d frames (%s)" % (FRAMES, vdb))
    with open(os.path.join(tmp, "floor.obj"), "w") as f:
        f.write("v -3 -3 0\nv 3 -3 0\nv 3 3 0\nv -3 3 0\nf 1 2 3\nf 1 3 4\n")
    scene = {
        "camera": {"position": [0.5, -2.2, 0.7], "look_at": [0.5, 0.5, 0.25], "up": [0, 0, 1], "fov_deg": 35,
                   "resolution": [24, 18]},
        "media": [{"vdb": vdb, "density_scale": 20, "albedo": 0.6,
                   "emission": {"grid": "flame", "color": [1.0, 0.45, 0.1], "scale": 4},
                   "temperature": {"grid": "temperature", "scale": 1500, "blackbody_intensity": 1}}],
        "surfaces": [{"mesh": "floor.obj", "material": {"type": "lambert", "albedo": 0.5}}],
        "render": {"passes": 1, "spp": 2, "seed": 3, "max_bounces": -1, "light_paths": 2048},
    }
    path = os.path.join(tmp, "fire.json")
    with open(path, "w") as f:
        json.dump(scene, f)
    for method in METHODS:
        out = os.path.join(tmp, method + ".exr")
        subprocess.run([os.path.join(BUILD, "bin", "vbl"), "render", path, "-o", out, "--method", method, "--threads", "2"],
                       check=True, stdout=subprocess.DEVNULL)
        exr = vbl.ExrFile(out)
        beauty = exr.layer("")[..., :3].astype(numpy.float64)
        names = [n for n in exr.layer_names if n in TRANSPORT]
        layers = {n: exr.layer(n)[..., :3].astype(numpy.float64) for n in names}
        total = sum(layers.values())
        finite = all(numpy.isfinite(v).all() and (v >= 0).all() for v in layers.values())
        check(finite and numpy.isfinite(beauty).all(), "%s: no NaN, Inf or negative pixel" % method)
        check(numpy.allclose(total, beauty, rtol=1e-5, atol=1e-9), "%s: the layers %s sum to the beauty"
              % (method, ", ".join(names)))
        means = {n: float(v.mean()) for n, v in layers.items()}
        print("  %s: %s" % (method, ", ".join("%s %.4g" % kv for kv in means.items())))
        lit = ["volume_emission", "volume_direct", "volume_from_volume"] + (["surface_direct"] if method != "beams" else [])
        check(all(means.get(n, 0.0) > 0.0 for n in lit), "%s: the fire is seen and lights %s" % (method, ", ".join(lit)))
    shutil.rmtree(tmp, ignore_errors=True)
    print("test_fire_frame: passed")


main()
