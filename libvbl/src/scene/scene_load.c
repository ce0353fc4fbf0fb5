/* Scene file loader: JSON (cJSON) -> vbl_scene. Schema in docs/readme/render.md. */
#include <errno.h>
#include <float.h>
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "core/error.h"
#include "scene/scene.h"
#include "scene/scene_build.h"
#include "scene/scene_frame.h"
#include "scene/scene_render_block.h"
#include "media/media_emission.h"
#include "scene/scene_grids.h"
#include "scene/scene_motion.h"
#include "scene/scene_camera.h"
#include "scene/scene_keyframes.h"
#include "scene/scene_json.h"
#include "scene/scene_surfaces.h"

#define VBL_COLOR_MAX 1e30

static vbl_result vbl_read_text_file(const char* path, char** out_text)
{
    FILE* f = fopen(path, "rb");
    if (!f) return vbl_error(VBL_ERROR_FILE_NOT_FOUND, "%s: cannot open scene file (%s)", path, strerror(errno));
    size_t cap = 1 << 16, len = 0;
    char* text = malloc(cap);
    if (!text) {
        fclose(f);
        return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory reading the scene", path);
    }
    for (;;) {
        if (len + 1 >= cap) {
            char* grown = realloc(text, cap * 2);
            if (!grown) {
                free(text);
                fclose(f);
                return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory reading the scene", path);
            }
            text = grown;
            cap *= 2;
        }
        size_t n = fread(text + len, 1, cap - len - 1, f);
        len += n;
        if (n == 0) break;
    }
    int failed = ferror(f);
    fclose(f);
    if (failed) {
        free(text);
        return vbl_error(VBL_ERROR_FILE_IO, "%s: read error", path);
    }
    text[len] = '\0';
    *out_text = text;
    return VBL_SUCCESS;
}

/* Directory part of `path` including the trailing '/', or "" for a bare file name. */
static void vbl_path_dir(const char* path, char* out, size_t size)
{
    const char* slash = strrchr(path, '/');
    size_t n = slash ? (size_t)(slash - path + 1) : 0;
    if (n >= size) n = size - 1;
    memcpy(out, path, n);
    out[n] = '\0';
}

/* Scene colours in a named input space (top-level "color_space"), converted to scene_linear by
 * the caller's callback (vbl_scene_load_options.convert_color). `space` NULL: no conversion. */
typedef struct vbl_scene_colors {
    const char* space;
    vbl_result (*convert)(void* user, const char* color_space, const char* field, double rgb[3]);
    void* user;
} vbl_scene_colors;

/* A colour `key` of `obj` (vbl_json_rgb), converted from colors->space when the scene names one;
 * the range [min, max] applies to the converted (scene_linear) value. Keeps *out when absent. */
static vbl_result vbl_parse_color(const vbl_json_ctx* ctx, const vbl_scene_colors* colors, const cJSON* obj,
                                  const char* parent_field, const char* key, int required, double min, double max,
                                  vbl_vec3* out)
{
    if (!colors || !colors->space) return vbl_json_rgb(ctx, obj, parent_field, key, required, min, max, out);
    vbl_vec3 v = *out;
    vbl_result r = vbl_json_rgb(ctx, obj, parent_field, key, required, -DBL_MAX, DBL_MAX, &v);
    if (r) return r;
    if (!cJSON_GetObjectItemCaseSensitive(obj, key)) return VBL_SUCCESS;
    char field[512];
    vbl_json_field(field, sizeof field, parent_field, key);
    double rgb[3] = {v.x, v.y, v.z};
    vbl_clear_error();
    r = colors->convert(colors->user, colors->space, field, rgb);
    if (r) {
        char inner[1024];
        const char* msg = vbl_last_error_message();
        snprintf(inner, sizeof inner, "%s", msg && msg[0] ? msg : vbl_result_name(r));
        return vbl_error(r, "%s: color_space = \"%s\" (%s): %s", ctx->path, colors->space, field, inner);
    }
    for (int i = 0; i < 3; ++i)
        if (!(isfinite(rgb[i]) && rgb[i] >= min && rgb[i] <= max))
            return vbl_json_fail(ctx, "%s converts to [%g, %g, %g] in scene_linear: outside [%g, %g]", field, rgb[0],
                                 rgb[1], rgb[2], min, max);
    *out = vbl_v3(rgb[0], rgb[1], rgb[2]);
    return VBL_SUCCESS;
}

