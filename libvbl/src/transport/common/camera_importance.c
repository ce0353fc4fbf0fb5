/* The camera-importance grid of vrl.light_guide (see camera_importance.h). */
#include "transport/common/camera_importance.h"

#include <stdlib.h>
#include <string.h>

#include "transport/common/light_emission.h"

void vbl_camera_importance_free(vbl_camera_importance* g)
{
    if (!g) return;
    free(g->value);
    memset(g, 0, sizeof *g);
}

/* One 3-tap box pass along axis `axis` (stride), from src into dst. */
static void vbl_box3(const float* src, float* dst, int res, int axis)
{
    const size_t stride = axis == 0 ? 1 : (axis == 1 ? (size_t)res : (size_t)res * (size_t)res);
    const size_t n = (size_t)res * (size_t)res * (size_t)res;
    for (size_t c = 0; c < n; ++c) {
        const int coord = (int)((c / stride) % (size_t)res);
        double s = src[c];
        if (coord > 0) s += src[c - stride];
        if (coord + 1 < res) s += src[c + stride];
        dst[c] = (float)(s * (1.0 / 3.0));
    }
}

int vbl_camera_importance_build(const vbl_render_context* ctx, vbl_camera_importance* g)
{
    memset(g, 0, sizeof *g);
    const vbl_scene* scene = ctx->scene;
    const vbl_extinction* ext = ctx->extinction;
    vbl_vec3 center;
    double radius = 0.0;
    if (ext->count == 0 || !vbl_media_bounding_sphere(scene, &center, &radius) || !(radius > 0.0)) return 0;
    const int res = VBL_CAMERA_IMPORTANCE_RES;
    const size_t n = (size_t)res * (size_t)res * (size_t)res;
    float* a = calloc(n, sizeof *a);
    float* b = calloc(n, sizeof *b);
    if (!a || !b) {
        free(a);
        free(b);
        return 0;
    }
    g->lo = vbl_v3_sub(center, vbl_v3(radius, radius, radius));
    g->voxel = 2.0 * radius / res;
    g->res = res;
    g->value = a;

    double albedo[VBL_MAX_MEDIA] = {0}; /* mean RGB albedo per medium (albedo grids ignored: a guide) */
    for (int m = 0; m < scene->media_count && m < VBL_MAX_MEDIA; ++m)
        albedo[m] = (scene->media[m].albedo.x + scene->media[m].albedo.y + scene->media[m].albedo.z) / 3.0;
    vbl_extinction_cursor cursor;
    vbl_extinction_cursor_init(&cursor, ext);
    const double h = 0.5 * g->voxel;
    const vbl_camera* cam = &scene->camera;
    for (int ry = 0; ry < VBL_CAMERA_IMPORTANCE_RAYS_Y; ++ry)
        for (int rx = 0; rx < VBL_CAMERA_IMPORTANCE_RAYS_X; ++rx) {
            vbl_camera_sample cs;
            memset(&cs, 0, sizeof cs);
            cs.sx = (rx + 0.5) * cam->width / VBL_CAMERA_IMPORTANCE_RAYS_X;
            cs.sy = (ry + 0.5) * cam->height / VBL_CAMERA_IMPORTANCE_RAYS_Y;
            vbl_camera_sample_ray(scene, &cs);
            double u0 = 0.0, u1 = 0.0;
            if (!vbl_extinction_ray_bounds(ext, cs.origin, cs.direction, 0.0, cs.t_max, &u0, &u1) || !(u1 > u0))
                continue;
            double T = 1.0;
            for (double u = u0; u < u1 && T > 1e-4; u += h) {
                const double step = u + h < u1 ? h : u1 - u;
                vbl_vec3 p = vbl_v3_madd(cs.origin, cs.direction, u + 0.5 * step);
                double comps[VBL_MAX_MEDIA] = {0};
                const double st = vbl_extinction_eval(ext, &cursor, p, comps);
                if (!(st > 0.0)) continue;
                double alb = 0.0;
                for (int m = 0; m < scene->media_count && m < VBL_MAX_MEDIA; ++m) alb += comps[m] * albedo[m];
                const double hit = 1.0 - exp(-st * step);
                const double fx = (p.x - g->lo.x) / g->voxel, fy = (p.y - g->lo.y) / g->voxel,
                             fz = (p.z - g->lo.z) / g->voxel;
                if (fx >= 0.0 && fy >= 0.0 && fz >= 0.0 && fx < res && fy < res && fz < res)
                    a[((size_t)fz * (size_t)res + (size_t)fy) * (size_t)res + (size_t)fx] += (float)(T * hit * alb / st);
                T *= 1.0 - hit;
            }
        }
    /* blur: two 3-tap passes per axis (a -> b -> a per axis) */
    for (int pass = 0; pass < 2; ++pass)
        for (int axis = 0; axis < 3; ++axis) {
            vbl_box3(a, b, res, axis);
            memcpy(a, b, n * sizeof *a);
        }
    free(b);
    double total = 0.0;
    for (size_t c = 0; c < n; ++c) total += a[c];
    g->total = total;
    return 1;
}
