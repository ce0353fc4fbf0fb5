"""vbl for Blender 3.4: a render engine that renders the scene with libvbl (through its Python
module) and loads the layers as render passes, and File > Export > vbl scene (.json).
Install and use: docs/readme/blender.md."""

bl_info = {
    "name": "vbl",
    "author": "libvbl",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "Render Properties > Render Engine > vbl; File > Export > vbl scene (.json)",
    "description": "Render OpenVDB volumes with libvbl; export scenes to vbl's JSON",
    "category": "Render",
}

import json

import bpy
from bpy.props import EnumProperty, IntProperty, StringProperty
from bpy_extras.io_utils import ExportHelper

from . import engine, export


class VblPreferences(bpy.types.AddonPreferences):
    bl_idname = __package__
    python_path: StringProperty(name="vbl Python package folder", subtype="DIR_PATH",
                                description="Folder holding the package vbl (build/python of a build tree, "
                                            "or the prefix's lib/python3/dist-packages)")

    def draw(self, context):
        self.layout.prop(self, "python_path")


class VblSettings(bpy.types.PropertyGroup):
    method: EnumProperty(name="Method", items=[(m, m, "") for m in ("pt", "vpl", "vrl", "vbl", "beams")],
                         default="pt")
    passes: IntProperty(name="Passes", default=16, min=1)
    spp: IntProperty(name="Samples per pass", default=4, min=1)
    light_paths: IntProperty(name="Light paths", default=10000, min=0)
    seed: IntProperty(name="Seed", default=0, min=0)
    max_bounces: IntProperty(name="Max bounces", default=-1, min=-1)
    threads: IntProperty(name="Threads", default=0, min=0, description="0: all cores")
    scene_path: StringProperty(name="Scene file", subtype="FILE_PATH",
                               description="Keep the exported scene here (empty: a temporary file)")
    exr_path: StringProperty(name="EXR", subtype="FILE_PATH",
                             description="Also write the film as `vbl render` would (empty: no file)")


class VBL_PT_render(bpy.types.Panel):
    bl_label = "vbl"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "render"
    COMPAT_ENGINES = {"VBL"}

    @classmethod
    def poll(cls, context):
        return context.engine == "VBL"

    def draw(self, context):
        settings = context.scene.vbl
        for name in ("method", "passes", "spp", "light_paths", "seed", "max_bounces", "threads", "scene_path",
                     "exr_path"):
            self.layout.prop(settings, name)


class VBL_OT_export(bpy.types.Operator, ExportHelper):
    """Export the scene as a vbl scene file (meshes as OBJ files next to it)"""
    bl_idname = "export_scene.vbl"
    bl_label = "Export vbl scene"
    filename_ext = ".json"

    def execute(self, context):
        import os
        scene = context.scene
        try:
            data, warnings = export.export_scene(scene, os.path.dirname(os.path.abspath(self.filepath)),
                                                 render=engine.render_block(scene.vbl))
        except export.ExportError as error:
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
        for warning in warnings:
            self.report({"WARNING"}, warning)
        with open(self.filepath, "w") as f:
            json.dump(data, f, indent=1)
        return {"FINISHED"}


def _menu_export(self, context):
    self.layout.operator(VBL_OT_export.bl_idname, text="vbl scene (.json)")


_CLASSES = (VblPreferences, VblSettings, VBL_PT_render, VBL_OT_export, engine.VblRenderEngine)


def register():
    for cls in _CLASSES:
        bpy.utils.register_class(cls)
    bpy.types.Scene.vbl = bpy.props.PointerProperty(type=VblSettings)
    bpy.types.TOPBAR_MT_file_export.append(_menu_export)


def unregister():
    bpy.types.TOPBAR_MT_file_export.remove(_menu_export)
    del bpy.types.Scene.vbl
    for cls in reversed(_CLASSES):
        bpy.utils.unregister_class(cls)