/* A light's "group": a name of letters, digits and '_' (at most 20); the first use adds it. */
static vbl_result vbl_scene_parse_light_group(const vbl_json_ctx* ctx, const cJSON* obj, const char* field,
                                              vbl_scene* scene, vbl_light* light)
{
    const char* name = NULL;
    vbl_result r = vbl_json_string(ctx, obj, field, "group", 0, &name);
    light->group = 0;
    if (r || !name) return r;
    size_t n = strlen(name);
    int ok = n > 0 && n <= 20; /* "lightgroup_<name>" fits a film layer name */
    for (size_t k = 0; ok && k < n; ++k)
        ok = (name[k] >= 'a' && name[k] <= 'z') || (name[k] >= 'A' && name[k] <= 'Z') ||
             (name[k] >= '0' && name[k] <= '9') || name[k] == '_';
    if (!ok)
        return vbl_json_fail(ctx, "%s.group = \"%s\" is not a name of 1 to 20 letters, digits or '_'", field, name);
    if (scene->light_group_count == 0) {
        snprintf(scene->light_groups[0], sizeof scene->light_groups[0], "default");
        scene->light_group_count = 1;
    }
    for (int g = 0; g < scene->light_group_count; ++g)
        if (!strcmp(scene->light_groups[g], name)) {
            light->group = g;
            return VBL_SUCCESS;
        }
    if (scene->light_group_count >= VBL_MAX_LIGHT_GROUPS)
        return vbl_json_fail(ctx, "%s.group = \"%s\": more than %d light groups", field, name, VBL_MAX_LIGHT_GROUPS - 1);
    snprintf(scene->light_groups[scene->light_group_count], sizeof scene->light_groups[0], "%s", name);
    light->group = scene->light_group_count++;
    return VBL_SUCCESS;
}

