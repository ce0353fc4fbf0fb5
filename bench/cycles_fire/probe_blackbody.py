"""What Cycles' Blackbody node returns (issue 15): one emissive quad per temperature seen
head-on by an orthographic camera, one pixel each, so each pixel is the node's colour exactly
(Emission strength 1). Prints per temperature the Rec.709 RGB, its luminance Y and CIE 1931 xy
(via the IEC 61966-2-1 matrix), as one JSON line "BLACKBODY {...}".

    blender -b --factory-startup --python probe_blackbody.py -- OUT_DIR
"""
import json
import os
import sys

import bpy

HERE = os.path.dirname(os.path.abspath(__file__))
KIT = os.environ.get("VBL_CYCLES_KIT",
                     os.path.normpath(os.path.join(HERE, "..", "..", "..", "shared", "tools", "cycles-reference")))
sys.path.insert(0, KIT)
import cycles_common as cc  # noqa: E402
from exr_io import read_exr  # noqa: E402

TEMPERATURES = (1000, 1500, 2000, 2500, 3000, 4000, 5000, 6500, 8000, 10000)
H = 0.1  # quad and pixel size, metres


def main():
    out_dir = sys.argv[sys.argv.index("--") + 1]
    scene = cc.reset_scene()
    cc.setup_render(scene, spp=1, width=1, height=1, volume_bounces=0)
    cc.black_world(scene)
    cc.add_camera(scene, {"type": "orthographic", "ortho_height": H, "position": [0.0, -1.0, 0.0],
                          "look_at": [0.0, 0.0, 0.0], "up": [0, 0, 1]})
    mat = bpy.data.materials.new("blackbody")
    mat.use_nodes = True
    nt = mat.node_tree
    for nd in list(nt.nodes):
        nt.nodes.remove(nd)
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    bb = nt.nodes.new("ShaderNodeBlackbody")
    em = nt.nodes.new("ShaderNodeEmission")
    em.inputs["Strength"].default_value = 1.0
    nt.links.new(bb.outputs["Color"], em.inputs["Color"])
    nt.links.new(em.outputs["Emission"], out.inputs["Surface"])
    verts = [(-H, 0, -H), (H, 0, -H), (H, 0, H), (-H, 0, H)]  # covers the single pixel
    cc.add_mesh(scene, "quad", verts, [(0, 1, 2, 3)], mat)
    rows = {}
    for t in TEMPERATURES:
        bb.inputs["Temperature"].default_value = float(t)
        path = os.path.join(out_dir, "blackbody_%d.exr" % t)
        cc.render_to(scene, path)
        r, g, b = (float(v) for v in read_exr(path)[0, 0])
        X = 0.4124 * r + 0.3576 * g + 0.1805 * b
        Y = 0.2126 * r + 0.7152 * g + 0.0722 * b
        Z = 0.0193 * r + 0.1192 * g + 0.9505 * b
        s = X + Y + Z
        rows[t] = {"rgb": [r, g, b], "Y": Y, "x": X / s if s > 0 else 0.0, "y": Y / s if s > 0 else 0.0}
    print("BLACKBODY " + json.dumps(rows))

main()
