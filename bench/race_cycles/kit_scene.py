"""A libvbl scene file as a scene of the Cycles reference kit (../shared/tools/cycles-reference,
README "Conventions"): one medium, distant and point lights, Lambert OBJ surfaces, black world.

    kit_scene(vbl_scene_path, vdb_path) -> dict   (raises ValueError naming the field it cannot map)

Mapping (the kit's conventions were measured against closed forms; vbl's scene schema is
docs/reference/scene.md):
- camera: position, look_at, up; vbl's `fov_deg` is vertical, as the kit's `vfov_deg`.
- distant: vbl's `direction` is the direction light travels; the kit wants the direction to the
  light (-direction). RGB irradiance -> strength max(rgb), colour rgb / max.
- point: RGB intensity [W/sr] -> intensity max(rgb), colour rgb / max (the kit sets Power 4 pi I).
- media[0]: the VDB, grid, `transform` (applied after the grid's own index-to-world transform,
  as the kit's object_to_world), density_scale, grey albedo, HG g.
- surfaces: OBJ in world coordinates with a Lambert material (scalar or RGB albedo).
- max bounces: vbl's -1 (unlimited) becomes 1024 volume and diffuse bounces (Blender's maximum).
"""
import json
import os


def _rgb_strength(value, field):
    rgb = [float(value)] * 3 if not isinstance(value, list) else [float(v) for v in value]
    if len(rgb) != 3 or min(rgb) < 0:
        raise ValueError(f"{field}: not a non-negative number or RGB triple")
    top = max(rgb)
    return top, ([c / top for c in rgb] if top > 0 else [1.0, 1.0, 1.0])


def _light(light, i):
    field = f"lights[{i}]"
    kind = light.get("type")
    if kind == "distant":
        e, color = _rgb_strength(light["irradiance"], field + ".irradiance")
        d = [-float(c) for c in light["direction"]]
        return {"type": "distant", "direction_to_light": d, "irradiance": e, "color": color}
    if kind == "point":
        inten, color = _rgb_strength(light["intensity"], field + ".intensity")
        return {"type": "point", "position": [float(c) for c in light["position"]], "intensity": inten,
                "color": color}
    raise ValueError(f"{field}.type = {kind!r}: the Cycles kit maps only distant and point lights")


def kit_scene(path, vdb):
    sd = json.load(open(path))
    base = os.path.dirname(os.path.abspath(path))
    cam = sd["camera"]
    if "fov_deg" not in cam:
        raise ValueError(f"{path}: camera.fov_deg: only a vertical fov is mapped")
    media = sd.get("media", [])
    if len(media) != 1:
        raise ValueError(f"{path}: media: the Cycles kit renders exactly one medium")
    med = media[0]
    albedo = med.get("albedo", 1.0)
    if isinstance(albedo, list):
        if max(albedo) != min(albedo):
            raise ValueError(f"{path}: media[0].albedo: the Cycles kit maps a grey albedo only")
        albedo = albedo[0]
    phase = med.get("phase", {"type": "hg", "g": 0.0})
    if phase.get("type", "hg") != "hg":
        raise ValueError(f"{path}: media[0].phase.type: only hg is mapped")
    if any(k in med for k in ("emission", "temperature")):
        raise ValueError(f"{path}: media[0]: emission is not mapped by the Cycles kit")
    out = {
        "format": "anchor-scene/1",
        "name": os.path.splitext(os.path.basename(path))[0],
        "camera": {"type": "perspective", "position": cam["position"], "look_at": cam["look_at"],
                   "up": cam.get("up", [0, 0, 1]), "vfov_deg": float(cam["fov_deg"]),
                   "resolution": cam["resolution"]},
        "lights": [_light(l, i) for i, l in enumerate(sd.get("lights", []))],
        "background": {"radiance": [0.0, 0.0, 0.0]},
        "volume": {"file": os.path.abspath(vdb), "grid": med.get("grid", "density"),
                   "object_to_world": med.get("transform", [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])},
        "medium": {"density_scale": float(med.get("density_scale", 1.0)), "albedo": float(albedo),
                   "phase": {"type": "henyey-greenstein", "g": float(phase.get("g", 0.0))}, "emission": 0.0},
        "integrator": {"max_volume_bounces": 1024, "max_diffuse_bounces": 1024, "max_bounces": 1024},
        "cycles": {"volume_step_rate": 1.0, "volume_max_steps": 4096, "material_volume_step_rate": 1.0},
    }
    surfaces = []
    for i, s in enumerate(sd.get("surfaces", [])):
        m = s.get("material", {})
        if m.get("type") != "lambert" or "transform" in s or "subdivision" in s:
            raise ValueError(f"{path}: surfaces[{i}]: only untransformed Lambert meshes are mapped")
        surfaces.append({"obj": os.path.normpath(os.path.join(base, s["mesh"])),
                         "material": {"type": "lambert", "albedo": m.get("albedo", 0.5)}})
    if surfaces:
        out["surfaces"] = surfaces
    return out