static vbl_result vbl_parse_light(const vbl_json_ctx* ctx, const vbl_scene_colors* colors, const cJSON* obj,
                                  const char* field, vbl_light* light)
{
    static const char* const point_keys[] = {"type", "position", "intensity", "group", NULL};
    static const char* const spot_keys[] = {"type", "position", "direction", "intensity",
                                            "inner_angle_deg", "outer_angle_deg", "group", NULL};
    static const char* const distant_keys[] = {"type", "direction", "irradiance", "group", NULL};
    static const char* const quad_keys[] = {"type", "corner", "edge1", "edge2", "radiance", "group", NULL};
    static const char* const env_keys[] = {"type", "radiance", "group", NULL};
    vbl_result r;
    if (!cJSON_IsObject(obj)) return vbl_json_fail(ctx, "%s must be an object", field);
    const char* type = NULL;
    if ((r = vbl_json_string(ctx, obj, field, "type", 1, &type))) return r;
    memset(light, 0, sizeof *light);
    if (!strcmp(type, "point") || !strcmp(type, "spot")) {
        int spot = type[0] == 's';
        light->type = spot ? VBL_LIGHT_SPOT : VBL_LIGHT_POINT;
        if ((r = vbl_json_check_keys(ctx, obj, field, spot ? spot_keys : point_keys))) return r;
        if ((r = vbl_json_vec3(ctx, obj, field, "position", 1, &light->position))) return r;
        if ((r = vbl_parse_color(ctx, colors, obj, field, "intensity", 1, 0.0, VBL_COLOR_MAX, &light->color))) return r;
        if (spot) {
            vbl_vec3 dir;
            double inner = 0.0, outer = 0.0;
            if ((r = vbl_json_vec3(ctx, obj, field, "direction", 1, &dir))) return r;
            if (!(vbl_v3_length(dir) > 0.0)) return vbl_json_fail(ctx, "%s.direction is zero", field);
            if ((r = vbl_json_number(ctx, obj, field, "outer_angle_deg", 1, &outer))) return r;
            inner = outer;
            if ((r = vbl_json_number(ctx, obj, field, "inner_angle_deg", 0, &inner))) return r;
            if (!(outer > 0.0 && outer <= 180.0))
                return vbl_json_fail(ctx, "%s.outer_angle_deg = %g is outside (0, 180]", field, outer);
            if (!(inner >= 0.0 && inner <= outer))
                return vbl_json_fail(ctx, "%s.inner_angle_deg = %g is outside [0, outer_angle_deg = %g]", field,
                                     inner, outer);
            light->direction = vbl_v3_normalize(dir);
            light->cos_inner = cos(inner * VBL_PI / 180.0);
            light->cos_outer = cos(outer * VBL_PI / 180.0);
        }
    } else if (!strcmp(type, "distant")) {
        light->type = VBL_LIGHT_DISTANT;
        vbl_vec3 dir;
        if ((r = vbl_json_check_keys(ctx, obj, field, distant_keys))) return r;
        if ((r = vbl_json_vec3(ctx, obj, field, "direction", 1, &dir))) return r;
        if (!(vbl_v3_length(dir) > 0.0)) return vbl_json_fail(ctx, "%s.direction is zero", field);
        light->direction = vbl_v3_normalize(dir);
        if ((r = vbl_parse_color(ctx, colors, obj, field, "irradiance", 1, 0.0, VBL_COLOR_MAX, &light->color))) return r;
    } else if (!strcmp(type, "quad")) {
        light->type = VBL_LIGHT_QUAD;
        if ((r = vbl_json_check_keys(ctx, obj, field, quad_keys))) return r;
        if ((r = vbl_json_vec3(ctx, obj, field, "corner", 1, &light->corner))) return r;
        if ((r = vbl_json_vec3(ctx, obj, field, "edge1", 1, &light->edge1))) return r;
        if ((r = vbl_json_vec3(ctx, obj, field, "edge2", 1, &light->edge2))) return r;
        if ((r = vbl_parse_color(ctx, colors, obj, field, "radiance", 1, 0.0, VBL_COLOR_MAX, &light->color))) return r;
        vbl_vec3 n = vbl_v3_cross(light->edge1, light->edge2);
        light->area = vbl_v3_length(n);
        if (!(light->area > 0.0)) return vbl_json_fail(ctx, "%s: edge1 and edge2 span no area", field);
        light->normal = vbl_v3_scale(n, 1.0 / light->area);
    } else if (!strcmp(type, "environment")) {
        light->type = VBL_LIGHT_ENVIRONMENT;
        if ((r = vbl_json_check_keys(ctx, obj, field, env_keys))) return r;
        if ((r = vbl_parse_color(ctx, colors, obj, field, "radiance", 1, 0.0, VBL_COLOR_MAX, &light->color))) return r;
    } else {
        return vbl_json_fail(ctx, "%s.type = \"%s\" is not one of point, spot, distant, quad, environment", field,
                             type);
    }
    return VBL_SUCCESS;
}

