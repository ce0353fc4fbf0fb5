/* Grids of a medium by role: name conventions of Houdini, EmberGen and Blender/Mantaflow. */
#include "scene/scene_grids.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"

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
        char tried[256] = "", listed[1024] = "";
        for (const char* const* n = vbl_grid_role_names(role); *n; ++n)
            snprintf(tried + strlen(tried), sizeof tried - strlen(tried), "%s'%s'", tried[0] ? ", " : "", *n);
        for (size_t i = 0; i < count; ++i)
            snprintf(listed + strlen(listed), sizeof listed - strlen(listed), "%s'%s' %s", i ? ", " : "",
                     grids[i].name, grids[i].type);
        vbl_grid_descriptions_free(grids);
        return vbl_error(VBL_ERROR_GRID_NOT_FOUND,
                         "%s: %s: '%s' has no %s grid (looked for %s; name one with \"grid\"); grids in file: %s",
                         scene_path, field, path, vbl_grid_role_name(role), tried, count ? listed : "none");
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

const char* vbl_grid_role_for(const char* grid_name)
{
    if (!grid_name) return NULL;
    vbl_grid_role role = vbl_grid_role_for_name(grid_name);
    return role == VBL_ROLE_NONE ? NULL : vbl_grid_role_name(role);
}
