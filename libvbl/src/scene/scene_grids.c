/* Grids of a medium by role: name conventions of Houdini, EmberGen and Blender/Mantaflow. */
#include "scene/scene_grids.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "volume/volume.h"

static const char* const vbl_density_names[] = {"density", NULL};
static const char* const vbl_emission_names[] = {"emission", "flame", "fire", NULL};
static const char* const vbl_temperature_names[] = {"temperature", "heat", "temp", NULL};
static const char* const vbl_albedo_names[] = {"albedo", "Cd", "color", NULL};
static const char* const vbl_velocity_names[] = {"velocity", "vel", "v", "vel.x", "vel.y", "vel.z", NULL};
static const char* const vbl_no_names[] = {NULL};

const char* vbl_grid_role_name(vbl_grid_role role)
{
    static const char* const names[] = {"density", "emission", "temperature", "albedo", "velocity", ""};
    return (unsigned)role <= VBL_ROLE_NONE ? names[role] : "";
}

const char* const* vbl_grid_role_names(vbl_grid_role role)
{
    switch (role) {
    case VBL_ROLE_DENSITY: return vbl_density_names;
    case VBL_ROLE_EMISSION: return vbl_emission_names;
    case VBL_ROLE_TEMPERATURE: return vbl_temperature_names;
    case VBL_ROLE_ALBEDO: return vbl_albedo_names;
    case VBL_ROLE_VELOCITY: return vbl_velocity_names;
    default: return vbl_no_names;
    }
}

vbl_grid_role vbl_grid_role_for_name(const char* grid_name)
{
    for (int r = 0; r < VBL_ROLE_NONE; ++r)
        for (const char* const* n = vbl_grid_role_names((vbl_grid_role)r); *n; ++n)
            if (!strcmp(*n, grid_name)) return (vbl_grid_role)r;
    return VBL_ROLE_NONE;
}

/* VBL_ERROR_GRID_NOT_FOUND for a role whose grid the file lacks: the names tried (then `also`) and
 * the file's grids with their types. */
static vbl_result vbl_role_grid_missing(const char* scene_path, const char* field, vbl_grid_role role,
                                        const char* path, const vbl_grid_description* grids, size_t count,
                                        const char* also)
{
    char tried[256] = "", listed[1024] = "";
    for (const char* const* n = vbl_grid_role_names(role); *n; ++n)
        snprintf(tried + strlen(tried), sizeof tried - strlen(tried), "%s'%s'", tried[0] ? ", " : "", *n);
    for (size_t i = 0; i < count; ++i)
        snprintf(listed + strlen(listed), sizeof listed - strlen(listed), "%s'%s' %s", i ? ", " : "",
                 grids[i].name, grids[i].type);
    return vbl_error(VBL_ERROR_GRID_NOT_FOUND,
                     "%s: %s: '%s' has no %s grid (looked for %s%s; name one with \"grid\"); grids in file: %s",
                     scene_path, field, path, vbl_grid_role_name(role), tried, also, count ? listed : "none");
}

vbl_result vbl_load_role_grid(const char* scene_path, const char* field, vbl_grid_role role, const char* path,
                              const char* grid, vbl_volume** out)
{
    *out = NULL;
    vbl_grid_description* grids = NULL;
    size_t count = 0;
    vbl_result r = vbl_file_list_grids(path, &grids, &count);
    if (r) {
        char inner[1024];
        snprintf(inner, sizeof inner, "%s", vbl_last_error_message());
        return vbl_error(r, "%s: %s: %s", scene_path, field, inner);
    }
    const char* pick = grid;
    if (!pick)
        for (const char* const* n = vbl_grid_role_names(role); *n && !pick; ++n)
            for (size_t i = 0; i < count; ++i)
                if (!strcmp(grids[i].name, *n)) {
                    pick = *n;
                    break;
                }
    if (!pick) {
        r = vbl_role_grid_missing(scene_path, field, role, path, grids, count, "");
        vbl_grid_descriptions_free(grids);
        return r;
    }
    vbl_grid_descriptions_free(grids);
    vbl_volume_load_options load = VBL_VOLUME_LOAD_OPTIONS_DEFAULT;
    load.grid_name = pick;
    r = vbl_volume_load(path, &load, out);
    if (r) {
        char inner[1024];
        snprintf(inner, sizeof inner, "%s", vbl_last_error_message());
        return vbl_error(r, "%s: %s (%s grid '%s'): %s", scene_path, field, vbl_grid_role_name(role), pick, inner);
    }
    return VBL_SUCCESS;
}

static int vbl_type_is_vec3(const char* type)
{
    if (!strncmp(type, "half ", 5)) type += 5;
    return !strcmp(type, "vec3s") || !strcmp(type, "vec3d") || !strcmp(type, "Vec3f") || !strcmp(type, "Vec3d");
}

static const vbl_grid_description* vbl_find_grid(const vbl_grid_description* grids, size_t count, const char* name)
{
    for (size_t i = 0; i < count; ++i)
        if (!strcmp(grids[i].name, name)) return &grids[i];
    return NULL;
}