static vbl_result vbl_parse_transform(const vbl_json_ctx* ctx, const cJSON* item, const char* field,
                                      vbl_affine* to_scene, vbl_affine* to_volume)
{
    double m[4][4];
    if (!cJSON_IsArray(item) || cJSON_GetArraySize(item) != 4)
        return vbl_json_fail(ctx, "%s must be a 4x4 array of rows", field);
    for (int i = 0; i < 4; ++i) {
        const cJSON* row = cJSON_GetArrayItem(item, i);
        if (!cJSON_IsArray(row) || cJSON_GetArraySize(row) != 4)
            return vbl_json_fail(ctx, "%s[%d] must be an array of 4 numbers", field, i);
        for (int j = 0; j < 4; ++j) {
            const cJSON* c = cJSON_GetArrayItem(row, j);
            if (!cJSON_IsNumber(c) || !isfinite(c->valuedouble))
                return vbl_json_fail(ctx, "%s[%d][%d] must be a finite number", field, i, j);
            m[i][j] = c->valuedouble;
        }
    }
    if (m[3][0] != 0.0 || m[3][1] != 0.0 || m[3][2] != 0.0 || m[3][3] != 1.0)
        return vbl_json_fail(ctx, "%s: the last row must be [0, 0, 0, 1] (affine maps only)", field);
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 4; ++j) to_scene->m[i][j] = m[i][j];
    if (!vbl_affine_invert(to_scene, to_volume)) return vbl_json_fail(ctx, "%s is singular", field);
    return VBL_SUCCESS;
}

