"""The Python binding (plugins/python/vbl) end to end through the shared library: struct layouts
against the C compiler's (abi_sizes), volumes (info, transmittance against the closed form of
box.vdb), scenes (render options, overrides), renders (layers sum to beauty, finite) and errors.
Run by ctest with PYTHONPATH, VBL_LIBRARY, VBL_FIXTURE_DIR and VBL_ABI_SIZES set; exits 77
(skipped) without numpy."""

import ctypes
import json
import math
import os
import subprocess
import sys
import tempfile
import unittest
import warnings

try:
    import numpy
except ImportError:
    print("test_python: SKIPPED: numpy is not installed (apt-get install python3-numpy)")
    sys.exit(77)

import vbl

FIXTURES = os.environ.get("VBL_FIXTURE_DIR", ".")
BOX = os.path.join(FIXTURES, "box.vdb")


def write_scene(folder, name="scene.json", **changes):
    """A 16x12 pt scene of box.vdb (density 0.5 on [0, 1.6]^3 world units)."""
    scene = {
        "camera": {"position": [0.75, -3.0, 0.75], "look_at": [0.75, 0.75, 0.75], "fov_deg": 40,
                   "resolution": [16, 12]},
        "lights": [{"type": "distant", "direction": [-0.3, 0.5, -0.8], "irradiance": [2.0, 1.8, 1.5]},
                   {"type": "environment", "radiance": [0.10, 0.12, 0.20]}],
        "media": [{"vdb": BOX, "density_scale": 3.0, "albedo": [0.9, 0.8, 0.7],
                   "phase": {"type": "hg", "g": 0.3}}],
        "render": {"method": "pt", "passes": 2, "spp": 1, "seed": 3, "max_bounces": 3},
    }
    for key, value in changes.items():
        scene[key] = value
    path = os.path.join(folder, name)
    with open(path, "w") as f:
        json.dump(scene, f)
    return path


class TestLayout(unittest.TestCase):
    def test_struct_sizes_and_offsets_match_c(self):
        helper = os.environ.get("VBL_ABI_SIZES")
        if not helper:
            self.skipTest("VBL_ABI_SIZES not set")
        structs = {"vbl_volume_load_options": vbl._VolumeLoadOptions, "vbl_volume_info": vbl._VolumeInfo,
                   "vbl_transmittance_options": vbl._TransmittanceOptions,
                   "vbl_transmittance_result": vbl._TransmittanceResult,
                   "vbl_scene_load_options": vbl._SceneLoadOptions, "vbl_render_progress": vbl._RenderProgress,
                   "vbl_render_option_info": vbl._OptionInfo, "vbl_film_stats": vbl._FilmStats,
                   "vbl_py_exr_options": vbl._native._ExrOptions}
        sizes = dict(vbl.STRUCT_SIZES, vbl_py_exr_options=ctypes.sizeof(vbl._native._ExrOptions))
        lines = subprocess.run([helper], check=True, stdout=subprocess.PIPE, universal_newlines=True).stdout
        checked = 0
        for line in lines.split("\n"):
            if not line.strip():
                continue
            name, value = line.split()
            if "." in name:
                struct, field = name.split(".")
                self.assertEqual(getattr(structs[struct], field).offset, int(value), name)
            else:
                self.assertEqual(sizes[name], int(value), name)
            checked += 1
        self.assertGreater(checked, 15)


