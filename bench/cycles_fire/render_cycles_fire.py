"""Render a libvbl fire scene (one emissive medium, optional Lambert floor) with Cycles (issue 15).

A thin adapter over the Cycles reference kit (../shared/tools/cycles-reference, imported by
relative path, not copied): it reads the libvbl scene JSON itself and builds the Cycles
equivalent with the kit's helpers (camera, render settings, floor, VDB object with the
half-voxel fix), plus a volume material whose emission follows libvbl's convention exactly.

libvbl emits sigma_a(x) Le(x) per unit length (docs/readme/emission.md "Convention") with
    sigma_a = (1 - albedo) * density_scale * density(x)
    Le      = emission.scale * emission.color * E(x) + blackbody_intensity * B(T(x) scale + offset)
Cycles' volume emission is a coefficient per unit length that does not depend on density, so
the material computes the product per shading point from the interpolated grids:
    Emission(strength = (1-a) D density(x) scale E(x), colour = emission.color)
  + Emission(strength = (1-a) D density(x) bi [kelvin > 0], colour = Blackbody(kelvin))
with kelvin = T(x) scale + offset; both added to a Principled Volume (Color = albedo,
Density = D, Absorption Color black, emission off) that gives sigma_s and sigma_a. Every
factor is interpolated (trilinearly) at the same point as in libvbl, so the mapping is exact
per voxel; only the blackbody colour differs: Cycles' Blackbody node is a fitted curve
normalised to luminance 1 (probe_blackbody.py measures it), compared with libvbl's
`normalization: "luminance"` (CIE 1931 Planck integral, Y = 1).

Run inside Blender 3.4:
    blender -b --factory-startup --python render_cycles_fire.py -- \
        --scene fire.json --spp 64 --out cycles.exr [--seed 0] [--threads 2]
Writes OUT (RGBA) and, like the kit's --passes, OUT.<pass>.exr for diffuse_direct,
diffuse_indirect, volume_direct, volume_indirect, emission (the kit's passes.py split).
"""
import argparse
import json
import os
import subprocess
import sys
import time

import bpy

HERE = os.path.dirname(os.path.abspath(__file__))
KIT = os.environ.get("VBL_CYCLES_KIT",
                     os.path.normpath(os.path.join(HERE, "..", "..", "..", "shared", "tools", "cycles-reference")))
sys.path.insert(0, KIT)
import cycles_common as cc  # noqa: E402