static vbl_result vbl_parse_medium(const vbl_json_ctx* ctx, const vbl_scene_colors* colors, const cJSON* obj,
                                   const char* field, const char* dir, const char* vdb_override,
                                   const vbl_scene_load_options* options, vbl_medium* medium)
{
    static const char* const keys[] = {"vdb",       "grid",     "density_scale", "albedo", "phase",
                                       "transform", "emission", "temperature",   "grid_index", "transform_frames",
                                       "velocity",  NULL};
    static const char* const phase_keys[] = {"type", "g", NULL};
    vbl_result r;
    if (!cJSON_IsObject(obj)) return vbl_json_fail(ctx, "%s must be an object", field);
    if ((r = vbl_json_check_keys(ctx, obj, field, keys))) return r;
    const char* vdb = NULL;
    const char* grid = "density";
    if ((r = vbl_json_string(ctx, obj, field, "vdb", vdb_override == NULL, &vdb))) return r;
    if ((r = vbl_json_string(ctx, obj, field, "grid", 0, &grid))) return r;
    double grid_index = -1.0; /* the grid_index-th grid of that name in file order (vbl info lists them) */
    if ((r = vbl_json_int(ctx, obj, field, "grid_index", 0, 0.0, 1e6, &grid_index))) return r;
    medium->density_scale = 1.0;
    if ((r = vbl_json_number(ctx, obj, field, "density_scale", 0, &medium->density_scale))) return r;
    if (medium->density_scale < 0.0)
        return vbl_json_fail(ctx, "%s.density_scale = %g is negative", field, medium->density_scale);
    medium->albedo = vbl_v3(1.0, 1.0, 1.0);
    const cJSON* albedo_grid = cJSON_GetObjectItemCaseSensitive(obj, "albedo");
    char albedo_field[512];
    vbl_json_field(albedo_field, sizeof albedo_field, field, "albedo");
    if (!cJSON_IsObject(albedo_grid)) {
        albedo_grid = NULL;
        if ((r = vbl_parse_color(ctx, colors, obj, field, "albedo", 0, 0.0, 1.0, &medium->albedo))) return r;
    } else if ((r = vbl_parse_color(ctx, colors, albedo_grid, albedo_field, "scale", 0, 0.0, 1.0, &medium->albedo))) {
        return r; /* {"grid", "vdb", "scale"}: albedo(x) = scale * A(x), loaded below */
    }
    medium->g = 0.0;
    const cJSON* phase = NULL;
    char phase_field[512];
    vbl_json_field(phase_field, sizeof phase_field, field, "phase");
    if ((r = vbl_json_object(ctx, obj, field, "phase", 0, &phase))) return r;
    if (phase) {
        const char* type = "hg";
        if ((r = vbl_json_check_keys(ctx, phase, phase_field, phase_keys))) return r;
        if ((r = vbl_json_string(ctx, phase, phase_field, "type", 0, &type))) return r;
        if (strcmp(type, "hg") && strcmp(type, "henyey-greenstein"))
            return vbl_json_fail(ctx, "%s.type = \"%s\" is not \"hg\"", phase_field, type);
        if ((r = vbl_json_number(ctx, phase, phase_field, "g", 0, &medium->g))) return r;
        if (!(medium->g > -1.0 && medium->g < 1.0))
            return vbl_json_fail(ctx, "%s.g = %g is outside (-1, 1)", phase_field, medium->g);
    }
    vbl_affine_set_identity(&medium->volume_to_scene);
    vbl_affine_set_identity(&medium->scene_to_volume);
    const cJSON* transform = cJSON_GetObjectItemCaseSensitive(obj, "transform");
    if (transform) {
        char tf[512];
        vbl_json_field(tf, sizeof tf, field, "transform");
        if ((r = vbl_parse_transform(ctx, transform, tf, &medium->volume_to_scene, &medium->scene_to_volume)))
            return r;
    }
    /* sequences: {"<frame>": 4x4, ...}, interpolated element by element between keyed frames
     * (exact for translation and scale; rotations between keys are approximate) */
    const cJSON* tframes = cJSON_GetObjectItemCaseSensitive(obj, "transform_frames");
    if (tframes && !cJSON_IsObject(tframes))
        return vbl_json_fail(ctx, "%s.transform_frames must be an object of frames", field);
    if (tframes && options && options->use_frame) {
        char tf[512];
        vbl_json_field(tf, sizeof tf, field, "transform_frames");
        const cJSON *below = NULL, *above = NULL;
        double w = 0.0;
        int found = vbl_keyframes_find(ctx, tframes, tf, NULL, options->frame, &below, &above, &w);
        if (found < 0) return VBL_ERROR_SCENE;
        if (found) {
            vbl_affine a, b, inv;
            char kf[600];
            snprintf(kf, sizeof kf, "%s.%s", tf, below->string);
            if ((r = vbl_parse_transform(ctx, below, kf, &a, &inv))) return r;
            snprintf(kf, sizeof kf, "%s.%s", tf, above->string);
            if ((r = vbl_parse_transform(ctx, above, kf, &b, &inv))) return r;
            for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 4; ++j) medium->volume_to_scene.m[i][j] = (1.0 - w) * a.m[i][j] + w * b.m[i][j];
            if (!vbl_affine_invert(&medium->volume_to_scene, &medium->scene_to_volume))
                return vbl_json_fail(ctx, "%s at frame %d is singular", tf, options->frame);
        }
    }
    /* resolve and load the VDB */
    if (vdb_override)
        snprintf(medium->vdb_path, sizeof medium->vdb_path, "%s", vdb_override);
    else if (vdb[0] == '/')
        snprintf(medium->vdb_path, sizeof medium->vdb_path, "%s", vdb);
    else
        snprintf(medium->vdb_path, sizeof medium->vdb_path, "%s%s", dir, vdb);
    FILE* probe = fopen(medium->vdb_path, "rb");
    if (!probe)
        return vbl_error(VBL_ERROR_FILE_NOT_FOUND, "%s: %s.vdb: cannot open '%s' (%s)", ctx->path, field,
                         medium->vdb_path, strerror(errno));
    fclose(probe);
    vbl_volume_load_options load = VBL_VOLUME_LOAD_OPTIONS_DEFAULT;
    load.grid_name = grid;
    load.grid_index = (int)grid_index;
    load.cancel = options ? options->cancel : NULL;
    r = vbl_volume_load(medium->vdb_path, &load, &medium->volume);
    if (r) {
        char inner[1024];
        snprintf(inner, sizeof inner, "%s", vbl_last_error_message());
        return vbl_error(r, "%s: %s.vdb = '%s': %s", ctx->path, field, medium->vdb_path, inner);
    }
    if (albedo_grid && (r = vbl_scene_parse_albedo_grid(ctx, albedo_grid, albedo_field, dir, medium))) return r;
    return vbl_scene_parse_velocity(ctx, obj, field, dir, medium);
}

/* The emission roles of medium `index` (docs/readme/emission.md): "emission" {grid, vdb, color,
 * scale} and "temperature" {grid, vdb, scale, offset, blackbody_intensity, normalization}. */
