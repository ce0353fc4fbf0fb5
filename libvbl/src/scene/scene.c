/* Scene lifecycle, getters and the pinhole camera. */
#include "scene/scene.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "volume/volume.h"

void vbl_scene_retain(vbl_scene* scene)
{
    if (scene) __atomic_add_fetch(&scene->refcount, 1, __ATOMIC_RELAXED);
}

void vbl_scene_release(vbl_scene* scene)
{
    if (!scene || __atomic_sub_fetch(&scene->refcount, 1, __ATOMIC_ACQ_REL) != 0) return;
    for (int i = 0; i < scene->media_count; ++i) {
        vbl_medium* m = &scene->media[i];
        if (m->volume) vbl_volume_release(m->volume);
        if (m->emission_volume) vbl_volume_release(m->emission_volume);
        if (m->temperature_volume) vbl_volume_release(m->temperature_volume);
        for (int a = 0; a < 3; ++a) {
            if (m->albedo_volume[a]) vbl_volume_release(m->albedo_volume[a]);
            if (m->velocity.v[a]) vbl_volume_release((vbl_volume*)m->velocity.v[a]);
        }
        vbl_blackbody_table_free(&m->blackbody);
    }
    vbl_emission_lights_free(&scene->emission_lights);
    vbl_extinction_free(&scene->extinction);
    vbl_scene_free_surfaces(scene);
    free(scene);
}

const char* vbl_scene_path(const vbl_scene* scene) { return scene ? scene->path : NULL; }

void vbl_scene_resolution(const vbl_scene* scene, int* width, int* height)
{
    if (width) *width = scene ? scene->camera.width : 0;
    if (height) *height = scene ? scene->camera.height : 0;
}

int vbl_scene_light_count(const vbl_scene* scene) { return scene ? scene->light_count : 0; }
int vbl_scene_medium_count(const vbl_scene* scene) { return scene ? scene->media_count : 0; }
int vbl_scene_has_emission(const vbl_scene* scene) { return scene ? scene->has_emission : 0; }

const char* vbl_scene_color_space(const vbl_scene* scene)
{
    return scene && scene->color_space[0] ? scene->color_space : NULL;
}

vbl_result vbl_scene_camera_matrices(const vbl_scene* scene, double world_to_camera[16], double world_to_ndc[16])
{
    if (!scene || !world_to_camera || !world_to_ndc)
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_scene_camera_matrices: NULL argument");
    const vbl_camera* c = &scene->camera;
    const vbl_vec3 axes[3] = {c->right, c->up, c->forward};
    /* camera space (row vectors): p_cam = (p - position) [r u f] */
    for (int j = 0; j < 3; ++j) {
        const double a[3] = {axes[j].x, axes[j].y, axes[j].z};
        for (int i = 0; i < 3; ++i) world_to_camera[4 * i + j] = a[i];
        world_to_camera[12 + j] = -vbl_v3_dot(c->position, axes[j]);
        world_to_camera[4 * j + 3] = 0.0;
    }
    world_to_camera[15] = 1.0;
    /* NDC (vbl_camera_ray inverted): x = 0.5 + 0.5 (x_c / z_c) / (tan aspect), y = 0.5 - 0.5 (y_c / z_c) / tan;
     * camera -> NDC as [x_c y_c z_c 1] P with w = z_c */
    const double aspect = (double)c->width / (double)c->height;
    const double sx = 0.5 / (c->tan_half_fov * aspect), sy = 0.5 / c->tan_half_fov;
    const double P[16] = {sx, 0.0, 0.0, 0.0, 0.0, -sy, 0.0, 0.0, 0.5, 0.5, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0};
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            double v = 0.0;
            for (int k = 0; k < 4; ++k) v += world_to_camera[4 * i + k] * P[4 * k + j];
            world_to_ndc[4 * i + j] = v;
        }
    return VBL_SUCCESS;
}

const char* vbl_scene_medium_path(const vbl_scene* scene, int index)
{
    if (!scene || index < 0 || index >= scene->media_count) return NULL;
    return scene->media[index].vdb_path;
}

