/* The scene's camera (scene_camera.h): which camera (the scene's "camera", a named one of
 * "cameras", or a camera file), its lens (vertical fov, or focal length + sensor + fit as in
 * Blender), the resolution (the scene's or the caller's override) and the automatic framing of the
 * media's bounding box. */
#define _POSIX_C_SOURCE 200809L
#include "scene/scene_camera.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "scene/scene_build.h"
#include "scene/scene_keyframes.h"

/* The media's bounding box in scene space: the 8 corners of every volume's world bounds through
 * its placement. 0 without media. */
static int vbl_camera_media_bounds(const vbl_scene* scene, vbl_vec3* lo, vbl_vec3* hi)
{
    int any = 0;
    for (int m = 0; m < scene->media_count; ++m) {
        vbl_volume_info info;
        memset(&info, 0, sizeof info);
        info.size = sizeof info;
        if (!scene->media[m].volume || vbl_volume_get_info(scene->media[m].volume, &info)) continue;
        for (int c = 0; c < 8; ++c) {
            vbl_vec3 p = vbl_v3(c & 1 ? info.world_bbox_max[0] : info.world_bbox_min[0],
                                c & 2 ? info.world_bbox_max[1] : info.world_bbox_min[1],
                                c & 4 ? info.world_bbox_max[2] : info.world_bbox_min[2]);
            p = vbl_affine_point(&scene->media[m].volume_to_scene, p);
            if (!any) *lo = *hi = p;
            lo->x = fmin(lo->x, p.x), lo->y = fmin(lo->y, p.y), lo->z = fmin(lo->z, p.z);
            hi->x = fmax(hi->x, p.x), hi->y = fmax(hi->y, p.y), hi->z = fmax(hi->z, p.z);
            any = 1;
        }
    }
    return any;
}

double vbl_camera_tan_half_vfov(double focal_length, double sensor_width, double sensor_height,
                                vbl_sensor_fit fit, int width, int height)
{
    const double aspect = (double)width / (double)height;
    if (fit == VBL_SENSOR_FIT_AUTO) { /* Blender: the sensor width spans the larger dimension */
        if (width >= height) return sensor_width / (2.0 * focal_length) / aspect;
        return sensor_width / (2.0 * focal_length);
    }
    if (fit == VBL_SENSOR_FIT_HORIZONTAL) return sensor_width / (2.0 * focal_length) / aspect;
    return sensor_height / (2.0 * focal_length);
}

/* "resolution": [w, h], each an integer in [1, 32768]. */
static vbl_result vbl_camera_resolution(const vbl_json_ctx* ctx, const cJSON* obj, const char* field, int required,
                                        int wh[2])
{
    const cJSON* res = cJSON_GetObjectItemCaseSensitive(obj, "resolution");
    if (!res) return required ? vbl_json_fail(ctx, "%s.resolution is missing", field) : VBL_SUCCESS;
    if (!cJSON_IsArray(res) || cJSON_GetArraySize(res) != 2)
        return vbl_json_fail(ctx, "%s.resolution must be an array [width, height]", field);
    for (int i = 0; i < 2; ++i) {
        const cJSON* c = cJSON_GetArrayItem(res, i);
        if (!cJSON_IsNumber(c) || c->valuedouble != floor(c->valuedouble))
            return vbl_json_fail(ctx, "%s.resolution[%d] must be an integer", field, i);
        if (c->valuedouble < 1 || c->valuedouble > 32768)
            return vbl_json_fail(ctx, "%s.resolution[%d] = %g is outside [1, 32768]", field, i, c->valuedouble);
        wh[i] = (int)c->valuedouble;
    }
    return VBL_SUCCESS;
}