static vbl_result vbl_parse_medium_emission(const vbl_json_ctx* ctx, const vbl_scene_colors* colors, const cJSON* obj,
                                            const char* field, const char* dir, vbl_scene* scene, int index)
{
    static const char* const emission_keys[] = {"grid", "vdb", "color", "scale", NULL};
    static const char* const temperature_keys[] = {"grid",  "vdb", "scale", "offset", "blackbody_intensity",
                                                   "normalization", NULL};
    const cJSON *em = NULL, *te = NULL;
    char ef[512], tf[512], path[1024];
    vbl_json_field(ef, sizeof ef, field, "emission");
    vbl_json_field(tf, sizeof tf, field, "temperature");
    vbl_result r;
    if ((r = vbl_json_object(ctx, obj, field, "emission", 0, &em))) return r;
    if ((r = vbl_json_object(ctx, obj, field, "temperature", 0, &te))) return r;
    if (!em && !te) return VBL_SUCCESS;
    vbl_volume *emission = NULL, *temperature = NULL;
    vbl_vec3 color = vbl_v3(1.0, 1.0, 1.0);
    double scale = 1.0, t_scale = 1.0, t_offset = 0.0, intensity = 1.0;
    vbl_blackbody_normalization norm = VBL_BLACKBODY_PEAK;
    const char* medium_path = scene->media[index].vdb_path;
    if (em) {
        const char* grid = NULL;
        if ((r = vbl_json_check_keys(ctx, em, ef, emission_keys))) goto done;
        if ((r = vbl_json_string(ctx, em, ef, "grid", 0, &grid))) goto done;
        if ((r = vbl_parse_color(ctx, colors, em, ef, "color", 0, 0.0, VBL_COLOR_MAX, &color))) goto done;
        if ((r = vbl_json_number(ctx, em, ef, "scale", 0, &scale))) goto done;
        if (!(scale >= 0.0)) {
            r = vbl_json_fail(ctx, "%s.scale = %g is negative", ef, scale);
            goto done;
        }
        if ((r = vbl_scene_role_file(ctx, em, ef, dir, medium_path, path, sizeof path))) goto done;
        if ((r = vbl_load_role_grid(ctx->path, ef, VBL_ROLE_EMISSION, path, grid, &emission))) goto done;
    }
    if (te) {
        const char *grid = NULL, *normalization = "peak";
        if ((r = vbl_json_check_keys(ctx, te, tf, temperature_keys))) goto done;
        if ((r = vbl_json_string(ctx, te, tf, "grid", 0, &grid))) goto done;
        if ((r = vbl_json_number(ctx, te, tf, "scale", 0, &t_scale))) goto done;
        if ((r = vbl_json_number(ctx, te, tf, "offset", 0, &t_offset))) goto done;
        if ((r = vbl_json_number(ctx, te, tf, "blackbody_intensity", 0, &intensity))) goto done;
        if ((r = vbl_json_string(ctx, te, tf, "normalization", 0, &normalization))) goto done;
        if (!(intensity >= 0.0)) {
            r = vbl_json_fail(ctx, "%s.blackbody_intensity = %g is negative", tf, intensity);
            goto done;
        }
        if (!strcmp(normalization, "luminance")) norm = VBL_BLACKBODY_LUMINANCE;
        else if (strcmp(normalization, "peak")) {
            r = vbl_json_fail(ctx, "%s.normalization = \"%s\" is not \"peak\" or \"luminance\"", tf, normalization);
            goto done;
        }
        if ((r = vbl_scene_role_file(ctx, te, tf, dir, medium_path, path, sizeof path))) goto done;
        if ((r = vbl_load_role_grid(ctx->path, tf, VBL_ROLE_TEMPERATURE, path, grid, &temperature))) goto done;
    }
    r = vbl_scene_set_medium_emission(scene, index, emission, color, scale, temperature, t_scale, t_offset, intensity,
                                      norm);
done:
    if (emission) vbl_volume_release(emission);
    if (temperature) vbl_volume_release(temperature);
    return r;
}

