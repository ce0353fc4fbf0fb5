/* Programmatic scene building: camera construction, media and lights appended to a scene. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "scene/scene.h"
#include "scene/scene_build.h"

vbl_result vbl_camera_make(vbl_vec3 position, vbl_vec3 look_at, vbl_vec3 up, double fov_deg, int width, int height,
                           vbl_camera* out)
{
    vbl_vec3 f = vbl_v3_sub(look_at, position);
    if (!(vbl_v3_length(f) > 0.0)) return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "camera: look_at equals position");
    f = vbl_v3_normalize(f);
    vbl_vec3 right = vbl_v3_cross(f, up);
    if (!(vbl_v3_length(right) > 1e-12 * fmax(1.0, vbl_v3_length(up))))
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "camera: up is zero or parallel to the view direction");
    if (!(fov_deg > 0.0 && fov_deg < 180.0) || width < 1 || height < 1)
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "camera: bad fov or resolution");
    out->position = position;
    out->forward = f;
    out->right = vbl_v3_normalize(right);
    out->up = vbl_v3_cross(out->right, f);
    out->tan_half_fov = tan(0.5 * fov_deg * VBL_PI / 180.0);
    out->width = width;
    out->height = height;
    return VBL_SUCCESS;
}

int vbl_affine_invert(const vbl_affine* a, vbl_affine* out)
{
    const double(*m)[4] = a->m;
    double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                 m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    double scale = 0.0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) scale = fmax(scale, fabs(m[i][j]));
    if (!(fabs(det) > 1e-12 * scale * scale * scale)) return 0;
    double inv[3][3] = {{(m[1][1] * m[2][2] - m[1][2] * m[2][1]) / det, (m[0][2] * m[2][1] - m[0][1] * m[2][2]) / det,
                         (m[0][1] * m[1][2] - m[0][2] * m[1][1]) / det},
                        {(m[1][2] * m[2][0] - m[1][0] * m[2][2]) / det, (m[0][0] * m[2][2] - m[0][2] * m[2][0]) / det,
                         (m[0][2] * m[1][0] - m[0][0] * m[1][2]) / det},
                        {(m[1][0] * m[2][1] - m[1][1] * m[2][0]) / det, (m[0][1] * m[2][0] - m[0][0] * m[2][1]) / det,
                         (m[0][0] * m[1][1] - m[0][1] * m[1][0]) / det}};
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) out->m[i][j] = inv[i][j];
        out->m[i][3] = -(inv[i][0] * m[0][3] + inv[i][1] * m[1][3] + inv[i][2] * m[2][3]);
    }
    return 1;
}

void vbl_affine_set_identity(vbl_affine* a)
{
    memset(a, 0, sizeof *a);
    a->m[0][0] = a->m[1][1] = a->m[2][2] = 1.0;
}

vbl_result vbl_scene_create_empty(const char* name, const vbl_camera* camera, vbl_scene** out_scene)
{
    vbl_scene* scene = calloc(1, sizeof *scene);
    if (!scene) return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "scene: out of memory");
    scene->refcount = 1;
    snprintf(scene->path, sizeof scene->path, "%s", name ? name : "(scene)");
    scene->camera = *camera;
    vbl_render_options defaults = VBL_RENDER_OPTIONS_DEFAULT;
    scene->render = defaults;
    vbl_extinction_init(&scene->extinction);
    *out_scene = scene;
    return VBL_SUCCESS;
}

vbl_result vbl_scene_add_medium(vbl_scene* scene, vbl_volume* volume, double density_scale, vbl_vec3 albedo,
                                double g, const vbl_affine* volume_to_scene)
{
    if (scene->media_count >= VBL_MAX_MEDIA)
        return vbl_error(VBL_ERROR_UNSUPPORTED, "%s: at most %d media", scene->path, VBL_MAX_MEDIA);
    if (!(g > -1.0 && g < 1.0)) return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "%s: g = %g is outside (-1, 1)", scene->path, g);
    vbl_medium* m = &scene->media[scene->media_count];
    memset(m, 0, sizeof *m);
    if (volume_to_scene) {
        m->volume_to_scene = *volume_to_scene;
        if (!vbl_affine_invert(volume_to_scene, &m->scene_to_volume))
            return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "%s: singular medium transform", scene->path);
    } else {
        vbl_affine_set_identity(&m->volume_to_scene);
        vbl_affine_set_identity(&m->scene_to_volume);
    }
    vbl_result r = vbl_extinction_add(&scene->extinction, volume, density_scale, &m->scene_to_volume);
    if (r) return r;
    vbl_volume_retain(volume);
    m->volume = volume;
    m->density_scale = density_scale;
    m->albedo = albedo;
    m->g = g;
    scene->media_count++;
    return VBL_SUCCESS;
}

vbl_result vbl_scene_add_light(vbl_scene* scene, const vbl_light* light)
{
    if (scene->light_count >= VBL_MAX_LIGHTS)
        return vbl_error(VBL_ERROR_UNSUPPORTED, "%s: at most %d lights", scene->path, VBL_MAX_LIGHTS);
    scene->lights[scene->light_count++] = *light;
    if (vbl_v3_max_component(light->color) > 0.0) {
        if (light->type == VBL_LIGHT_QUAD || light->type == VBL_LIGHT_ENVIRONMENT)
            scene->has_visible_lights = 1;
        else
            scene->has_delta_lights = 1;
    }
    return VBL_SUCCESS;
}