/* 1 if the file has float grids base.x, base.y, base.z. */
static int vbl_has_triplet(const vbl_grid_description* grids, size_t count, const char* base)
{
    static const char* const axes[] = {".x", ".y", ".z"};
    char name[300];
    for (int a = 0; a < 3; ++a) {
        snprintf(name, sizeof name, "%s%s", base, axes[a]);
        const vbl_grid_description* d = vbl_find_grid(grids, count, name);
        if (!d || !d->is_float) return 0;
    }
    return 1;
}

static vbl_result vbl_role_fail(vbl_result r, const char* scene_path, const char* field, vbl_grid_role role,
                                const char* pick)
{
    char inner[1024];
    snprintf(inner, sizeof inner, "%s", vbl_last_error_message());
    return vbl_error(r, "%s: %s (%s grid '%s'): %s", scene_path, field, vbl_grid_role_name(role), pick, inner);
}

vbl_result vbl_load_role_vec3(const char* scene_path, const char* field, vbl_grid_role role, const char* path,
                              const char* grid, vbl_volume* out[3])
{
    out[0] = out[1] = out[2] = NULL;
    const int velocity = role == VBL_ROLE_VELOCITY;
    vbl_grid_description* grids = NULL;
    size_t count = 0;
    vbl_result r = vbl_file_list_grids(path, &grids, &count);
    if (r) {
        char inner[1024];
        snprintf(inner, sizeof inner, "%s", vbl_last_error_message());
        return vbl_error(r, "%s: %s: %s", scene_path, field, inner);
    }
    char pick[300] = "";
    int triplet = 0; /* pick is the base name of a .x/.y/.z triplet */
    if (grid) {
        if (vbl_find_grid(grids, count, grid)) snprintf(pick, sizeof pick, "%s", grid);
        else if (velocity && vbl_has_triplet(grids, count, grid)) {
            snprintf(pick, sizeof pick, "%s", grid);
            triplet = 1;
        } else
            snprintf(pick, sizeof pick, "%s", grid); /* the loader names what is missing */
    } else {
        for (const char* const* n = vbl_grid_role_names(role); *n && !pick[0]; ++n) {
            const vbl_grid_description* d = vbl_find_grid(grids, count, *n);
            if (d && (!velocity || vbl_type_is_vec3(d->type))) snprintf(pick, sizeof pick, "%s", *n);
        }
        if (!pick[0] && velocity && vbl_has_triplet(grids, count, "vel")) {
            snprintf(pick, sizeof pick, "vel");
            triplet = 1;
        }
    }
    if (!pick[0]) {
        r = vbl_role_grid_missing(scene_path, field, role, path, grids, count,
                                  velocity ? " as vec3s, or float vel.x/vel.y/vel.z" : "");
        vbl_grid_descriptions_free(grids);
        return r;
    }
    const vbl_grid_description* d = triplet ? NULL : vbl_find_grid(grids, count, pick);
    const int is_float = d && d->is_float;
    vbl_grid_descriptions_free(grids);
    vbl_volume_load_options load = VBL_VOLUME_LOAD_OPTIONS_DEFAULT;
    if (triplet) {
        static const char* const axes[] = {".x", ".y", ".z"};
        for (int a = 0; a < 3; ++a) {
            char name[320];
            snprintf(name, sizeof name, "%s%s", pick, axes[a]);
            load.grid_name = name;
            if ((r = vbl_volume_load_signed(path, &load, &out[a]))) {
                vbl_result e = vbl_role_fail(r, scene_path, field, role, name);
                for (int b = 0; b < a; ++b) vbl_volume_release(out[b]);
                out[0] = out[1] = out[2] = NULL;
                return e;
            }
        }
        return VBL_SUCCESS;
    }
    load.grid_name = pick;
    if (is_float && !velocity) { /* a grey albedo grid */
        if ((r = vbl_volume_load(path, &load, &out[0]))) return vbl_role_fail(r, scene_path, field, role, pick);
        vbl_volume_retain(out[0]);
        vbl_volume_retain(out[0]);
        out[1] = out[2] = out[0];
        return VBL_SUCCESS;
    }
    if (is_float) {
        vbl_error(VBL_ERROR_GRID_TYPE, "%s: grid '%s' is a float grid; velocity needs a vec3s grid or three float grids '%s.x', '%s.y', '%s.z'",
                  path, pick, pick, pick, pick);
        return vbl_role_fail(VBL_ERROR_GRID_TYPE, scene_path, field, role, pick);
    }
    for (int a = 0; a < 3; ++a)
        if ((r = vbl_volume_load_vec3_component(path, &load, a, velocity, &out[a]))) {
            vbl_result e = vbl_role_fail(r, scene_path, field, role, pick);
            for (int b = 0; b < a; ++b) vbl_volume_release(out[b]);
            out[0] = out[1] = out[2] = NULL;
            return e;
        }
    return VBL_SUCCESS;
}

const char* vbl_grid_role_for(const char* grid_name)
{
    if (!grid_name) return NULL;
    vbl_grid_role role = vbl_grid_role_for_name(grid_name);
    return role == VBL_ROLE_NONE ? NULL : vbl_grid_role_name(role);
}