class TestOptionsTable(unittest.TestCase):
    """The binding reads the library's options table instead of mirroring vbl_render_options."""

    def test_table_rows(self):
        rows = {row["name"]: row for row in vbl.RENDER_OPTIONS}
        self.assertEqual(tuple(rows), vbl.RENDER_OPTION_FIELDS)
        self.assertGreaterEqual(len(rows), 26)
        self.assertEqual(rows["vbl_alpha"]["key"], "vbl.alpha")
        self.assertEqual(rows["vbl_alpha"]["flag"], "--vbl-alpha")
        self.assertEqual(rows["vbl_alpha"]["type"], "double")
        self.assertEqual((rows["vbl_alpha"]["min"], rows["vbl_alpha"]["max"]), (0.0, 1.0))
        self.assertEqual(rows["passes"]["default"], 16.0)
        self.assertEqual(rows["method"]["choices"], ["pt", "vpl", "vrl", "vbl", "beams"])
        self.assertIsNone(rows["threads"]["key"])
        for row in rows.values():
            self.assertTrue(row["help"], row["name"])

    def test_defaults_set_get_round_trip(self):
        options = vbl._options.Options()
        values = options.to_dict()
        self.assertEqual(values["method"], "pt")
        self.assertEqual(values["passes"], 16)
        self.assertEqual(values["vsl_lights"], 1024)
        self.assertIs(values["vrl_long"], False)
        for name, value in [("vbl_alpha", 0.3), ("vrl_long", True), ("vsl_placement", "blue_noise"),
                            ("seed", 2 ** 63 + 5), ("transmittance", "delta"), ("max_bounces", 7)]:
            options.set(name, value)
            self.assertEqual(options.get(name), value, name)
        options.set("method", 2)  # an enum by its number
        self.assertEqual(options.get("method"), "vrl")
        with self.assertRaises(vbl.VblError) as raised:
            options.set("vbl_alpha", 1.0)
        self.assertIn("vbl_alpha = 1 is outside (0, 1)", raised.exception.message)
        self.assertEqual(options.get("vbl_alpha"), 0.3)  # unchanged by the failed set


class TestVolume(unittest.TestCase):
    def test_version(self):
        self.assertRegex(vbl.version(), r"^\d+\.\d+\.\d+")

    def test_info(self):
        volume = vbl.Volume(BOX)
        info = volume.info
        self.assertEqual(info["grid_name"], "density")
        self.assertEqual(info["active_voxels"], 16 ** 3)
        self.assertEqual(info["index_bbox_min"], [0, 0, 0])
        self.assertEqual(info["index_bbox_max"], [15, 15, 15])
        for v in info["voxel_size"]:
            self.assertAlmostEqual(v, 0.1, places=9)
        self.assertAlmostEqual(info["value_mean"], 0.5, places=6)
        self.assertTrue(info["file_path"].endswith("box.vdb"))
        self.assertAlmostEqual(volume.sample([0.75, 0.75, 0.75]), 0.5, places=6)

    def test_transmittance_closed_form(self):
        # Inside the box (index 1..14 on x at the centre) the trilinear density is exactly 0.5:
        # T = exp(-density_scale * 0.5 * length).
        volume = vbl.Volume(BOX)
        length = 1.3
        expected = math.exp(-2.0 * 0.5 * length)
        result = volume.transmittance([0.1, 0.75, 0.75], [1, 0, 0], 0.0, length, estimator="ratio",
                                      density_scale=2.0, samples=256, seed=7)
        self.assertGreater(result.lookups, 0)
        self.assertLess(abs(result.mean - expected), 4.0 * result.std_error + 1e-9,
                        "%r vs %g" % (result, expected))
        march = volume.transmittance([0.1, 0.75, 0.75], [1, 0, 0], 0.0, length, estimator="march",
                                     density_scale=2.0, samples=1)
        self.assertAlmostEqual(march.mean, expected, places=3)

    def test_errors(self):
        with self.assertRaises(vbl.VblError) as raised:
            vbl.Volume(os.path.join(FIXTURES, "does_not_exist.vdb"))
        self.assertEqual(raised.exception.result, "VBL_ERROR_FILE_NOT_FOUND")
        self.assertIn("does_not_exist.vdb", raised.exception.message)
        with self.assertRaises(vbl.VblError) as raised:
            vbl.Volume(BOX, grid="nope")
        self.assertEqual(raised.exception.result, "VBL_ERROR_GRID_NOT_FOUND")
        with self.assertRaises(vbl.VblError):
            vbl.Volume(BOX).transmittance([0, 0, 0], [1, 0, 0], 0, 1, estimator="bogus")


