#!/usr/bin/python3
"""libvbl pt against Cycles on a Mantaflow fire frame (issue 15): mean per layer with error bars.

Bakes a small fire with the Cycles kit's bake_gas.py (or takes --vdb), pads its grids with active
zero voxels (pad_vdb.py), writes a libvbl scene (flame as emission, temperature as blackbody with
`normalization: "luminance"`), renders it K times with libvbl pt and K times with Cycles
(render_cycles_fire.py, the emission mapped per shading point), and compares per layer
    volume_emission <-> Cycles Emit        (fire seen directly)
    volume_direct   <-> Cycles VolumeDir   (fire light scattered once)
    volume_from_volume <-> Cycles VolumeInd (scattered two or more times)
    beauty          <-> Combined
the image means (RGB summed), with the standard error of each mean from the spread of its K
independent renders. Writes RESULTS.txt and a side-by-side PNG (libvbl | Cycles, sRGB).
Not run by CI (5-10 min on 2 cores): a benchmark, results in bench/results/, documented in
docs/readme/emission.md "Comparison with Cycles". The default Cycles step rate is 0.25: at 1
(Cycles' default) its ray-marching bias makes the scattered fire light 4-6 % low on this frame.

    /usr/bin/python3 bench/cycles_fire/compare_fire.py --build build --runs 3 --cycles-spp 512 \
        --results bench/results/cycles_fire_issue15_step025.txt
"""
import argparse
import json
import math
import os
import shutil
import sys
import subprocess
import tempfile
import time

import numpy as np
import OpenImageIO as oiio

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
KIT = os.environ.get("VBL_CYCLES_KIT", os.path.normpath(os.path.join(ROOT, "..", "shared", "tools", "cycles-reference")))
PAIRS = (("volume_emission", "emission"), ("volume_direct", "volume_direct"),
         ("volume_from_volume", "volume_indirect"), ("", None))
# acceptance (docs/readme/emission.md "Comparison with Cycles"): |ratio - 1| within this and |z| <= 2
TOLERANCE = {"volume_emission": 0.01, "volume_direct": 0.03, "volume_from_volume": 0.03, "": 0.01}


def read(path, layer=""):
    inp = oiio.ImageInput.open(path)
    if inp is None:
        raise IOError("%s: %s" % (path, oiio.geterror()))
    s = inp.spec()
    a = np.asarray(inp.read_image(0, 0, 0, s.nchannels, "float")).reshape(s.height, s.width, s.nchannels)
    inp.close()
    names = list(s.channelnames)
    pre = layer + "." if layer else ""
    return a[:, :, [names.index(pre + c) for c in "RGB"]].astype(np.float64)


def blender(args, log):
    cmd = [os.environ.get("BLENDER", "blender"), "-b", "--factory-startup", "--python-exit-code", "1", "--python"] + args
    with open(log, "w") as f:
        subprocess.run(cmd, check=True, stdout=f, stderr=subprocess.STDOUT)