def parse():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    ap = argparse.ArgumentParser()
    ap.add_argument("--scene", required=True)
    ap.add_argument("--spp", type=int, required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--step-rate", type=float, default=1.0)
    return ap.parse_args(argv)


def scalar(v, what):
    if isinstance(v, (list, tuple)):
        if len(set(v)) != 1:
            raise ValueError(f"{what}: only grey values are mapped ({v})")
        return float(v[0])
    return float(v)


def node(nt, kind, **inputs):
    n = nt.nodes.new(kind)
    for k, v in inputs.items():
        if k == "operation":
            n.operation = v
        else:
            n.inputs[k].default_value = v
    return n


def attribute(nt, name):
    n = nt.nodes.new("ShaderNodeAttribute")
    n.attribute_type = "GEOMETRY"
    n.attribute_name = name
    return n.outputs["Fac"]


def multiply(nt, a, b):
    m = node(nt, "ShaderNodeMath", operation="MULTIPLY")
    for i, x in enumerate((a, b)):
        if isinstance(x, (int, float)):
            m.inputs[i].default_value = float(x)
        else:
            nt.links.new(x, m.inputs[i])
    return m.outputs["Value"]


def fire_material(med):
    """Principled Volume (scattering, absorption) + the two emission terms of libvbl's convention."""
    D = float(med.get("density_scale", 1.0))
    a = scalar(med.get("albedo", 0.5), "albedo")
    g = float(med.get("phase", {}).get("g", 0.0)) if isinstance(med.get("phase"), dict) else 0.0
    mat = cc.principled_volume_material("fire", density_scale=D, albedo=a, g=g, absorption_color=0.0,
                                        interpolation="LINEAR", density_attribute=med.get("grid", "density"))
    nt = mat.node_tree
    out = next(n for n in nt.nodes if n.bl_idname == "ShaderNodeOutputMaterial")
    pv = next(n for n in nt.nodes if n.bl_idname == "ShaderNodeVolumePrincipled")
    sigma_a = multiply(nt, attribute(nt, med.get("grid", "density")), (1.0 - a) * D)
    shader = pv.outputs["Volume"]
    em = med.get("emission")
    if em:
        c = em.get("color", 1.0)
        c = tuple(float(x) for x in c) if isinstance(c, (list, tuple)) else (float(c),) * 3
        e = nt.nodes.new("ShaderNodeEmission")
        e.inputs["Color"].default_value = (c[0], c[1], c[2], 1.0)
        strength = multiply(nt, multiply(nt, sigma_a, attribute(nt, em.get("grid", "flame"))), float(em.get("scale", 1.0)))
        nt.links.new(strength, e.inputs["Strength"])
        add = nt.nodes.new("ShaderNodeAddShader")
        nt.links.new(shader, add.inputs[0])
        nt.links.new(e.outputs["Emission"], add.inputs[1])
        shader = add.outputs["Shader"]
    te = med.get("temperature")
    if te:
        if te.get("normalization", "peak") != "luminance":
            raise ValueError("temperature.normalization must be 'luminance' (Cycles' Blackbody node colour)")
        kelvin = node(nt, "ShaderNodeMath", operation="MULTIPLY_ADD")
        nt.links.new(attribute(nt, te.get("grid", "temperature")), kelvin.inputs[0])
        kelvin.inputs[1].default_value = float(te.get("scale", 1.0))
        kelvin.inputs[2].default_value = float(te.get("offset", 0.0))
        hot = node(nt, "ShaderNodeMath", operation="GREATER_THAN")
        nt.links.new(kelvin.outputs["Value"], hot.inputs[0])
        hot.inputs[1].default_value = 0.0           # libvbl: kelvin <= 0 emits nothing
        bb = nt.nodes.new("ShaderNodeBlackbody")
        nt.links.new(kelvin.outputs["Value"], bb.inputs["Temperature"])
        e = nt.nodes.new("ShaderNodeEmission")
        nt.links.new(bb.outputs["Color"], e.inputs["Color"])
        strength = multiply(nt, multiply(nt, sigma_a, hot.outputs["Value"]), float(te.get("blackbody_intensity", 1.0)))
        nt.links.new(strength, e.inputs["Strength"])
        add = nt.nodes.new("ShaderNodeAddShader")
        nt.links.new(shader, add.inputs[0])
        nt.links.new(e.outputs["Emission"], add.inputs[1])
        shader = add.outputs["Shader"]
    nt.links.new(shader, out.inputs["Volume"])
    return mat


def main():
    a = parse()
    scene_path = os.path.abspath(a.scene)
    base = os.path.dirname(scene_path)
    sd = json.load(open(scene_path))
    cam = sd["camera"]
    W, H = cam["resolution"]
    r = sd.get("render", {})
    if len(sd["media"]) != 1 or sd.get("lights"):
        raise ValueError("one emissive medium and no lights are mapped")
    mb = r.get("max_bounces", -1)
    bounces = 128 if mb is None or mb < 0 else int(mb)
    scene = cc.reset_scene()
    cc.setup_render(scene, spp=a.spp, seed=a.seed, threads=a.threads, width=W, height=H,
                    volume_bounces=bounces, diffuse_bounces=bounces if sd.get("surfaces") else 0,
                    volume_step_rate=a.step_rate, volume_max_steps=4096)
    cc.black_world(scene)
    cc.add_camera(scene, {"position": cam["position"], "look_at": cam["look_at"], "up": cam.get("up", [0, 0, 1]),
                          "vfov_deg": cam.get("fov_deg", 40.0)})
    for k, s in enumerate(sd.get("surfaces", [])):
        m = s["material"]
        if m["type"] != "lambert" or "transform" in s:
            raise ValueError("surfaces: only untransformed Lambert meshes are mapped")
        cc.add_obj_surface(scene, os.path.normpath(os.path.join(base, s["mesh"])),
                           cc.lambert_material(f"lambert{k}", m["albedo"]), name=f"surface{k}")
    med = sd["media"][0]
    if "transform" in med:
        raise ValueError("media[0].transform is not mapped")
    vdb = os.path.normpath(os.path.join(base, med["vdb"]))
    cc.add_vdb_volume(scene, vdb, fire_material(med), grid_name=med.get("grid", "density"))
    out = os.path.abspath(a.out)
    stem = out[:-4] if out.lower().endswith(".exr") else out
    cc.enable_light_passes(scene)
    t0 = time.time()
    cc.render_to(scene, stem + ".layers.exr")
    dt = time.time() - t0
    py = os.environ.get("PYTHON3", "/usr/bin/python3")
    p = subprocess.run([py, os.path.join(KIT, "passes.py"), "split", stem + ".layers.exr", out, "--delete"],
                       capture_output=True, text=True)
    print(p.stdout)
    if p.returncode != 0:
        print(p.stderr, file=sys.stderr)
        raise RuntimeError("passes.py split failed")
    json.dump({"scene": scene_path, "spp": a.spp, "seed": a.seed, "render_wall_seconds": dt,
               "volume_step_rate": a.step_rate, "bounces": bounces, "blender": bpy.app.version_string,
               "passes": json.loads(p.stdout.strip().splitlines()[-1])}, open(out + ".json", "w"), indent=1)
    print(f"RENDER_WALL_SECONDS {dt:.3f}")


if __name__ == "__main__":
    try:
        main()
    except Exception as e:  # a clear message and a non-zero exit from blender -b
        import traceback
        traceback.print_exc()
        print(f"render_cycles_fire: {e}", file=sys.stderr)
        sys.exit(1)
