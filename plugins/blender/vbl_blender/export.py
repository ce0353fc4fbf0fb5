"""Blender 3.4 scene -> vbl scene (a dict in the JSON schema of docs/reference/scene.md).

Units follow the conventions measured between vbl scenes and Blender/Cycles in the Cycles
reference kit (../shared/tools/cycles-reference/README.md, "Conventions"):
- camera: pinhole; Blender looks along its local -Z with +Y up; lens, sensor width/height and
  sensor fit go out as the scene's focal_length, sensor_width/height and sensor_fit (so a
  --resolution override re-fits the lens as Blender would);
- sun: Strength is irradiance E [W/m^2] (vbl `distant`, travelling along the sun's local -Z);
- point: Power P [W] = 4 pi I (vbl `point`, intensity I [W/sr]); spot: the same intensity on the
  axis, cone half-angle spot_size / 2 and a smoothstep blend over
  (1 - cos(outer)) * spot_blend in cosine (Cycles' spot_smooth), vbl's inner angle; not exact:
  Cycles is 2-17% dimmer by the cone's width (docs/readme/blender.md);
- area (square/rectangle): radiance L = P / (4 A) for Power P [W] and area A (measured against
  Cycles 3.4 in test_blender_addon: P / (pi A), the flux of a Lambertian emitter, is 4/pi too
  bright), vbl `quad`, emitting along the light's local -Z;
- volume objects: voxel (i, j, k) of Cycles 3.4 sits at indexToWorld(i + 1/2, ...), so the vbl
  transform is matrix_world @ T(half a voxel); density `render.space` OBJECT divides the density
  by the object's scale;
- Principled Volume: sigma_s = Color * Density * grid, sigma_a = (1 - Color)(1 - sqrt(Absorption
  Color)) * Density * grid; with Absorption Color black, density_scale = Density and albedo = Color
  exactly; otherwise vbl's grey extinction takes the mean over RGB (a warning);
- Mantaflow gas domains: the cache's VDB (data/fluid_data_####.vdb) in the domain's frame
  (origin at the domain's min corner, cell-averaged values, so the same half-voxel shift).
Everything that cannot be mapped exactly is listed in the returned warnings."""

import math
import os

import bpy
from mathutils import Matrix, Vector


class ExportError(Exception):
    """A scene vbl cannot render (no camera, an orthographic camera, a volume without its file)."""


def _rows(matrix):
    return [[float(matrix[i][j]) for j in range(4)] for i in range(4)]


def _rgb(values, scale=1.0):
    return [float(values[0]) * scale, float(values[1]) * scale, float(values[2]) * scale]


def _resolution(scene):
    r = scene.render
    return (max(1, int(round(r.resolution_x * r.resolution_percentage / 100.0))),
            max(1, int(round(r.resolution_y * r.resolution_percentage / 100.0))))


# Blender's Sensor Fit -> the scene's sensor_fit (the same rules: docs/readme/render.md, "Camera")
_SENSOR_FIT = {"AUTO": "auto", "HORIZONTAL": "horizontal", "VERTICAL": "vertical"}


def export_camera(scene, warnings):
    obj = scene.camera
    if obj is None:
        raise ExportError("the scene has no camera")
    cam = obj.data
    if cam.type != "PERSP":
        raise ExportError("camera %r is %s: vbl renders pinhole (perspective) cameras only" % (obj.name, cam.type))
    width, height = _resolution(scene)
    if abs(cam.shift_x) > 0 or abs(cam.shift_y) > 0:
        warnings.append("camera %r: lens shift is not exported (vbl has no shift)" % obj.name)
    if cam.dof.use_dof:
        warnings.append("camera %r: depth of field is not exported (pinhole)" % obj.name)
    if scene.render.pixel_aspect_x != scene.render.pixel_aspect_y:
        warnings.append("non-square pixels are not exported")
    m = obj.matrix_world
    position = m.translation
    forward = -(m.to_3x3() @ Vector((0.0, 0.0, 1.0))).normalized()
    up = (m.to_3x3() @ Vector((0.0, 1.0, 0.0))).normalized()
    return {"position": list(position), "look_at": list(position + forward), "up": list(up),
            "focal_length": cam.lens, "sensor_width": cam.sensor_width, "sensor_height": cam.sensor_height,
            "sensor_fit": _SENSOR_FIT[cam.sensor_fit], "resolution": [width, height]}


