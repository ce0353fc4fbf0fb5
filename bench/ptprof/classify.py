#!/usr/bin/python3
"""bench/ptprof/classify.py PROFILE.txt...: shares of a `perf report --no-children --sort dso,symbol`
listing by cost class of pt (issue 14, brief ptprof), matched on "dso symbol". Unknown symbols go
to 'other'. Functions inlined into others count where they were inlined."""
import re, sys

CLASSES = [
    ("grid lookups (trilinear, PNanoVDB, extinction eval)",
     r"vbl_grid_|vbl_extinction_eval|pnanovdb|trilinear"),
    ("majorant DDA (iterator init/clip/steps, ray bounds)",
     r"vbl_majorant_iter|vbl_extinction_iter|vbl_extinction_ray_bounds|vbl_dda"),
    ("trackers (free flight, ratio/delta loops, exp draws)", r"vbl_track|vbl_free_flight|vbl_transmittance_estimate$|vbl_exp_carry|vbl_medium_free_flight|__log1p|log1p"),
    ("unbiased-march shadow estimator", r"vbl_um_|vbl_transmittance_unbiased_march"),
    ("light sampling / equiangular NEE", r"vbl_light|vbl_pt_equiangular|vbl_equiangular|vbl_quad|vbl_pt_pick"),
    ("phase / BRDF sampling", r"vbl_hg_|vbl_medium_phase|vbl_mat_|vbl_material|phase"),
    ("surfaces (Embree)", r"rtc|embree|vbl_surfaces"),
    ("film / tiles / driver", r"vbl_film|vbl_render_with_estimator|vbl_tile|vbl_accum"),
    ("rng", r"vbl_rng|pcg"),
    ("allocation", r"malloc|free|calloc|_int_|realloc|memset|memcpy"),
    ("OpenMP runtime", r"libgomp|GOMP"),
    ("startup (dynamic linking, scene/volume load, majorant build)",
     r"ld-linux|_dl_|do_lookup|vbl_scene|vbl_volume|majorant_grid_build|nanovdb|openvdb|libtbb|kernel|\[k\]"),
    ("libm (exp, log, sincos, atan, fmax)", r"libm\.so"),
    ("path tracer body (pt_camera_sample)", r"vbl_pt_"),
]

def classify(path):
    shares = {}
    for line in open(path):
        m = re.match(r"\s+([0-9.]+)%\s+(\S+)\s+(\[[.k]\])\s+(\S+)", line)
        if not m:
            continue
        pct, sym = float(m.group(1)), m.group(2) + " " + m.group(3) + " " + m.group(4)
        name = "other"
        for cls, pat in CLASSES:
            if re.search(pat, sym):
                name = cls
                break
        shares[name] = shares.get(name, 0.0) + pct
    return shares

files = sys.argv[1:]
tables = [classify(f) for f in files]
names = [c for c, _ in CLASSES] + ["other"]
print("| class | " + " | ".join(f.split("/")[-1].replace(".txt", "") for f in files) + " |")
print("|---|" + "---|" * len(files))
for n in names:
    if any(t.get(n, 0) > 0 for t in tables):
        print(f"| {n} | " + " | ".join(f"{t.get(n, 0.0):.1f} %" for t in tables) + " |")