/* One camera object (or the string "auto") named `field`. */
static vbl_result vbl_camera_from_json(const vbl_json_ctx* ctx, const cJSON* obj, const char* field,
                                       const vbl_scene* scene, const vbl_scene_load_options* options,
                                       vbl_camera* cam)
{
    static const char* const keys[] = {"position",     "look_at",       "up",         "fov_deg",
                                       "resolution",   "focal_length",  "sensor_width", "sensor_height",
                                       "sensor_fit",   "frame_media",   "frames",       "shutter",
                                       NULL};
    static const char* const key_keys[] = {"position", "look_at", "up", "fov_deg", "focal_length", NULL};
    static const char* const frame_keys[] = {"direction", "margin", NULL};
    vbl_result r;
    const int framed_string = cJSON_IsString(obj) && !strcmp(obj->valuestring, "auto");
    if (!framed_string && !cJSON_IsObject(obj))
        return vbl_json_fail(ctx, "%s must be an object or \"auto\"", field);
    cJSON* placeholder = NULL;
    if (framed_string) {
        placeholder = cJSON_CreateObject();
        if (!placeholder) return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory", ctx->path);
        cJSON_AddItemToObject(placeholder, "frame_media", cJSON_CreateObject());
        obj = placeholder;
    }
    r = vbl_json_check_keys(ctx, obj, field, keys);
    const cJSON* frame = NULL;
    if (!r) r = vbl_json_object(ctx, obj, field, "frame_media", 0, &frame);
    vbl_vec3 position = vbl_v3(0, 0, 0), look_at = vbl_v3(0, 0, 0), up = vbl_v3(0.0, 0.0, 1.0);
    double fov = 40.0, focal = 0.0, sensor_w = 36.0, sensor_h = 24.0;
    const char* fit_name = "auto";
    if (!r && !frame) r = vbl_json_vec3(ctx, obj, field, "position", 1, &position);
    if (!r && !frame) r = vbl_json_vec3(ctx, obj, field, "look_at", 1, &look_at);
    if (!r && frame && (cJSON_GetObjectItemCaseSensitive(obj, "position") || cJSON_GetObjectItemCaseSensitive(obj, "look_at")))
        r = vbl_json_fail(ctx, "%s: frame_media places the camera itself (no position / look_at)", field);
    if (!r) r = vbl_json_vec3(ctx, obj, field, "up", 0, &up);
    if (!r) r = vbl_json_number(ctx, obj, field, "fov_deg", 0, &fov);
    if (!r && !(fov > 0.0 && fov < 180.0)) r = vbl_json_fail(ctx, "%s.fov_deg = %g is outside (0, 180)", field, fov);
    const int has_focal = cJSON_GetObjectItemCaseSensitive(obj, "focal_length") != NULL;
    if (!r && has_focal && cJSON_GetObjectItemCaseSensitive(obj, "fov_deg"))
        r = vbl_json_fail(ctx, "%s: give fov_deg or focal_length, not both", field);
    if (!r) r = vbl_json_number(ctx, obj, field, "focal_length", 0, &focal);
    if (!r) r = vbl_json_number(ctx, obj, field, "sensor_width", 0, &sensor_w);
    if (!r) r = vbl_json_number(ctx, obj, field, "sensor_height", 0, &sensor_h);
    if (!r) r = vbl_json_string(ctx, obj, field, "sensor_fit", 0, &fit_name);
    if (!r && has_focal && !(focal > 0.0 && focal < 1e6))
        r = vbl_json_fail(ctx, "%s.focal_length = %g mm is outside (0, 1e6)", field, focal);
    if (!r && !(sensor_w > 0.0 && sensor_w < 1e6 && sensor_h > 0.0 && sensor_h < 1e6))
        r = vbl_json_fail(ctx, "%s.sensor_width / sensor_height = %g / %g mm: each must be in (0, 1e6)", field, sensor_w,
                          sensor_h);
    /* sequences: per-frame values, interpolated between keyed frames (scene_keyframes.h) */
    const cJSON* frames = cJSON_GetObjectItemCaseSensitive(obj, "frames");
    if (!r && frames && !cJSON_IsObject(frames)) r = vbl_json_fail(ctx, "%s.frames must be an object of frames", field);
    if (!r && frames && options && options->use_frame) {
        char kf[512];
        vbl_json_field(kf, sizeof kf, field, "frames");
        for (const cJSON* k = frames->child; !r && k; k = k->next) {
            char one[600];
            snprintf(one, sizeof one, "%s.%s", kf, k->string ? k->string : "");
            if (!cJSON_IsObject(k)) r = vbl_json_fail(ctx, "%s must be an object", one);
            else r = vbl_json_check_keys(ctx, k, one, key_keys);
            if (!r && !has_focal && cJSON_GetObjectItemCaseSensitive(k, "focal_length"))
                r = vbl_json_fail(ctx, "%s.focal_length: animate a focal_length only on a camera that has one", one);
        }
        if (!r && !frame) r = vbl_keyframes_vec3(ctx, frames, kf, "position", options->frame, &position);
        if (!r && !frame) r = vbl_keyframes_vec3(ctx, frames, kf, "look_at", options->frame, &look_at);
        if (!r) r = vbl_keyframes_vec3(ctx, frames, kf, "up", options->frame, &up);
        if (!r) r = vbl_keyframes_number(ctx, frames, kf, "fov_deg", options->frame, &fov);
        if (!r) r = vbl_keyframes_number(ctx, frames, kf, "focal_length", options->frame, &focal);
        if (!r && !(fov > 0.0 && fov < 180.0))
            r = vbl_json_fail(ctx, "%s: fov_deg = %g at frame %d is outside (0, 180)", kf, fov, options->frame);
        if (!r && has_focal && !(focal > 0.0 && focal < 1e6))
            r = vbl_json_fail(ctx, "%s: focal_length = %g mm at frame %d is outside (0, 1e6)", kf, focal, options->frame);
    }
    vbl_sensor_fit fit = VBL_SENSOR_FIT_AUTO;
    if (!r) {
        if (!strcmp(fit_name, "auto")) fit = VBL_SENSOR_FIT_AUTO;
        else if (!strcmp(fit_name, "horizontal")) fit = VBL_SENSOR_FIT_HORIZONTAL;
        else if (!strcmp(fit_name, "vertical")) fit = VBL_SENSOR_FIT_VERTICAL;
        else r = vbl_json_fail(ctx, "%s.sensor_fit = \"%s\" is not auto, horizontal or vertical", field, fit_name);
    }
    int wh[2] = {640, 480};
    if (!r) r = vbl_camera_resolution(ctx, obj, field, !frame && !(options && options->width > 0), wh);
    if (!r && options && options->width > 0 && options->height > 0) wh[0] = options->width, wh[1] = options->height;
    double tan_v = tan(0.5 * fov * VBL_PI / 180.0);
    if (has_focal) tan_v = vbl_camera_tan_half_vfov(focal, sensor_w, sensor_h, fit, wh[0], wh[1]);
    if (!r && frame) {
        /* the bounding sphere of the media's box inside the narrower of the two fovs */
        vbl_vec3 dir = vbl_v3(0.0, 1.0, 0.0), lo = vbl_v3(0, 0, 0), hi = vbl_v3(0, 0, 0);
        double margin = 1.05;
        char ff[512];
        vbl_json_field(ff, sizeof ff, field, "frame_media");
        r = vbl_json_check_keys(ctx, frame, ff, frame_keys);
        if (!r) r = vbl_json_vec3(ctx, frame, ff, "direction", 0, &dir);
        if (!r) r = vbl_json_number(ctx, frame, ff, "margin", 0, &margin);
        if (!r && !(margin >= 1.0 && margin < 1e3))
            r = vbl_json_fail(ctx, "%s.margin = %g is outside [1, 1000)", ff, margin);
        if (!r && !(vbl_v3_length(dir) > 0.0)) r = vbl_json_fail(ctx, "%s.direction is zero", ff);
        if (!r && !vbl_camera_media_bounds(scene, &lo, &hi))
            r = vbl_json_fail(ctx, "%s: the scene has no media to frame", ff);
        if (!r) {
            dir = vbl_v3_normalize(dir);
            vbl_vec3 centre = vbl_v3_scale(vbl_v3_add(lo, hi), 0.5);
            double radius = 0.5 * vbl_v3_length(vbl_v3_sub(hi, lo));
            double aspect = (double)wh[0] / (double)wh[1];
            double half = atan(fmin(tan_v, tan_v * aspect));
            double distance = margin * fmax(radius, 1e-9) / sin(half);
            look_at = centre;
            position = vbl_v3_madd(centre, dir, -distance);
        }
    }
    cJSON_Delete(placeholder);
    if (r) return r;
    if (!(vbl_v3_length(vbl_v3_sub(look_at, position)) > 0.0))
        return vbl_json_fail(ctx, "%s.look_at equals %s.position", field, field);
    if (!(tan_v > 0.0 && isfinite(tan_v)))
        return vbl_json_fail(ctx, "%s: the lens gives no field of view", field);
    if (vbl_camera_make(position, look_at, up, 1.0, wh[0], wh[1], cam))
        return vbl_json_fail(ctx, "%s.up is zero or parallel to the view direction", field);
    cam->tan_half_fov = tan_v;
    return VBL_SUCCESS;
}

