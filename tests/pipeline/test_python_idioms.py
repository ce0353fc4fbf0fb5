"""The idiomatic face of the Python package (issue 17 part 4): builtin exception bases, close() and
context managers, Ctrl-C with and without a callback keeping the complete passes, the cancel
argument, Scene.from_dict, colour-managed loading, transport layers apart from AOVs, and
Film.write_exr against `vbl render` attribute by attribute. Run by ctest with PYTHONPATH,
VBL_LIBRARY, VBL_FIXTURE_DIR and VBL_CLI; exits 77 (skipped) without numpy."""

import json
import os
import signal
import subprocess
import sys
import tempfile
import threading
import unittest

try:
    import numpy
except ImportError:
    print("test_python_idioms: SKIPPED: numpy is not installed (apt-get install python3-numpy)")
    sys.exit(77)

import vbl

FIXTURES = os.environ.get("VBL_FIXTURE_DIR", ".")
BOX = os.path.join(FIXTURES, "box.vdb")


def scene_dict(**changes):
    """A 12x8 pt scene of box.vdb (density 0.5 on [0, 1.6]^3) lit by a sun and a sky."""
    scene = {
        "camera": {"position": [0.75, -3.0, 0.75], "look_at": [0.75, 0.75, 0.75], "fov_deg": 40,
                   "resolution": [12, 8]},
        "lights": [{"type": "distant", "direction": [-0.3, 0.5, -0.8], "irradiance": [2.0, 1.8, 1.5]},
                   {"type": "environment", "radiance": [0.10, 0.12, 0.20]}],
        "media": [{"vdb": "box.vdb", "density_scale": 3.0, "albedo": [0.9, 0.8, 0.7],
                   "phase": {"type": "hg", "g": 0.3}}],
        "render": {"method": "pt", "passes": 2, "spp": 1, "seed": 3, "max_bounces": 3},
    }
    scene.update(changes)
    return scene


def same_film(test, a, b):
    test.assertEqual(a.layer_names, b.layer_names)
    for name in a.layer_names:
        numpy.testing.assert_array_equal(a.layer(name), b.layer(name), err_msg=name)


class TestErrors(unittest.TestCase):
    def test_builtin_bases(self):
        with self.assertRaises(FileNotFoundError) as raised:
            vbl.Volume(os.path.join(FIXTURES, "missing.vdb"))
        self.assertIsInstance(raised.exception, vbl.VblError)
        self.assertEqual(raised.exception.result, "VBL_ERROR_FILE_NOT_FOUND")
        self.assertIn("missing.vdb", str(raised.exception))
        with self.assertRaises(LookupError):
            vbl.Volume(BOX, grid="nope")
        with self.assertRaises(ValueError) as raised:
            vbl.Scene.from_dict(scene_dict(media=[{"vdb": "box.vdb", "phase": {"type": "hg", "g": 1.2}}]),
                                base_dir=FIXTURES)
        self.assertIsInstance(raised.exception, vbl.SceneError)
        self.assertIn("media[0].phase.g", raised.exception.message)
        with vbl.Scene.from_dict(scene_dict(), base_dir=FIXTURES) as scene:
            with self.assertRaises(ValueError):
                vbl.render(scene, passes=0)
        self.assertFalse(issubclass(vbl.RenderInterrupted, Exception))
        self.assertTrue(issubclass(vbl.RenderInterrupted, KeyboardInterrupt))


class TestLifetime(unittest.TestCase):
    def test_close_and_context_managers(self):
        with vbl.Scene.from_dict(scene_dict(), base_dir=FIXTURES) as scene:
            path = scene.path
            self.assertTrue(os.path.exists(path))
            with vbl.render(scene) as film:
                self.assertEqual(film.width, 12)
            self.assertTrue(film.closed)
            with self.assertRaises(ValueError):
                film.layer("")
            film.close()  # idempotent
        self.assertTrue(scene.closed)
        self.assertFalse(os.path.exists(path))  # the temporary scene file went with it
        volume = vbl.Volume(BOX)
        volume.close()
        with self.assertRaises(vbl.InvalidArgument):
            volume.info