vbl_result vbl_scene_render_options(const vbl_scene* scene, vbl_render_options* options)
{
    if (!scene || !options) return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_scene_render_options: NULL argument");
    if (options->size < sizeof(vbl_render_options))
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_scene_render_options: options.size is too small");
    vbl_render_options keep = *options;
    *options = scene->render;
    options->size = keep.size;
    options->threads = keep.threads;
    options->callback = keep.callback;
    options->callback_user_data = keep.callback_user_data;
    return VBL_SUCCESS;
}

static const char* const vbl_method_names[] = {"pt", "vpl", "vrl", "vbl", "beams"};
#define VBL_METHOD_COUNT (sizeof vbl_method_names / sizeof vbl_method_names[0])

const char* vbl_render_method_name(vbl_render_method method)
{
    return (unsigned)method < VBL_METHOD_COUNT ? vbl_method_names[method] : "unknown";
}

vbl_result vbl_render_method_parse(const char* name, vbl_render_method* out)
{
    for (int i = 0; name && i < (int)VBL_METHOD_COUNT; ++i)
        if (!strcmp(name, vbl_method_names[i])) {
            *out = (vbl_render_method)i;
            return VBL_SUCCESS;
        }
    return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "unknown render method '%s' (pt, vpl, vrl, vbl, beams)", name ? name : "");
}

/* The scene-space box of the media's majorant grids (what tracking sees): every block grid's index
 * box through its volume's index-to-world map and the medium's placement. 0 without media. */
int vbl_scene_media_box(const vbl_scene* scene, vbl_vec3* lo, vbl_vec3* hi)
{
    int any = 0;
    for (int m = 0; m < scene->media_count; ++m) {
        const vbl_volume* v = scene->media[m].volume;
        if (!v) continue;
        const vbl_majorant_grid* g = &v->majorant;
        if (g->dims[0] <= 0 || g->dims[1] <= 0 || g->dims[2] <= 0) continue;
        for (int c = 0; c < 8; ++c) {
            vbl_vec3 p = vbl_v3(g->origin[0] + (c & 1 ? g->dims[0] * g->block : 0),
                                g->origin[1] + (c & 2 ? g->dims[1] * g->block : 0),
                                g->origin[2] + (c & 4 ? g->dims[2] * g->block : 0));
            p = vbl_affine_point(&scene->media[m].volume_to_scene, vbl_affine_point(&v->index_to_world, p));
            if (!any) *lo = *hi = p;
            lo->x = fmin(lo->x, p.x), lo->y = fmin(lo->y, p.y), lo->z = fmin(lo->z, p.z);
            hi->x = fmax(hi->x, p.x), hi->y = fmax(hi->y, p.y), hi->z = fmax(hi->z, p.z);
            any = 1;
        }
    }
    return any;
}

int vbl_camera_raster(const vbl_camera* camera, vbl_vec3 p, double* sx, double* sy)
{
    const vbl_vec3 d = vbl_v3_sub(p, camera->position);
    const double z = vbl_v3_dot(d, camera->forward);
    if (!(z > 0.0) || !(camera->tan_half_fov > 0.0)) return 0;
    const double aspect = (double)camera->width / (double)camera->height;
    const double a = vbl_v3_dot(d, camera->right) / z, b = vbl_v3_dot(d, camera->up) / z;
    *sx = (a / (camera->tan_half_fov * aspect) + 1.0) * 0.5 * camera->width;
    *sy = (1.0 - b / camera->tan_half_fov) * 0.5 * camera->height;
    return isfinite(*sx) && isfinite(*sy);
}

void vbl_camera_ray(const vbl_camera* camera, double sx, double sy, vbl_vec3* origin, vbl_vec3* direction)
{
    double aspect = (double)camera->width / (double)camera->height;
    double a = (2.0 * sx / camera->width - 1.0) * camera->tan_half_fov * aspect;
    double b = (1.0 - 2.0 * sy / camera->height) * camera->tan_half_fov;
    vbl_vec3 d = vbl_v3_add(camera->forward, vbl_v3_add(vbl_v3_scale(camera->right, a), vbl_v3_scale(camera->up, b)));
    *origin = camera->position;
    *direction = vbl_v3_normalize(d);
}