def export_light(obj, warnings):
    light = obj.data
    m = obj.matrix_world
    axis = -(m.to_3x3() @ Vector((0.0, 0.0, 1.0))).normalized()  # Blender lights emit along local -Z
    color = light.color
    if light.type == "SUN":
        if light.angle > 0.0:
            warnings.append("sun %r: angle %.3g deg exported as a delta direction" % (obj.name, math.degrees(light.angle)))
        return {"type": "distant", "direction": list(axis), "irradiance": _rgb(color, light.energy)}
    if light.type in ("POINT", "SPOT"):
        if light.shadow_soft_size > 0.0:
            warnings.append("%s %r: radius %.3g exported as 0 (vbl point lights are deltas)"
                            % (light.type.lower(), obj.name, light.shadow_soft_size))
        out = {"type": "point", "position": list(m.translation),
               "intensity": _rgb(color, light.energy / (4.0 * math.pi))}
        if light.type == "SPOT":
            outer = 0.5 * light.spot_size
            cos_inner = math.cos(outer) + (1.0 - math.cos(outer)) * light.spot_blend
            out.update({"type": "spot", "direction": list(axis), "outer_angle_deg": math.degrees(outer),
                        "inner_angle_deg": math.degrees(math.acos(min(1.0, cos_inner)))})
        return out
    if light.type == "AREA":
        if light.shape in ("DISK", "ELLIPSE"):
            warnings.append("area %r: %s shape exported as its bounding rectangle" % (obj.name, light.shape.lower()))
        sx = light.size
        sy = light.size if light.shape in ("SQUARE", "DISK") else light.size_y
        x = m.to_3x3() @ Vector((sx, 0.0, 0.0))
        y = m.to_3x3() @ Vector((0.0, sy, 0.0))
        area = x.cross(y).length
        if area <= 0.0:
            warnings.append("area %r has no area: skipped" % obj.name)
            return None
        corner = m.translation - 0.5 * x - 0.5 * y
        # one-sided along local -Z: cross(edge1, edge2) = cross(y, x) points along -Z
        return {"type": "quad", "corner": list(corner), "edge1": list(y), "edge2": list(x),
                "radiance": _rgb(color, light.energy / (4.0 * area))}
    warnings.append("light %r of type %s is not exported" % (obj.name, light.type))
    return None


def _socket_value(node, name):
    socket = node.inputs.get(name)
    if socket is None:
        return None
    return socket.default_value


def _linked_attribute(node, name):
    """The attribute name when input `name` is linked from an Attribute node, else None."""
    socket = node.inputs.get(name)
    if socket is None or not socket.is_linked:
        return None
    source = socket.links[0].from_node
    return source.attribute_name if source.type == "ATTRIBUTE" else None


def _volume_node(material):
    if material is None or not material.use_nodes:
        return None
    for node in material.node_tree.nodes:
        if node.type == "OUTPUT_MATERIAL" and node.is_active_output:
            socket = node.inputs.get("Volume")
            if socket is not None and socket.is_linked:
                return socket.links[0].from_node
    return None