class TestSceneFromDict(unittest.TestCase):
    def test_same_film_as_the_file(self):
        with tempfile.TemporaryDirectory() as tmp:
            data = scene_dict()
            data["media"][0]["vdb"] = BOX
            path = os.path.join(tmp, "scene.json")
            with open(path, "w") as f:
                json.dump(data, f)
            with vbl.Scene(path) as a, vbl.Scene.from_dict(scene_dict(), base_dir=FIXTURES) as b:
                self.assertEqual(b.medium_path(0), BOX)
                same_film(self, vbl.render(a, threads=2), vbl.render(b, threads=2))

    def test_color_managed_loading(self):
        if not vbl.native_available():
            self.skipTest("libvbl_python not built")
        config = vbl.default_color_config()
        self.assertTrue(config.scene_linear)
        data = scene_dict(color_space="ACEScg")
        with vbl.Scene.from_dict(data, base_dir=FIXTURES) as managed, \
                vbl.Scene.from_dict(scene_dict(), base_dir=FIXTURES) as plain:
            a, b = vbl.render(managed).beauty, vbl.render(plain).beauty
            self.assertTrue(numpy.all(numpy.isfinite(a)))
            self.assertFalse(numpy.array_equal(a, b))  # the colours were converted
        with self.assertRaises(vbl.SceneError) as raised:
            vbl.Scene.from_dict(data, base_dir=FIXTURES, color_config=False)
        self.assertIn("colour-managed loader", raised.exception.message)
        with self.assertRaises(vbl.SceneError) as raised:
            vbl.Scene.from_dict(scene_dict(color_space="no such space"), base_dir=FIXTURES)
        self.assertIn("no such space", raised.exception.message)


class TestLayers(unittest.TestCase):
    def test_transport_layers_and_aovs_apart(self):
        with vbl.Scene.from_dict(scene_dict(), base_dir=FIXTURES) as scene:
            film = vbl.render(scene)
            self.assertEqual(sorted(film.aovs), ["Z", "samples", "variance"])
            self.assertTrue(film.layers)
            for name in film.layers:
                self.assertIn(name, vbl.TRANSPORT_LAYERS)
            self.assertNotIn("", film.layers)
            self.assertIn("volume_emission", vbl.TRANSPORT_LAYERS)
            total = sum(film.layer(name) for name in film.layers)
            numpy.testing.assert_allclose(total, film.beauty[..., :3], rtol=1e-5, atol=1e-7)
            # the totals are colour layers summing their classes, not AOVs and not in `layers`
            self.assertEqual(film.totals, ["volume_indirect"])  # no surfaces: no surface_indirect
            self.assertTrue(set(film.totals) <= set(vbl.TOTAL_LAYERS))
            for name in film.totals:
                self.assertNotIn(name, film.layers)
            members = {"volume_indirect": ("volume_from_surface", "volume_from_volume"),
                       "surface_indirect": ("surface_from_surface", "surface_from_volume")}
            for name in film.totals:
                parts = members[name]
                want = sum(film.layer(p) for p in parts if p in film.layers)
                numpy.testing.assert_allclose(film.layer(name), want, rtol=1e-6, atol=1e-9)
            self.assertEqual(film.light_groups, [])

    def test_light_groups_are_colour_layers(self):
        data = scene_dict()
        data["lights"][0]["group"] = "key"  # the sky stays in the group `default`
        with vbl.Scene.from_dict(data, base_dir=FIXTURES) as scene:
            film = vbl.render(scene, light_groups=1)
            self.assertEqual(sorted(film.light_groups), ["lightgroup_default", "lightgroup_key"])
            for name in film.light_groups:
                self.assertNotIn(name, film.aovs)
                self.assertNotIn(name, film.layers)
            # the classes still sum to the beauty; the groups do too (to float rounding)
            total = sum(film.layer(name) for name in film.layers)
            numpy.testing.assert_allclose(total, film.beauty[..., :3], rtol=1e-5, atol=1e-7)
            groups = sum(film.layer(name) for name in film.light_groups)
            numpy.testing.assert_allclose(groups, film.beauty[..., :3], rtol=1e-5, atol=1e-6)
            self.assertGreater(float(film.layer("lightgroup_key").max()), 0.0)

    def test_scene_shot_overrides(self):
        with vbl.Scene.from_dict(scene_dict(), base_dir=FIXTURES, width=20, height=10) as scene:
            self.assertEqual(scene.resolution, (20, 10))
            film = vbl.render(scene)
            self.assertEqual((film.width, film.height), (20, 10))
        with self.assertRaises(vbl.InvalidArgument):
            vbl.Scene.from_dict(scene_dict(), base_dir=FIXTURES, width=20)
        with self.assertRaises(vbl.FileNotFound):
            vbl.Scene.from_dict(scene_dict(), base_dir=FIXTURES, camera="no-such-camera")