/* Surface colours go through the same conversion as media albedo (scene_surfaces.h). */
static vbl_result vbl_surface_color(const vbl_json_ctx* ctx, const void* colors, const cJSON* obj,
                                    const char* parent_field, const char* key, double min, double max, vbl_vec3* out)
{
    return vbl_parse_color(ctx, colors, obj, parent_field, key, 0, min, max, out);
}

static vbl_result vbl_scene_parse(vbl_scene* scene, const cJSON* root, const vbl_scene_load_options* options)
{
    static const char* const keys[] = {"camera", "cameras", "lights", "media", "render", "color_space", "surfaces", "fps", NULL};
    vbl_json_ctx ctx = {scene->path};
    vbl_result r;
    if (!cJSON_IsObject(root)) return vbl_json_fail(&ctx, "the top level must be an object");
    if ((r = vbl_json_check_keys(&ctx, root, "", keys))) return r;

    /* colours in a named input space: converted to scene_linear by the caller's callback */
    vbl_scene_colors colors = {NULL, NULL, NULL};
    const char* color_space = NULL;
    if ((r = vbl_json_string(&ctx, root, "", "color_space", 0, &color_space))) return r;
    if (color_space) {
        if (!color_space[0]) return vbl_json_fail(&ctx, "color_space is empty");
        if (strlen(color_space) >= sizeof scene->color_space)
            return vbl_json_fail(&ctx, "color_space is too long (at most %d characters)",
                                 (int)sizeof scene->color_space - 1);
        if (!options || !options->convert_color)
            return vbl_json_fail(&ctx, "color_space = \"%s\" needs a colour-managed loader (vbl render, or "
                                       "vbl_scene_load_ex with convert_color)", color_space);
        snprintf(scene->color_space, sizeof scene->color_space, "%s", color_space);
        colors.space = scene->color_space;
        colors.convert = options->convert_color;
        colors.user = options->convert_color_user;
    }

    const cJSON* lights = cJSON_GetObjectItemCaseSensitive(root, "lights");
    if (lights) {
        if (!cJSON_IsArray(lights)) return vbl_json_fail(&ctx, "lights must be an array");
        if (cJSON_GetArraySize(lights) > VBL_MAX_LIGHTS)
            return vbl_json_fail(&ctx, "lights has %d entries (at most %d)", cJSON_GetArraySize(lights), VBL_MAX_LIGHTS);
        int i = 0;
        for (const cJSON* l = lights->child; l; l = l->next, ++i) {
            char field[64];
            snprintf(field, sizeof field, "lights[%d]", i);
            if ((r = vbl_parse_light(&ctx, &colors, l, field, &scene->lights[i]))) return r;
            if ((r = vbl_scene_parse_light_group(&ctx, l, field, scene, &scene->lights[i]))) return r;
            if (vbl_v3_max_component(scene->lights[i].color) <= 0.0) continue; /* black lights do nothing */
            if (scene->lights[i].type == VBL_LIGHT_QUAD || scene->lights[i].type == VBL_LIGHT_ENVIRONMENT)
                scene->has_visible_lights = 1;
            else
                scene->has_delta_lights = 1;
        }
        scene->light_count = i;
    }

    char dir[1024];
    vbl_path_dir(scene->path, dir, sizeof dir);
    const cJSON* media = cJSON_GetObjectItemCaseSensitive(root, "media");
    if (media) {
        if (!cJSON_IsArray(media)) return vbl_json_fail(&ctx, "media must be an array");
        if (cJSON_GetArraySize(media) > VBL_MAX_MEDIA)
            return vbl_json_fail(&ctx, "media has %d entries (at most %d)", cJSON_GetArraySize(media), VBL_MAX_MEDIA);
        int i = 0;
        for (const cJSON* m = media->child; m; m = m->next, ++i) {
            char field[64];
            snprintf(field, sizeof field, "media[%d]", i);
            const char* override = NULL;
            if (options && options->vdb_overrides && i < options->vdb_override_count)
                override = options->vdb_overrides[i];
            char framed[1024]; /* VDB sequences: frame patterns (scene_frame.h) */
            if ((r = vbl_scene_frame_vdb(ctx.path, field, m, dir, options, &override, framed, sizeof framed)))
                return r;
            if (options && options->cancel && *options->cancel)
                return vbl_error(VBL_ERROR_INTERRUPTED, "%s: load cancelled before %s", ctx.path, field);
            scene->media_count = i + 1; /* so a failure releases what was loaded */
            if ((r = vbl_parse_medium(&ctx, &colors, m, field, dir, override, options, &scene->media[i]))) return r;
            if ((r = vbl_parse_medium_emission(&ctx, &colors, m, field, dir, scene, i))) return r;
        }
        scene->media_count = i;
    }
    if (options && options->vdb_override_count > scene->media_count)
        return vbl_json_fail(&ctx, "%d VDB overrides given but the scene has %d media", options->vdb_override_count,
                             scene->media_count);

    if ((r = vbl_scene_parse_surfaces(scene, &ctx, root, dir, vbl_surface_color, &colors))) return r;
    /* after the media: "frame_media" frames their bounds */
    if ((r = vbl_scene_parse_camera(&ctx, root, scene, options, &scene->camera))) return r;

    vbl_render_options defaults = VBL_RENDER_OPTIONS_DEFAULT;
    scene->render = defaults;
    if ((r = vbl_scene_parse_render_block(&ctx, root, &scene->render))) return r;

    /* the extinction field (components in media order) */
    vbl_extinction_init(&scene->extinction);
    for (int i = 0; i < scene->media_count; ++i) {
        r = vbl_extinction_add(&scene->extinction, scene->media[i].volume, scene->media[i].density_scale,
                               &scene->media[i].scene_to_volume);
        if (r) return vbl_json_fail(&ctx, "media[%d]: %s", i, vbl_last_error_message());
        scene->has_albedo_grids |= scene->media[i].albedo_volume[0] != NULL;
    }
    return vbl_scene_parse_motion(&ctx, root, scene);
}

