"""The vbl render engine: exports the scene (export.py), renders it with the Python module `vbl`
in Blender's render thread (progress after every pass, Esc cancels the pass in progress through
the library's cancel flag), and loads the film's layers as render passes: Combined (the beauty),
one pass per transport layer (emission, volume_direct, ...), Depth (Z) and the samples and
variance AOVs, for the compositor."""

import json
import os
import shutil
import tempfile

import bpy

from . import export

# Render passes besides Combined: vbl layer -> (Blender pass name, channels, channel ids, type)
AOV_PASSES = {"Z": ("Depth", 1, "Z", "VALUE"), "samples": ("vbl_samples", 1, "X", "VALUE"),
              "variance": ("vbl_variance", 3, "RGB", "COLOR")}


def import_vbl():
    """The `vbl` module: importable as is, or from the add-on preference / $VBL_PYTHONPATH."""
    import importlib
    import sys
    try:
        return importlib.import_module("vbl")
    except ImportError:
        pass
    paths = [os.environ.get("VBL_PYTHONPATH", "")]
    addon = bpy.context.preferences.addons.get(__package__)
    if addon is not None:
        paths.insert(0, addon.preferences.python_path)
    for path in paths:
        if path and os.path.isdir(path) and path not in sys.path:
            sys.path.insert(0, path)
    return importlib.import_module("vbl")


def render_block(settings):
    block = {"method": settings.method, "passes": settings.passes, "spp": settings.spp, "seed": settings.seed,
             "max_bounces": settings.max_bounces}
    if settings.method != "pt":
        block["light_paths"] = settings.light_paths
    return block


def transport_pass_names(vbl):
    return list(vbl.TRANSPORT_LAYERS)


class VblRenderEngine(bpy.types.RenderEngine):
    bl_idname = "VBL"
    bl_label = "vbl"
    bl_use_preview = False
    bl_use_postprocess = True

    def update_render_passes(self, scene=None, renderlayer=None):
        self.register_pass(scene, renderlayer, "Combined", 4, "RGBA", "COLOR")
        try:
            names = transport_pass_names(import_vbl())
        except ImportError:
            return
        for name in names:
            self.register_pass(scene, renderlayer, name, 3, "RGB", "COLOR")
        for pass_name, channels, ids, kind in AOV_PASSES.values():
            self.register_pass(scene, renderlayer, pass_name, channels, ids, kind)
        for group in getattr(renderlayer, "lightgroups", ()):  # vbl's lightgroup_<name> layers
            self.register_pass(scene, renderlayer, "lightgroup_" + group.name, 3, "RGB", "COLOR")

    def render(self, depsgraph):
        scene = depsgraph.scene
        settings = scene.vbl
        try:
            vbl = import_vbl()
        except ImportError as error:
            self.report({"ERROR"}, "vbl: the Python module is not importable (set its folder in the add-on "
                                   "preferences or $VBL_PYTHONPATH): %s" % error)
            return
        # the scene file and its OBJ meshes: next to the kept scene file, else in a temporary folder
        # removed after the render
        kept = bpy.path.abspath(settings.scene_path) if settings.scene_path else ""
        folder = os.path.dirname(kept) if kept else tempfile.mkdtemp(prefix="vbl-blender-")
        try:
            self.render_scene(vbl, scene, settings, depsgraph, folder, kept or os.path.join(folder, "scene.json"))
        finally:
            if not kept:
                shutil.rmtree(folder, ignore_errors=True)

    def render_scene(self, vbl, scene, settings, depsgraph, folder, path):
        try:
            data, warnings = export.export_scene(scene, folder, depsgraph, render_block(settings))
        except export.ExportError as error:
            self.report({"ERROR"}, "vbl: %s" % error)
            return
        for warning in warnings:
            self.report({"WARNING"}, "vbl: %s" % warning)
        with open(path, "w") as f:
            json.dump(data, f, indent=1)
        width, height = data["camera"]["resolution"]
        total = settings.passes

        latest = {}

        def progress(p):  # runs in the render's worker thread: only record it
            latest["progress"] = p
            return False

        def cancel():  # polled every 50 ms in this (Blender's render) thread
            p = latest.pop("progress", None)
            if p is not None:
                self.update_progress(p["pass"] / float(total))
                self.update_stats("vbl", "pass %d / %d, %.1f s" % (p["pass"], total, p["elapsed_seconds"]))
            return self.should_cancel()

        overrides = {"threads": settings.threads} if settings.threads > 0 else {}
        film = None
        try:
            with vbl.Scene(path) as vscene:
                # the documented limits of the method at the extremes (vbl.render_limits; render.md
                # "Limits at the extremes"): the render still runs, the user sees why it may be dark
                for line in vbl.render_limits(vscene, **overrides) if hasattr(vbl, "render_limits") else ():
                    self.report({"WARNING"}, "vbl: %s" % line)
                try:
                    film = vbl.render(vscene, callback=progress, cancel=cancel, **overrides)
                except vbl.RenderInterrupted as error:
                    film = error.film
                except vbl.VblError as error:
                    self.report({"ERROR"}, "vbl: %s" % error)
                    return
                if film is None:
                    return
                if settings.exr_path:
                    film.write_exr(bpy.path.abspath(settings.exr_path), aovs="all")
                self.write_passes(vbl, film, width, height)
        finally:
            if film is not None:
                film.close()

    def should_cancel(self):
        """Esc in Blender (RenderEngine.test_break); a Python method so tests can stand in for it."""
        return self.test_break()

    def write_passes(self, vbl, film, width, height):
        result = self.begin_result(0, 0, width, height)
        layer = result.layers[0]
        # Blender's rows run bottom to top; the film's top to bottom
        layer.passes["Combined"].rect = film.beauty[::-1].reshape(-1, 4)
        for name in film.layers:
            render_pass = layer.passes.get(name)
            if render_pass is not None:
                render_pass.rect = film.layer(name)[::-1].reshape(-1, 3)
        for name in film.light_groups:
            render_pass = layer.passes.get(name)
            if render_pass is not None:
                render_pass.rect = film.layer(name)[::-1].reshape(-1, 3)
        for name in film.aovs:
            if name not in AOV_PASSES:
                continue
            pass_name, channels, _, _ = AOV_PASSES[name]
            render_pass = layer.passes.get(pass_name)
            if render_pass is not None:
                render_pass.rect = film.layer(name)[::-1].reshape(-1, channels)
        self.end_result(result)