class TestInterrupt(unittest.TestCase):
    """Ctrl-C (SIGINT to this process) stops the render and keeps the complete passes: the film
    equals a render of that many passes bit for bit (no assertion on time)."""

    def interrupted(self, scene, **kwargs):
        with self.assertRaises(vbl.RenderInterrupted) as raised:
            vbl.render(scene, passes=1000000, threads=2, **kwargs)
        film = raised.exception.film
        self.assertIsNotNone(film)
        passes = film.stats["passes"]
        self.assertGreaterEqual(passes, 1)
        self.assertLess(passes, 1000000)
        same_film(self, film, vbl.render(scene, passes=passes, threads=2))
        return passes

    def test_ctrl_c_without_callback(self):
        with vbl.Scene.from_dict(scene_dict(), base_dir=FIXTURES) as scene:
            timer = threading.Timer(0.4, os.kill, (os.getpid(), signal.SIGINT))
            timer.start()
            try:
                self.interrupted(scene)
            finally:
                timer.cancel()

    def test_ctrl_c_with_callback(self):
        seen = []

        def progress(p):
            seen.append(p["pass"])
            if p["pass"] == 3:
                os.kill(os.getpid(), signal.SIGINT)
            return False

        with vbl.Scene.from_dict(scene_dict(), base_dir=FIXTURES) as scene:
            passes = self.interrupted(scene, callback=progress)
        self.assertGreaterEqual(passes, 3)
        self.assertEqual(seen[:3], [1, 2, 3])

    def test_cancel_event_returns_the_film(self):
        stop = threading.Event()
        with vbl.Scene.from_dict(scene_dict(), base_dir=FIXTURES) as scene:
            film = vbl.render(scene, passes=1000000, callback=lambda p: stop.set() if p["pass"] == 2 else None,
                              cancel=stop)
            self.assertGreaterEqual(film.stats["passes"], 2)
            self.assertEqual(film.stats["cancelled"], 1)
            same_film(self, film, vbl.render(scene, passes=film.stats["passes"]))
            # stopped before the first pass completes: RenderInterrupted with the library's message
            early = threading.Event()
            early.set()
            with self.assertRaises(vbl.RenderInterrupted) as raised:
                vbl.render(scene, passes=1000000, cancel=early)
            self.assertIsNone(raised.exception.film)
            self.assertIn("no pass completed", raised.exception.message)