def srgb(x):
    x = np.clip(x, 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--vdb", help="a fire frame (default: bake one with bake_gas.py)")
    ap.add_argument("--runs", type=int, default=4, help="independent renders per renderer")
    ap.add_argument("--vbl-spp", type=int, default=1024)
    ap.add_argument("--cycles-spp", type=int, default=1024)
    ap.add_argument("--res", default="48x36")
    ap.add_argument("--step-rate", type=float, default=0.25, help="Cycles volume step rate (step = voxel x rate)")
    ap.add_argument("--exposure", type=float, default=5.0, help="PNG exposure multiplier")
    ap.add_argument("--results")
    ap.add_argument("--png")
    ap.add_argument("--keep", action="store_true")
    a = ap.parse_args()
    W, H = (int(v) for v in a.res.split("x"))
    tmp = tempfile.mkdtemp(prefix="vbl-cycles-fire-")
    t0 = time.time()
    vdb = a.vdb
    if vdb is None:
        blender([os.path.join(KIT, "bake_gas.py"), "--", "--out", tmp, "--flow", "BOTH", "--frames", "12", "--res", "32"],
                os.path.join(tmp, "bake.log"))
        vdb = os.path.join(tmp, "data", "fluid_data_0012.vdb")
    padded = os.path.join(tmp, "fire_padded.vdb")
    blender([os.path.join(HERE, "pad_vdb.py"), "--", vdb, padded, "2"], os.path.join(tmp, "pad.log"))
    scene = {
        "camera": {"position": [0.5, -2.2, 0.7], "look_at": [0.5, 0.5, 0.25], "up": [0, 0, 1], "fov_deg": 20,
                   "resolution": [W, H]},
        "media": [{"vdb": padded, "density_scale": 20, "albedo": 0.6,
                   "emission": {"grid": "flame", "color": [1.0, 0.45, 0.1], "scale": 4},
                   "temperature": {"grid": "temperature", "scale": 1500, "offset": 1000, "blackbody_intensity": 1,
                                   "normalization": "luminance"}}],
        "render": {"passes": 1, "spp": a.vbl_spp, "seed": 0, "max_bounces": -1},
    }
    vbl_imgs, cyc_imgs = [], []
    for k in range(a.runs):
        scene["render"]["seed"] = 1000 + k
        sp = os.path.join(tmp, "fire_%d.json" % k)
        json.dump(scene, open(sp, "w"), indent=1)
        out = os.path.join(tmp, "vbl_%d.exr" % k)
        subprocess.run([os.path.join(a.build, "bin", "vbl"), "render", sp, "-o", out, "--method", "pt", "--threads", "2"],
                       check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        vbl_imgs.append({l: read(out, l) for l, _ in PAIRS})
        cout = os.path.join(tmp, "cycles_%d.exr" % k)
        blender([os.path.join(HERE, "render_cycles_fire.py"), "--", "--scene", sp, "--spp", str(a.cycles_spp),
                 "--seed", str(k), "--step-rate", str(a.step_rate), "--out", cout], os.path.join(tmp, "cycles_%d.log" % k))
        stem = cout[:-4]
        cyc_imgs.append({l: read(cout if p is None else "%s.%s.exr" % (stem, p)) for l, p in PAIRS})
    lines = ["# libvbl pt vs Cycles 3.4 on a Mantaflow fire frame (bake_gas.py --flow BOTH --frames 12 --res 32,",
             "# frame 12, grids padded by 2 active zero voxels), %dx%d, %d runs each: libvbl %d spp, Cycles %d spp,"
             % (W, H, a.runs, a.vbl_spp, a.cycles_spp),
             "# Cycles volume step rate %g (ray-marching step = voxel size x rate)" % a.step_rate,
             "# scene: " + json.dumps({k: v for k, v in scene["media"][0].items() if k != "vdb"}),
             "# mean = image mean of R+G+B over the runs; se = standard error from the runs' spread",
             "%-20s %12s %10s %12s %10s %8s %6s %s" % ("layer", "libvbl", "se", "cycles", "se", "ratio", "z", "ok")]
    failed = []
    for l, _ in PAIRS:
        v = np.array([im[l].sum(axis=2).mean() for im in vbl_imgs])
        c = np.array([im[l].sum(axis=2).mean() for im in cyc_imgs])
        vs, cs = v.std(ddof=1) / math.sqrt(len(v)), c.std(ddof=1) / math.sqrt(len(c))
        z = (c.mean() - v.mean()) / math.sqrt(vs * vs + cs * cs) if vs + cs > 0 else 0.0
        ok = abs(c.mean() / v.mean() - 1.0) <= TOLERANCE[l] and abs(z) <= 2.0
        if not ok:
            failed.append(l or "beauty")
        lines.append("%-20s %12.6g %10.3g %12.6g %10.3g %8.4f %6.2f %s" % (l or "beauty", v.mean(), vs, c.mean(), cs,
                                                                           c.mean() / v.mean(), z, "ok" if ok else "FAIL"))
    lines.append("# wall %.0f s (bake, pad, %d libvbl renders, %d Cycles runs incl. Blender start-up)"
                 % (time.time() - t0, a.runs, a.runs))
    text = "\n".join(lines) + "\n"
    print(text, end="")
    if a.results:
        with open(a.results, "w") as f:
            f.write(text)
    if a.png:
        left = np.mean([im[""] for im in vbl_imgs], axis=0)
        right = np.mean([im[""] for im in cyc_imgs], axis=0)
        gap = np.ones((H, 2, 3))
        img = srgb(np.concatenate([left, gap, right], axis=1) * a.exposure)
        img = np.repeat(np.repeat(img, 4, axis=0), 4, axis=1)  # 4x nearest, to be seen
        spec = oiio.ImageSpec(img.shape[1], img.shape[0], 3, "uint8")
        o = oiio.ImageOutput.create(a.png)
        o.open(a.png, spec)
        o.write_image(np.ascontiguousarray((img * 255 + 0.5).astype(np.uint8)))
        o.close()
    if not a.keep:
        shutil.rmtree(tmp, ignore_errors=True)
    else:
        print("kept " + tmp)
    if failed:
        print("compare_fire: outside the tolerance: " + ", ".join(failed))
        sys.exit(1)


if __name__ == "__main__":
    main()
