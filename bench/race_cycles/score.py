"""Scoring of the Cycles race (bench/race_cycles): layers of a vbl or Cycles EXR, and the error
metrics of issues #13 and #14.

- rMAE(img, ref) = sum |img - ref| / sum |ref| over every pixel and RGB channel (the metric of
  bench/bench_reference.c: an image-wide relative L1 error, so dark pixels do not dominate).
- the reference's own error (its floor) from two independent halves h1, h2 of it:
  sum |h1 - h2| / (2 sum |ref|) (for independent noise, the mean of the halves has half the
  spread of their difference).
- energy(img, ref) = sum img / sum ref.
- fireflies(img, ref) = pixels whose luminance is above 10x the reference's, the reference taken
  as at least 1% of its mean luminance (so black reference pixels do not count every speck).
"""
import os

import numpy as np

# Cycles' light passes (the kit's --passes) as sums of vbl's transport layers (docs/readme/output.md)
CYCLES_GROUPS = {
    "beauty": ["beauty"],
    "diffuse_direct": ["surface_direct"],
    "diffuse_indirect": ["surface_from_surface", "surface_from_volume"],
    "volume_direct": ["volume_direct"],
    "volume_indirect": ["volume_from_surface", "volume_from_volume"],
}
VBL_LAYERS = ["beauty", "surface_direct", "surface_from_surface", "surface_from_volume", "volume_direct",
              "volume_from_surface", "volume_from_volume"]
LUMA = np.array([0.2126, 0.7152, 0.0722])


def read_vbl_layers(path):
    """{layer: (H, W, 3) float64} of a vbl render's EXR; the beauty is R, G, B."""
    import OpenImageIO as oiio
    inp = oiio.ImageInput.open(path)
    if inp is None:
        raise IOError(f"{path}: {oiio.geterror()}")
    spec = inp.spec()
    px = np.asarray(inp.read_image(0, 0, 0, spec.nchannels, "float"), dtype=np.float64)
    inp.close()
    px = px.reshape(spec.height, spec.width, spec.nchannels)
    names = list(spec.channelnames)
    out = {}
    for layer in VBL_LAYERS:
        prefix = "" if layer == "beauty" else layer + "."
        keys = [prefix + c for c in "RGB"]
        if all(k in names for k in keys):
            out[layer] = np.stack([px[:, :, names.index(k)] for k in keys], axis=-1)
    return out


def read_cycles_layers(path):
    """{cycles pass: (H, W, 3)} of the kit's render.sh --passes output (OUT.exr + OUT.<pass>.exr)."""
    layers = {"beauty": read_vbl_layers(path)["beauty"]}
    stem = path[:-4] if path.endswith(".exr") else path
    for name in CYCLES_GROUPS:
        if name != "beauty" and os.path.exists(f"{stem}.{name}.exr"):
            layers[name] = read_vbl_layers(f"{stem}.{name}.exr")["beauty"]
    return layers


def group_layers(layers):
    """vbl layers -> Cycles passes (sums of the classes); a pass none of whose classes is present
    is left out."""
    out = {}
    for name, parts in CYCLES_GROUPS.items():
        have = [layers[p] for p in parts if p in layers]
        if have:
            out[name] = sum(have)
    return out


def rmae(img, ref):
    s = float(np.abs(ref).sum())
    return float(np.abs(img - ref).sum()) / s if s > 0 else float("nan")


def floor_rmae(h1, h2):
    s = float(np.abs(0.5 * (h1 + h2)).sum())
    return float(np.abs(h1 - h2).sum()) / (2.0 * s) if s > 0 else float("nan")


def energy(img, ref):
    s = float(ref.sum())
    return float(img.sum()) / s if s != 0 else float("nan")


def fireflies(img, ref, factor=10.0):
    li, lr = img @ LUMA, ref @ LUMA
    base = np.maximum(lr, 0.01 * float(lr.mean()))
    return int(np.count_nonzero(li > factor * base))


def equal_time_rmae(value, cpu, budget):
    """rMAE moved to the budget's CPU time by the 1/sqrt(t) law of an unbiased estimator (used
    only to correct the small mismatch between a run's CPU time and the budget)."""
    return value * (cpu / budget) ** 0.5 if cpu > 0 and budget > 0 else value


def time_to_rmae(value, cpu, target):
    """CPU seconds to reach `target` by the same 1/sqrt(t) law."""
    return cpu * (value / target) ** 2