class TestWriteExr(unittest.TestCase):
    def test_same_file_as_the_cli(self):
        cli = os.environ.get("VBL_CLI")
        if not cli or not vbl.native_available():
            self.skipTest("VBL_CLI not set or libvbl_python not built")
        with tempfile.TemporaryDirectory() as tmp:
            data = scene_dict()
            data["media"][0]["vdb"] = BOX
            path = os.path.join(tmp, "scene.json")
            with open(path, "w") as f:
                json.dump(data, f)
            subprocess.run([cli, "render", path, "-o", os.path.join(tmp, "cli.exr"), "--threads", "2",
                            "--aov", "all", "--quiet"], check=True, stdout=subprocess.DEVNULL)
            with vbl.Scene(path) as scene:
                film = vbl.render(scene, threads=2)
                film.write_exr(os.path.join(tmp, "py.exr"), aovs="all")
                with self.assertRaises(vbl.InvalidArgument):
                    film.write_exr(os.path.join(tmp, "bad.exr"), aovs=["depth"])
                with self.assertRaises(vbl.InvalidArgument):  # as --half-layers Z
                    film.write_exr(os.path.join(tmp, "bad.exr"), half_layers=["Z"])
                self.assertFalse(os.path.exists(os.path.join(tmp, "bad.exr")))
            a, b = vbl.ExrFile(os.path.join(tmp, "cli.exr")), vbl.ExrFile(os.path.join(tmp, "py.exr"))
            self.assertEqual(a.channel_names, b.channel_names)
            for channel in a.channel_names:
                numpy.testing.assert_array_equal(a.channel(channel), b.channel(channel), err_msg=channel)
            want, have = a.attributes, b.attributes
            self.assertEqual(sorted(want), sorted(have))
            for name in want:
                if name != "vbl:render_seconds":
                    self.assertEqual(want[name], have[name], name)
            self.assertEqual(have["vbl:status"], "complete")
            self.assertEqual(sorted(a.layer_names),
                             sorted(["", "Z"] + film.layers + film.totals + ["samples", "variance"]))
            # --output-space: the same conversion as the CLI's
            subprocess.run([cli, "render", path, "-o", os.path.join(tmp, "cli_acescg.exr"), "--threads", "2",
                            "--output-space", "ACEScg", "--quiet"], check=True, stdout=subprocess.DEVNULL)
            with vbl.Scene(path) as scene:
                vbl.render(scene, threads=2).write_exr(os.path.join(tmp, "py_acescg.exr"), output_space="ACEScg")
                with self.assertRaises(vbl.InvalidArgument):
                    vbl.render(scene, passes=1).write_exr(os.path.join(tmp, "bad.exr"), output_space="no such space")
            ca, cb = vbl.ExrFile(os.path.join(tmp, "cli_acescg.exr")), vbl.ExrFile(os.path.join(tmp, "py_acescg.exr"))
            self.assertEqual(ca.channel_names, cb.channel_names)
            for channel in ca.channel_names:
                numpy.testing.assert_array_equal(ca.channel(channel), cb.channel(channel), err_msg=channel)
            want, have = ca.attributes, cb.attributes
            self.assertEqual(sorted(want), sorted(have))
            for name in want:
                if name != "vbl:render_seconds":
                    self.assertEqual(want[name], have[name], name)
            self.assertNotEqual(want["oiio:ColorSpace"], vbl.default_color_config().scene_linear)
            # a checkpoint written from Python resumes with the CLI
            with vbl.Scene(path) as scene:
                vbl.render(scene, passes=1, threads=2).write_exr(os.path.join(tmp, "part.exr"), status="checkpoint")
            subprocess.run([cli, "render", path, "-o", os.path.join(tmp, "part.exr"), "--resume", "--threads", "2",
                            "--quiet"], check=True, stdout=subprocess.DEVNULL)
            resumed = vbl.ExrFile(os.path.join(tmp, "part.exr"))
            self.assertEqual(resumed.attributes["vbl:passes"], 2)
            numpy.testing.assert_allclose(resumed.layer(""), a.layer(""), rtol=4e-7, atol=0)

    def test_same_file_as_the_cli_transparent_groups_acescg(self):
        """Transparent, light groups, a total layer, HALF and --output-space together: the beauty
        and the totals re-summed from the converted classes (background left out), the
        vbl:transparent / vbl:alpha / camera-matrix attributes: all from the one writer."""
        cli = os.environ.get("VBL_CLI")
        if not cli or not vbl.native_available():
            self.skipTest("VBL_CLI not set or libvbl_python not built")
        with tempfile.TemporaryDirectory() as tmp:
            data = scene_dict()
            data["media"][0]["vdb"] = BOX
            data["lights"][0]["group"] = "key"
            path = os.path.join(tmp, "scene.json")
            with open(path, "w") as f:
                json.dump(data, f)
            subprocess.run([cli, "render", path, "-o", os.path.join(tmp, "cli.exr"), "--threads", "2", "--passes", "1",
                            "--transparent", "on", "--light-groups", "on", "--output-space", "ACEScg",
                            "--aov", "variance", "--half-layers", "volume_direct,lightgroup_key", "--quiet"],
                           check=True, stdout=subprocess.DEVNULL)
            with vbl.Scene(path) as scene:
                film = vbl.render(scene, threads=2, passes=1, transparent=1, light_groups=1)
                film.write_exr(os.path.join(tmp, "py.exr"), aovs="variance", output_space="ACEScg",
                               half_layers=["volume_direct", "lightgroup_key"])
            a, b = vbl.ExrFile(os.path.join(tmp, "cli.exr")), vbl.ExrFile(os.path.join(tmp, "py.exr"))
            self.assertIn("lightgroup_key.R", a.channel_names)
            self.assertIn("volume_indirect.R", a.channel_names)
            self.assertEqual(a.channel_names, b.channel_names)
            for channel in a.channel_names:
                numpy.testing.assert_array_equal(a.channel(channel), b.channel(channel), err_msg=channel)
            want, have = a.attributes, b.attributes
            self.assertEqual(sorted(want), sorted(have))
            for name in want:
                if name != "vbl:render_seconds":
                    self.assertEqual(want[name], have[name], name)
            self.assertEqual(have["vbl:transparent"], 1)
            self.assertIn("worldToCamera", have)
            self.assertIn("worldToNDC", have)


if __name__ == "__main__":
    result = unittest.main(exit=False, verbosity=2).result
    failed = len(result.failures) + len(result.errors)
    skipped = len(result.skipped)
    print("%d passed, %d failed, %d skipped" % (result.testsRun - failed - skipped, failed, skipped))
    sys.exit(1 if failed or not result.wasSuccessful() else 0)