def export_medium(obj, material, vdb, matrix, warnings, default_grid="density"):
    """A vbl medium from a Principled Volume (or Volume Scatter + Absorption is not mapped)."""
    node = _volume_node(material)
    medium = {"vdb": vdb, "transform": _rows(matrix)}
    if node is None or node.type != "PRINCIPLED_VOLUME":
        warnings.append("volume %r: no Principled Volume on the material output; exported with density 1, "
                        "albedo 1, isotropic" % obj.name)
        medium["grid"] = default_grid
        return medium
    density = float(_socket_value(node, "Density"))
    color = list(_socket_value(node, "Color"))[:3]
    absorption = list(_socket_value(node, "Absorption Color"))[:3]
    grid = _socket_value(node, "Density Attribute") or default_grid
    medium["grid"] = grid
    if node.inputs["Color"].is_linked or node.inputs["Density"].is_linked:
        warnings.append("volume %r: linked Color/Density inputs are exported at their default values" % obj.name)
    sigma_s = [c * density for c in color]
    sigma_a = [(1.0 - c) * (1.0 - math.sqrt(max(0.0, a))) * density for c, a in zip(color, absorption)]
    sigma_t = [s + a for s, a in zip(sigma_s, sigma_a)]
    mean_t = sum(sigma_t) / 3.0
    if max(sigma_t) - min(sigma_t) > 1e-6 * max(1.0, mean_t):
        warnings.append("volume %r: colour-dependent extinction (Absorption Color not black) exported as its "
                        "mean: vbl's extinction is grey" % obj.name)
    medium["density_scale"] = mean_t
    medium["albedo"] = [min(1.0, s / t) if t > 0.0 else 1.0 for s, t in zip(sigma_s, sigma_t)]
    g = float(_socket_value(node, "Anisotropy"))
    medium["phase"] = {"type": "hg", "g": max(-0.999, min(0.999, g))}
    # emission: Cycles adds j = Strength * Color (times a linked attribute) per unit length; vbl adds
    # sigma_a * Le (docs/readme/emission.md, "Convention") with sigma_a = Density (1 - albedo) grid,
    # so Le = j / sigma_a: exact where the density grid is 1 over the emitting region.
    strength = float(_socket_value(node, "Emission Strength"))
    mean_a = sum(sigma_a) / 3.0
    if strength > 0.0 or _linked_attribute(node, "Emission Strength"):
        if mean_a <= 0.0:
            warnings.append("volume %r: emission with Color white (no absorption) cannot be mapped: vbl emits "
                            "sigma_a Le" % obj.name)
        else:
            emission_color = list(_socket_value(node, "Emission Color"))[:3]
            attribute = _linked_attribute(node, "Emission Strength")
            medium["emission"] = {"grid": attribute or grid, "color": emission_color,
                                  "scale": (strength if not attribute else 1.0) / mean_a}
            warnings.append("volume %r: emission mapped as Le = j / sigma_a (exact where the density grid "
                            "is 1)" % obj.name)
    blackbody = float(_socket_value(node, "Blackbody Intensity"))
    if blackbody > 0.0:
        if mean_a <= 0.0:
            warnings.append("volume %r: blackbody with no absorption cannot be mapped" % obj.name)
        else:
            temperature = _socket_value(node, "Temperature Attribute") or "temperature"
            medium["temperature"] = {"grid": temperature, "blackbody_intensity": blackbody / mean_a,
                                     "normalization": "luminance"}
    return medium


def _half_voxel(matrix_object):
    return (matrix_object @ Vector((0.5, 0.5, 0.5))) - (matrix_object @ Vector((0.0, 0.0, 0.0)))


def _object_scale(obj):
    s = obj.matrix_world.to_scale()
    return abs(s[0] * s[1] * s[2]) ** (1.0 / 3.0)


