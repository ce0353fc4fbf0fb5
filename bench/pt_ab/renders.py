"""Helpers of the pt A/B scripts (bench/pt_ab/run.py, bench/pt_direct_strata/run.py): render with
vbl and measure the child's CPU time, read an EXR's layers, rMAE against a reference."""
import os, resource, subprocess

import numpy as np
import OpenImageIO as oiio

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
VBL = os.path.join(ROOT, "build", "bin", "vbl")
LAYERS = ("beauty", "volume_direct", "volume_from_volume", "surface_direct", "surface_from_volume",
          "volume_from_surface", "surface_from_surface", "volume_emission")


def layers(path):
    buf = oiio.ImageBuf(path)
    px = buf.get_pixels(oiio.FLOAT)
    out = {}
    for i, name in enumerate(buf.spec().channelnames):
        lay, _, ch = name.rpartition(".")
        if ch in ("R", "G", "B"):
            out.setdefault(lay or "beauty", []).append(px[..., i].astype(np.float64))
    return {k: np.stack(v, -1) for k, v in out.items()}


def render(scene, out, extra):
    """extra: vbl flags; a NAME=VALUE token sets that environment variable (experiments), and
    VBL_BIN=path renders with another build's vbl (an A/B of two commits)."""
    env = dict(os.environ)
    flags = []
    for tok in extra:
        name, eq, value = tok.partition("=")
        if eq and name.isupper() and not name.startswith("-"):
            env[name] = value
        else:
            flags.append(tok)
    cmd = [env.pop("VBL_BIN", VBL), "render", scene, "-o", out] + flags  # VBL_BIN=path: another build
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def rmae(img, ref):
    s = np.abs(ref).sum()
    return float(np.abs(img - ref).sum() / s) if s > 0 else float("nan")
