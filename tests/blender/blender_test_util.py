"""What the Blender add-on tests share: paths from the command line, pass/fail bookkeeping,
rendering a scene to an EXR, the comparison with Cycles (mean and brightness centroid)."""

import math
import os
import sys

import bpy

SOURCE, BUILD = sys.argv[sys.argv.index("--") + 1:][:2]
sys.path[:0] = [os.path.join(SOURCE, "plugins", "blender"), os.path.join(BUILD, "python"),
                os.path.join(SOURCE, "..", "shared", "tools", "cycles-reference")]
os.environ.setdefault("VBL_LIBRARY", os.path.join(BUILD, "libvbl", "libvbl.so"))
# more samples on both sides for measuring the agreement (the tests' tolerances hold at 1)
SCALE = int(os.environ.get("VBL_TEST_SCALE", "4"))

try:
    import numpy  # noqa: F401
except ImportError:
    print("SKIPPED: numpy is not importable in Blender's Python (apt-get install python3-numpy)")
    sys.exit(77)

FAILURES = []


def check(condition, message):
    print(("ok    " if condition else "FAIL  ") + message)
    if not condition:
        FAILURES.append(message)


def finish(name):
    if FAILURES:
        print("%s: %d FAILED" % (name, len(FAILURES)))
        sys.exit(1)
    print("%s: all passed" % name)
    sys.exit(0)


def black_world(scene):
    world = bpy.data.worlds.new("black")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
    scene.world = world


def principled_volume(name, density, color, g, attribute="density"):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nodes = mat.node_tree.nodes
    for node in list(nodes):
        nodes.remove(node)
    out = nodes.new("ShaderNodeOutputMaterial")
    pv = nodes.new("ShaderNodeVolumePrincipled")
    pv.inputs["Color"].default_value = tuple(color) + (1.0,)
    pv.inputs["Density"].default_value = density
    pv.inputs["Density Attribute"].default_value = attribute
    pv.inputs["Anisotropy"].default_value = g
    pv.inputs["Absorption Color"].default_value = (0.0, 0.0, 0.0, 1.0)
    mat.node_tree.links.new(pv.outputs["Volume"], out.inputs["Volume"])
    mat.cycles.volume_interpolation = "LINEAR"
    return mat


def render_to(scene, path, file_format):
    scene.render.filepath = path
    scene.render.use_file_extension = False
    image = scene.render.image_settings
    image.file_format, image.color_depth = file_format, "32"
    if file_format == "OPEN_EXR":
        image.color_mode = "RGBA"
    image.exr_codec = "ZIP"
    bpy.ops.render.render(write_still=True)


def centroid(rgb):
    """The brightness-weighted centroid (column, row) in pixels."""
    import numpy
    weight = rgb.mean(axis=-1)
    rows, cols = numpy.mgrid[0:weight.shape[0], 0:weight.shape[1]]
    return float((weight * cols).sum() / weight.sum()), float((weight * rows).sum() / weight.sum())


def compare_with_cycles(scene, vbl_beauty, path, spp, volume_bounces, tolerance, centroid_tolerance):
    """Renders `scene` with Cycles (the reference kit's unbiased settings) and checks the image mean
    and centroid against vbl's beauty. Returns (ratio, centroid distance)."""
    import numpy
    import cycles_common
    import vbl
    r = scene.render
    width, height, percentage = r.resolution_x, r.resolution_y, r.resolution_percentage
    cycles_common.setup_render(scene, spp=spp, seed=0, threads=2, width=width, height=height,
                               volume_bounces=volume_bounces)  # vbl max_bounces = Cycles volume_bounces + 1
    r.resolution_percentage = percentage
    render_to(scene, path, "OPEN_EXR")
    cycles = vbl.ExrFile(path).layer("")[..., :3]
    mine = vbl_beauty[..., :3]
    vbl_mean, cycles_mean = float(numpy.mean(mine)), float(numpy.mean(cycles))
    ratio = vbl_mean / cycles_mean if cycles_mean > 0 else float("inf")
    check(abs(ratio - 1.0) < tolerance, "mean vbl %.6g / Cycles %.6g = %.4f (tolerance %.2f)"
          % (vbl_mean, cycles_mean, ratio, tolerance))
    (vx, vy), (cx, cy) = centroid(mine), centroid(cycles)
    distance = math.hypot(vx - cx, vy - cy)
    check(distance < centroid_tolerance, "centroid vbl (%.3f, %.3f) px, Cycles (%.3f, %.3f) px, %.3f apart "
          "(tolerance %.2f px)" % (vx, vy, cx, cy, distance, centroid_tolerance))
    print("BLENDER_TEST_MEANS vbl %.6g cycles %.6g ratio %.4f centroid_distance %.4f"
          % (vbl_mean, cycles_mean, ratio, distance))
    return ratio, distance