vbl_result vbl_scene_parse_camera(const vbl_json_ctx* ctx, const cJSON* root, const vbl_scene* scene,
                                  const vbl_scene_load_options* options, vbl_camera* cam)
{
    const char* pick = options ? options->camera : NULL;
    const cJSON* cameras = cJSON_GetObjectItemCaseSensitive(root, "cameras");
    if (cameras && !cJSON_IsObject(cameras)) return vbl_json_fail(ctx, "cameras must be an object of named cameras");
    if (!pick || !pick[0]) {
        const cJSON* obj = cJSON_GetObjectItemCaseSensitive(root, "camera");
        if (!obj) return vbl_json_fail(ctx, "camera is missing");
        return vbl_camera_from_json(ctx, obj, "camera", scene, options, cam);
    }
    const cJSON* named = cameras ? cJSON_GetObjectItemCaseSensitive(cameras, pick) : NULL;
    if (named) {
        char field[512];
        snprintf(field, sizeof field, "cameras.%s", pick);
        return vbl_camera_from_json(ctx, named, field, scene, options, cam);
    }
    /* a camera file: a camera object, or an object with a "camera" */
    FILE* f = fopen(pick, "rb");
    if (!f)
        return vbl_error(VBL_ERROR_FILE_NOT_FOUND, "%s: camera '%s' is neither in the scene's cameras nor a file (%s)",
                         ctx->path, pick, strerror(errno));
    char* text = NULL;
    size_t size = 0, cap = 0, n;
    char buf[4096];
    while ((n = fread(buf, 1, sizeof buf, f)) > 0) {
        if (size + n + 1 > cap) {
            cap = 2 * (size + n + 1);
            if (cap > ((size_t)1 << 24)) break; /* a camera is small */
            char* grown = realloc(text, cap);
            if (!grown) break;
            text = grown;
        }
        memcpy(text + size, buf, n);
        size += n;
    }
    fclose(f);
    if (!text) return vbl_error(VBL_ERROR_CORRUPT_FILE, "%s: camera file '%s' is empty or too large", ctx->path, pick);
    text[size] = 0;
    cJSON* doc = cJSON_Parse(text);
    free(text);
    vbl_json_ctx file_ctx = {pick};
    if (!doc) return vbl_error(VBL_ERROR_CORRUPT_FILE, "%s: invalid JSON", pick);
    const cJSON* obj = cJSON_GetObjectItemCaseSensitive(doc, "camera");
    vbl_result r = vbl_camera_from_json(&file_ctx, obj ? obj : doc, obj ? "camera" : "(camera file)", scene, options, cam);
    cJSON_Delete(doc);
    return r;
}