class TestRender(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory(prefix="vbl_python_")
        cls.scene_path = write_scene(cls.tmp.name)

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_render_options(self):
        scene = vbl.Scene(self.scene_path)
        self.assertEqual(scene.resolution, (16, 12))
        self.assertEqual(scene.medium_count, 1)
        options = scene.render_options()
        self.assertEqual(options["method"], "pt")
        self.assertEqual(options["passes"], 2)
        self.assertEqual(options["spp"], 1)
        self.assertEqual(options["seed"], 3)
        self.assertEqual(options["max_bounces"], 3)
        self.assertEqual(options["transmittance"], "ratio")
        self.assertEqual(options["vsl_placement"], "light_paths")
        self.assertEqual(set(options), set(vbl.RENDER_OPTION_FIELDS))

    def test_render_layers_sum_to_beauty(self):
        scene = vbl.Scene(self.scene_path)
        film = vbl.render(scene, threads=2)
        self.assertEqual((film.width, film.height), (16, 12))
        self.assertIn("", film.layer_names)
        beauty = film.layer("")
        self.assertEqual(beauty.dtype, numpy.float32)
        self.assertEqual(beauty.shape[:2], (12, 16))
        self.assertTrue(numpy.all(numpy.isfinite(beauty)))
        transport = [n for n in ("background", "volume_direct", "volume_from_volume") if n in film.layers]
        self.assertTrue(transport, film.layers)
        total = numpy.zeros((12, 16, 3), dtype=numpy.float32)
        for name in transport:  # the documented order: the sum is exact in float
            layer = film.layer(name)
            self.assertEqual(layer.shape, (12, 16, 3))
            self.assertTrue(numpy.all(numpy.isfinite(layer)))
            total = total + layer
        self.assertGreater(float(beauty[..., :3].sum()), 0.0)
        numpy.testing.assert_allclose(total, beauty[..., :3], rtol=1e-5, atol=1e-6)
        stats = film.stats
        self.assertEqual(stats["method"], "pt")
        self.assertEqual(stats["passes"], 2)
        with self.assertRaises(vbl.VblError):
            film.layer("no_such_layer")
        # The copy outlives the film.
        del film
        self.assertTrue(numpy.all(numpy.isfinite(beauty)))

    def test_overrides_change_stats(self):
        scene = vbl.Scene(self.scene_path)
        film = vbl.render(scene, passes=3, spp=2, seed=11, threads=1)
        stats = film.stats
        self.assertEqual(stats["passes"], 3)
        self.assertEqual(stats["spp"], 2)
        self.assertEqual(stats["seed"], 11)
        seen = []
        film = vbl.render(scene, passes=3, callback=lambda p: seen.append(p["pass"]) or p["pass"] >= 1)
        self.assertEqual(seen, [1])
        self.assertEqual(film.stats["passes"], 1)
        self.assertEqual(film.stats["cancelled"], 1)
        with self.assertRaises(vbl.VblError):
            vbl.render(scene, method="bogus")
        with self.assertRaises(vbl.VblError):
            vbl.render(scene, not_an_option=1)

    def test_render_limits_warn(self):
        # g 0.999 with vpl: one documented limit (vbl_render_limits), warned by render(); none for pt
        media = [{"vdb": BOX, "density_scale": 3.0, "albedo": [0.9, 0.8, 0.7], "phase": {"type": "hg", "g": 0.999}}]
        scene = vbl.Scene(write_scene(self.tmp.name, "forward.json", media=media))
        limits = vbl.render_limits(scene, method="vpl")
        self.assertEqual(len(limits), 1, limits)
        self.assertIn("media[0] phase g = 0.999", limits[0])
        self.assertIn("forward.json", limits[0])
        self.assertEqual(vbl.render_limits(scene), [])  # the scene's method: pt
        self.assertTrue(issubclass(vbl.LimitWarning, UserWarning))
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            film = vbl.render(scene, method="vpl", passes=1, light_paths=64, threads=1)
            self.assertEqual(film.stats["passes"], 1)  # the render still runs
            vbl.render(scene, passes=1, threads=1)
        raised = [w for w in caught if issubclass(w.category, vbl.LimitWarning)]
        self.assertEqual([str(w.message) for w in raised], limits)
        self.assertEqual(raised[0].filename, __file__)  # points at the caller's render()

    def test_merge_equals_single_render(self):
        # 1 + 3 passes merged = one render of 4, to float rounding (vbl_film_merge)
        scene = vbl.Scene(self.scene_path)
        single = vbl.render(scene, passes=4, seed=5, threads=2)
        parts = [vbl.render(scene, first_pass=1, passes=3, seed=5, threads=2),
                 vbl.render(scene, first_pass=0, passes=1, seed=5, threads=2)]
        merged = vbl.merge(parts)
        self.assertEqual(merged.stats["passes"], 4)
        self.assertEqual(merged.stats["first_pass"], 0)
        self.assertEqual(merged.layer_names, single.layer_names)
        for name in single.layer_names:
            if name in ("variance", "Z"):
                continue
            a, b = merged.layer(name), single.layer(name)
            if name == "samples":
                numpy.testing.assert_array_equal(a, b)
            else:
                numpy.testing.assert_allclose(a, b, rtol=4e-7, atol=0)
        transport = [n for n in vbl.TRANSPORT_LAYERS if n in merged.layers]
        self.assertGreaterEqual(len(transport), 2)
        total = numpy.zeros_like(merged.layer(transport[0]))
        for name in transport:
            total = total + merged.layer(name)
        numpy.testing.assert_array_equal(total, merged.layer("")[..., :3])  # exactly, in float
        with self.assertRaises(vbl.VblError) as raised:
            vbl.merge([parts[0], parts[0]])
        self.assertIn("overlaps", raised.exception.message)
        # a 1-pass checkpoint resumed to 4 passes
        resumed = vbl.resume(scene, parts[1], passes=4, seed=5, threads=2)
        self.assertEqual(resumed.stats["passes"], 4)
        numpy.testing.assert_allclose(resumed.layer(""), single.layer(""), rtol=4e-7, atol=0)

    def test_vdb_overrides(self):
        scene = vbl.Scene(self.scene_path, vdb_overrides=[os.path.join(FIXTURES, "box.nvdb")])
        self.assertTrue(scene.medium_path(0).endswith("box.nvdb"))
        with self.assertRaises(vbl.VblError) as raised:
            vbl.Scene(self.scene_path, vdb_overrides=[os.path.join(self.tmp.name, "missing.vdb")])
        self.assertIn("missing.vdb", raised.exception.message)

    def test_vdb_sequence_frame(self):
        import shutil
        shutil.copyfile(BOX, os.path.join(self.tmp.name, "seq.0007.vdb"))
        media = [{"vdb": "seq.####.vdb", "density_scale": 3.0}]
        path = write_scene(self.tmp.name, "seq.json", media=media)
        scene = vbl.Scene(path, frame=7)
        self.assertTrue(scene.medium_path(0).endswith("seq.0007.vdb"))
        with self.assertRaises(vbl.VblError) as raised:
            vbl.Scene(path)                      # a pattern needs a frame
        self.assertIn("media[0].vdb", raised.exception.message)
        with self.assertRaises(vbl.VblError) as raised:
            vbl.Scene(path, frame=8)             # a missing frame names the frame and the file
        self.assertEqual(raised.exception.result, "VBL_ERROR_FILE_NOT_FOUND")
        self.assertIn("frame 8", raised.exception.message)
        self.assertIn("seq.0008.vdb", raised.exception.message)

    def test_bad_scene_names_field(self):
        media = [{"vdb": BOX, "density_scale": 3.0, "albedo": [0.9, 0.8, 0.7],
                  "phase": {"type": "hg", "g": 1.2}}]
        path = write_scene(self.tmp.name, "bad.json", media=media)
        with self.assertRaises(vbl.VblError) as raised:
            vbl.Scene(path)
        self.assertEqual(raised.exception.result, "VBL_ERROR_SCENE")
        self.assertIn("media[0].phase.g", raised.exception.message)
        self.assertIn("bad.json", raised.exception.message)


if __name__ == "__main__":
    result = unittest.main(exit=False, verbosity=2).result
    failed = len(result.failures) + len(result.errors)
    skipped = len(result.skipped)
    print("%d passed, %d failed, %d skipped" % (result.testsRun - failed - skipped, failed, skipped))
    sys.exit(1 if failed or not result.wasSuccessful() else 0)