vbl_result vbl_scene_load_ex(const char* path, const vbl_scene_load_options* options, vbl_scene** out_scene)
{
    if (!path || !out_scene) return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_scene_load: NULL argument");
    /* callers built before convert_color (a smaller struct) get no colour conversion */
    vbl_scene_load_options copy = VBL_SCENE_LOAD_OPTIONS_DEFAULT;
    if (options) {
        if (options->size < offsetof(vbl_scene_load_options, convert_color))
            return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_scene_load: options.size is too small");
        memcpy(&copy, options, options->size < sizeof copy ? options->size : sizeof copy);
        copy.size = sizeof copy;
        options = &copy;
    }
    *out_scene = NULL;
    if (strlen(path) >= 1024) return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_scene_load: path too long");
    char* text = NULL;
    vbl_result r = vbl_read_text_file(path, &text);
    if (r) return r;
    const char* end = NULL;
    cJSON* root = cJSON_ParseWithOpts(text, &end, 0);
    if (!root) {
        int line = 1;
        for (const char* p = text; end && p < end && *p; ++p) line += *p == '\n';
        free(text);
        return vbl_error(VBL_ERROR_CORRUPT_FILE, "%s: invalid JSON near line %d", path, line);
    }
    free(text);
    vbl_scene* scene = calloc(1, sizeof *scene);
    if (!scene) {
        cJSON_Delete(root);
        return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    }
    scene->refcount = 1;
    snprintf(scene->path, sizeof scene->path, "%s", path);
    r = vbl_scene_parse(scene, root, options);
    cJSON_Delete(root);
    if (r) {
        vbl_scene_release(scene);
        return r;
    }
    *out_scene = scene;
    return VBL_SUCCESS;
}

vbl_result vbl_scene_load(const char* path, vbl_scene** out_scene)
{
    return vbl_scene_load_ex(path, NULL, out_scene);
}