def export_volume_object(obj, scene, warnings):
    volume = obj.data
    try:
        path = volume.grids.frame_filepath or volume.filepath
    except AttributeError:
        path = volume.filepath
    path = bpy.path.abspath(path)
    if not path or not os.path.exists(path):
        raise ExportError("volume %r: file %r does not exist" % (obj.name, path))
    volume.grids.load()
    grid_name = volume.grids[volume.grids.active_index].name if len(volume.grids) else "density"
    matrix_object = Matrix.Identity(4)
    for grid in volume.grids:
        if grid.name == "density":
            grid_name = "density"
    for grid in volume.grids:
        if grid.name == grid_name:
            matrix_object = grid.matrix_object
    matrix = obj.matrix_world @ Matrix.Translation(_half_voxel(matrix_object))
    material = obj.active_material
    medium = export_medium(obj, material, path, matrix, warnings, default_grid=grid_name)
    if volume.render.space == "OBJECT":
        scale = _object_scale(obj)
        if abs(scale - 1.0) > 1e-6:
            medium["density_scale"] /= scale
    if volume.render.precision != "FULL":
        warnings.append("volume %r: Cycles quantises the grid (precision %s); vbl reads it in full"
                        % (obj.name, volume.render.precision))
    return medium


def _fluid_domain(obj):
    for modifier in obj.modifiers:
        if modifier.type == "FLUID" and modifier.fluid_type == "DOMAIN":
            return modifier.domain_settings
    return None


def export_mantaflow_domain(obj, domain, scene, warnings):
    """A gas domain's cache frame: the VDB in the domain's frame, origin at the domain's min corner."""
    if domain.domain_type != "GAS":
        return None
    folder = bpy.path.abspath(domain.cache_directory)
    path = os.path.join(folder, "data", "fluid_data_%04d.vdb" % scene.frame_current)
    if not os.path.exists(path):
        raise ExportError("fluid domain %r: no baked cache frame %s (bake the domain, cache format OpenVDB)"
                          % (obj.name, path))
    if domain.use_adaptive_domain:
        warnings.append("fluid domain %r: adaptive domain offsets are not exported" % obj.name)
    corners = [Vector(c) for c in obj.bound_box]
    lo = Vector((min(c[0] for c in corners), min(c[1] for c in corners), min(c[2] for c in corners)))
    hi = Vector((max(c[0] for c in corners), max(c[1] for c in corners), max(c[2] for c in corners)))
    size = hi - lo
    cell = max(size) / float(domain.resolution_max)  # Mantaflow's cell in the domain's local units
    # the cache stores the grid with voxel = the world cell (its own transform); rescale it to the
    # domain's local cell, then place the local box by matrix_world; cell-averaged values: half a cell
    world_cell = cell * _object_scale(obj)
    voxel_to_local = Matrix.Diagonal(Vector((cell / world_cell,) * 3)).to_4x4()
    matrix = obj.matrix_world @ Matrix.Translation(lo) @ voxel_to_local @ Matrix.Translation(Vector((0.5 * world_cell,) * 3))
    material = obj.active_material
    return export_medium(obj, material, path, matrix, warnings)


def _write_obj(path, mesh, matrix):
    with open(path, "w") as f:
        f.write("# written by the vbl Blender add-on: world coordinates\n")
        for v in mesh.vertices:
            p = matrix @ v.co
            f.write("v %.9g %.9g %.9g\n" % (p[0], p[1], p[2]))
        mesh.calc_loop_triangles()
        for tri in mesh.loop_triangles:
            a, b, c = tri.vertices
            f.write("f %d %d %d\n" % (a + 1, b + 1, c + 1))


