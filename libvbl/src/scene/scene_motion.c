/* Vector role grids (albedo, velocity) and the shutter of the scene file (scene_motion.h). */
#include "scene/scene_motion.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/error.h"
#include "scene/scene_grids.h"

vbl_result vbl_scene_role_file(const vbl_json_ctx* ctx, const cJSON* obj, const char* field, const char* dir,
                               const char* medium_path, char* out, size_t size)
{
    const char* vdb = NULL;
    vbl_result r = vbl_json_string(ctx, obj, field, "vdb", 0, &vdb);
    if (r) return r;
    if (!vdb) snprintf(out, size, "%s", medium_path);
    else if (vdb[0] == '/') snprintf(out, size, "%s", vdb);
    else snprintf(out, size, "%s%s", dir, vdb);
    return VBL_SUCCESS;
}

static double vbl_volume_max_value(const vbl_volume* v)
{
    return v->majorant.max_density ? v->majorant.global_max : 0.0;
}

vbl_result vbl_scene_parse_albedo_grid(const vbl_json_ctx* ctx, const cJSON* albedo, const char* field, const char* dir,
                                       vbl_medium* medium)
{
    static const char* const keys[] = {"grid", "vdb", "scale", NULL};
    vbl_result r;
    if ((r = vbl_json_check_keys(ctx, albedo, field, keys))) return r;
    const char* grid = NULL;
    char path[1024];
    if ((r = vbl_json_string(ctx, albedo, field, "grid", 0, &grid))) return r;
    if ((r = vbl_scene_role_file(ctx, albedo, field, dir, medium->vdb_path, path, sizeof path))) return r;
    vbl_volume* a[3];
    if ((r = vbl_load_role_vec3(ctx->path, field, VBL_ROLE_ALBEDO, path, grid, a))) return r;
    for (int c = 0; c < 3; ++c) medium->albedo_volume[c] = a[c];
    /* the grid's range, through its majorant grid (every value trilinear interpolation reads) */
    const double k[3] = {medium->albedo.x, medium->albedo.y, medium->albedo.z};
    double lo[3];
    for (int c = 0; c < 3; ++c) {
        double hi = k[c] * vbl_volume_max_value(a[c]);
        lo[c] = a[c]->majorant.max_density ? k[c] * fmax(0.0, a[c]->majorant.global_min) : 0.0;
        if (hi > 1.0)
            return vbl_error(VBL_ERROR_SCENE,
                             "%s: %s (albedo grid '%s'): %s: albedo up to %g in channel %d (scale %g times grid "
                             "values up to %g) is above 1; lower %s.scale",
                             ctx->path, field, a[c]->info.grid_name, path, hi, c, k[c], vbl_volume_max_value(a[c]), field);
    }
    medium->albedo_min = vbl_v3(lo[0], lo[1], lo[2]);
    return VBL_SUCCESS;
}

vbl_result vbl_scene_parse_velocity(const vbl_json_ctx* ctx, const cJSON* obj, const char* field, const char* dir,
                                    vbl_medium* medium)
{
    static const char* const keys[] = {"grid", "vdb", "scale", NULL};
    const cJSON* vel = NULL;
    char vf[512], path[1024];
    vbl_json_field(vf, sizeof vf, field, "velocity");
    vbl_result r;
    if ((r = vbl_json_object(ctx, obj, field, "velocity", 0, &vel))) return r;
    if (!vel) return VBL_SUCCESS;
    if ((r = vbl_json_check_keys(ctx, vel, vf, keys))) return r;
    const char* grid = NULL;
    double scale = 1.0;
    if ((r = vbl_json_string(ctx, vel, vf, "grid", 0, &grid))) return r;
    if ((r = vbl_json_number(ctx, vel, vf, "scale", 0, &scale))) return r;
    if (!isfinite(scale)) return vbl_json_fail(ctx, "%s.scale = %g is not finite", vf, scale);
    if ((r = vbl_scene_role_file(ctx, vel, vf, dir, medium->vdb_path, path, sizeof path))) return r;
    vbl_volume* v[3];
    if ((r = vbl_load_role_vec3(ctx->path, vf, VBL_ROLE_VELOCITY, path, grid, v))) return r;
    for (int a = 0; a < 3; ++a) medium->velocity.v[a] = v[a];
    medium->velocity.scale = scale;
    medium->velocity.max_speed = vbl_velocity_max_speed(&medium->velocity);
    return VBL_SUCCESS;
}

vbl_result vbl_scene_parse_motion(const vbl_json_ctx* ctx, const cJSON* root, vbl_scene* scene)
{
    vbl_result r;
    scene->fps = 24.0;
    if ((r = vbl_json_number(ctx, root, "", "fps", 0, &scene->fps))) return r;
    if (!(scene->fps > 0.0) || !isfinite(scene->fps)) return vbl_json_fail(ctx, "fps = %g must be > 0", scene->fps);
    int moving = 0;
    for (int i = 0; i < scene->media_count; ++i) /* a zero velocity grid moves nothing: no motion */
        moving |= scene->media[i].velocity.v[0] != NULL && scene->media[i].velocity.max_speed > 0.0;
    /* camera.shutter: [open, close] in frames relative to the frame, or a length centred on it;
     * default (a medium has a velocity): 0.5 frames centred, as Cycles */
    double open = -0.25, close = 0.25;
    const cJSON* cam = cJSON_GetObjectItemCaseSensitive(root, "camera");
    const cJSON* shutter = cJSON_IsObject(cam) ? cJSON_GetObjectItemCaseSensitive(cam, "shutter") : NULL;
    if (shutter) {
        if (cJSON_IsNumber(shutter)) {
            if (!(shutter->valuedouble >= 0.0) || !isfinite(shutter->valuedouble))
                return vbl_json_fail(ctx, "camera.shutter = %g must be a length >= 0 in frames", shutter->valuedouble);
            open = -0.5 * shutter->valuedouble;
            close = 0.5 * shutter->valuedouble;
        } else if (cJSON_IsArray(shutter) && cJSON_GetArraySize(shutter) == 2 &&
                   cJSON_IsNumber(cJSON_GetArrayItem(shutter, 0)) && cJSON_IsNumber(cJSON_GetArrayItem(shutter, 1))) {
            open = cJSON_GetArrayItem(shutter, 0)->valuedouble;
            close = cJSON_GetArrayItem(shutter, 1)->valuedouble;
            if (!isfinite(open) || !isfinite(close) || close < open || fabs(open) > 1e6 || fabs(close) > 1e6)
                return vbl_json_fail(ctx, "camera.shutter = [%g, %g] must be finite frames with open <= close", open,
                                     close);
        } else
            return vbl_json_fail(ctx, "camera.shutter must be [open, close] in frames or a length in frames");
    }
    scene->shutter_open = open / scene->fps;
    scene->shutter_close = close / scene->fps;
    scene->motion = moving && close > open;
    if (!scene->motion) return VBL_SUCCESS;
    const double max_time = fmax(fabs(scene->shutter_open), fabs(scene->shutter_close));
    for (int i = 0; i < scene->media_count; ++i) {
        if (!scene->media[i].velocity.v[0] || !(scene->media[i].velocity.max_speed > 0.0)) continue;
        if ((r = vbl_extinction_set_velocity(&scene->extinction, i, &scene->media[i].velocity, max_time)))
            return vbl_json_fail(ctx, "media[%d].velocity: %s", i, vbl_last_error_message());
    }
    return VBL_SUCCESS;
}
