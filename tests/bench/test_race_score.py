"""The Cycles race's scoring and scene mapping (bench/race_cycles/score.py, kit_scene.py) on tiny
synthetic images and the race scenes: every metric against a hand-computed value."""
import math
import os
import sys

try:
    import numpy as np
except ImportError:
    print("SKIPPED: numpy is not importable (apt-get install python3-numpy)")
    sys.exit(77)

SOURCE = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "..")
sys.path.insert(0, os.path.join(SOURCE, "bench", "race_cycles"))
import kit_scene  # noqa: E402
import score  # noqa: E402

FAILURES = []


def check(ok, message):
    print(("ok    " if ok else "FAIL  ") + message)
    if not ok:
        FAILURES.append(message)


ref = np.ones((2, 2, 3))
img = ref.copy()
img[0, 0] = [3.0, 1.0, 1.0]  # one channel off by 2: sum |d| = 2 of sum |ref| = 12
check(abs(score.rmae(img, ref) - 2.0 / 12.0) < 1e-12, "rmae = sum|img - ref| / sum|ref|")
check(math.isnan(score.rmae(img, np.zeros_like(ref))), "rmae of an all-zero reference is NaN")
check(abs(score.energy(img, ref) - 14.0 / 12.0) < 1e-12, "energy = sum img / sum ref")
h1, h2 = ref * 0.9, ref * 1.1  # mean 1, |h1 - h2| = 0.2 per channel
check(abs(score.floor_rmae(h1, h2) - 0.1) < 1e-12, "floor = sum|h1 - h2| / (2 sum|mean|)")

# fireflies: luminance above 10x the reference, the reference at least 1% of its mean
ref = np.full((4, 4, 3), 1.0)
ref[0, 0] = 0.0
img = ref.copy()
img[1, 1] = 10.5   # 10.5 > 10 x 1: counts
img[2, 2] = 9.5    # below 10x: does not
img[0, 0] = 0.05   # black reference pixel: base 0.01 x mean 15/16, 10x that = 0.094 > 0.05
check(score.fireflies(img, ref) == 1, "fireflies counts only pixels above 10x the reference")
img[0, 0] = 1.0    # now above 0.094
check(score.fireflies(img, ref) == 2, "a black reference pixel counts against 1% of the mean")

check(abs(score.equal_time_rmae(0.2, 4.0, 1.0) - 0.4) < 1e-12, "4x the CPU time: 2x the rMAE at the budget")
check(abs(score.time_to_rmae(0.2, 10.0, 0.1) - 40.0) < 1e-12, "halving rMAE takes 4x the time")

layers = {k: np.full((1, 1, 3), float(i + 1)) for i, k in enumerate(score.VBL_LAYERS)}
g = score.group_layers(layers)
check(float(g["diffuse_indirect"][0, 0, 0]) == 3.0 + 4.0, "diffuse_indirect = surface_from_surface + surface_from_volume")
check(float(g["volume_indirect"][0, 0, 0]) == 6.0 + 7.0, "volume_indirect = volume_from_surface + volume_from_volume")
del layers["surface_direct"]
check("diffuse_direct" not in score.group_layers(layers), "a pass without its classes is left out")

scenes = os.path.join(SOURCE, "bench", "scenes")
k = kit_scene.kit_scene(os.path.join(scenes, "race_cloud_ground.json"), "/x/cloud.vdb")
sun = k["lights"][0]
check(sun["direction_to_light"] == [0.4, -0.5, 0.8], "a distant light points to the light (-direction)")
check(sun["irradiance"] == 3.0 and abs(sun["color"][1] - 2.9 / 3.0) < 1e-12, "RGB irradiance -> max x colour")
check(k["camera"]["vfov_deg"] == 35.0 and k["camera"]["resolution"] == [128, 128], "camera fov and resolution")
check(k["medium"]["density_scale"] == 12.0 and k["medium"]["phase"]["g"] == 0.5, "medium density scale and g")
check(k["volume"]["object_to_world"][2][3] == 0.8, "medium transform")
check(os.path.isabs(k["surfaces"][0]["obj"]) and k["surfaces"][0]["obj"].endswith("samples/ground.obj"),
      "surface mesh path resolved against the scene file")
room = kit_scene.kit_scene(os.path.join(scenes, "race_room.json"), "/x/cloud.vdb")
check(room["lights"][0]["type"] == "point" and room["lights"][0]["intensity"] == 6.0, "point light intensity")
try:
    kit_scene.kit_scene(os.path.join(scenes, "race_spot_smoke.json"), "/x/cloud.vdb")
    check(False, "a spot light is refused")
except ValueError as e:
    check("lights[0].type" in str(e), "a spot light is refused, naming the field: " + str(e))

if FAILURES:
    print("%d FAILED" % len(FAILURES))
    sys.exit(1)
print("all passed")