def export_surface_material(obj, warnings):
    """Lambert from Diffuse BSDF / Principled BSDF (metallic 0), GGX from Glossy BSDF."""
    material = obj.active_material
    node = None
    if material is not None and material.use_nodes:
        for n in material.node_tree.nodes:
            if n.type == "OUTPUT_MATERIAL" and n.is_active_output and n.inputs["Surface"].is_linked:
                node = n.inputs["Surface"].links[0].from_node
    if node is None:
        color = list(material.diffuse_color)[:3] if material is not None else [0.8, 0.8, 0.8]
        return {"type": "lambert", "albedo": color}
    if node.type == "BSDF_DIFFUSE":
        return {"type": "lambert", "albedo": list(_socket_value(node, "Color"))[:3]}
    if node.type == "BSDF_GLOSSY":
        roughness = float(_socket_value(node, "Roughness"))
        return {"type": "ggx", "albedo": 0.0, "specular": list(_socket_value(node, "Color"))[:3],
                "roughness": max(1e-3, roughness * roughness)}
    if node.type == "BSDF_PRINCIPLED":
        base = list(_socket_value(node, "Base Color"))[:3]
        if float(_socket_value(node, "Metallic")) > 0.0 or float(_socket_value(node, "Transmission")) > 0.0:
            warnings.append("mesh %r: metallic/transmission Principled BSDF exported as GGX over diffuse" % obj.name)
        roughness = float(_socket_value(node, "Roughness"))
        specular = 0.08 * float(_socket_value(node, "Specular"))
        return {"type": "ggx", "albedo": [c * (1.0 - specular) for c in base], "specular": specular,
                "roughness": max(1e-3, roughness * roughness)}
    warnings.append("mesh %r: shader %s exported as grey Lambert" % (obj.name, node.type))
    return {"type": "lambert", "albedo": 0.8}


def export_scene(scene, folder, depsgraph=None, render=None):
    """(scene dict, warnings): the Blender scene as a vbl scene; meshes are written to OBJ files in
    `folder` (world coordinates), VDB paths are absolute. `render`: the vbl `render` block."""
    warnings = []
    out = {"_doc": "exported from Blender %s by the vbl add-on (plugins/blender)" % bpy.app.version_string,
           "camera": export_camera(scene, warnings), "lights": [], "media": [], "surfaces": []}
    depsgraph = depsgraph or bpy.context.evaluated_depsgraph_get()
    for obj in scene.objects:
        if obj.hide_render:
            continue
        if obj.type == "LIGHT":
            light = export_light(obj, warnings)
            if light:
                if getattr(obj, "lightgroup", ""):  # Blender 3.2+: Object > Shading > Light Group
                    light["group"] = obj.lightgroup
                out["lights"].append(light)
        elif obj.type == "VOLUME":
            out["media"].append(export_volume_object(obj, scene, warnings))
        elif obj.type == "MESH":
            domain = _fluid_domain(obj)
            if domain is not None:
                medium = export_mantaflow_domain(obj, domain, scene, warnings)
                if medium:
                    out["media"].append(medium)
                continue
            evaluated = obj.evaluated_get(depsgraph)
            mesh = evaluated.to_mesh()
            try:
                if len(mesh.polygons) == 0:
                    continue
                path = os.path.join(folder, "%s.obj" % bpy.path.clean_name(obj.name))
                _write_obj(path, mesh, obj.matrix_world)
            finally:
                evaluated.to_mesh_clear()
            out["surfaces"].append({"mesh": path, "material": export_surface_material(obj, warnings)})
    world = scene.world
    if world is not None and world.use_nodes:
        background = world.node_tree.nodes.get("Background")
        if background is not None and not background.inputs["Color"].is_linked:
            strength = float(background.inputs["Strength"].default_value)
            color = _rgb(background.inputs["Color"].default_value, strength)
            if max(color) > 0.0:
                out["lights"].append({"type": "environment", "radiance": color})
                if getattr(world, "lightgroup", ""):
                    out["lights"][-1]["group"] = world.lightgroup
    if not out["surfaces"]:
        del out["surfaces"]
    if len(out["media"]) > 8 or len(out["lights"]) > 64:
        raise ExportError("vbl takes at most 8 media and 64 lights (%d, %d)" % (len(out["media"]), len(out["lights"])))
    if render:
        out["render"] = dict(render)
    if any("group" in light for light in out["lights"]):  # Blender light groups -> lightgroup_<name> layers
        out.setdefault("render", {})["light_groups"] = True
    return out, warnings
