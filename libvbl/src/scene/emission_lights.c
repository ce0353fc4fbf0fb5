/* Emissive media as light sources: block power bounds and the cone-mixture direction sampler. */
#include "scene/emission_lights.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "core/error.h"
#include "sampling/sphere.h"
#include "scene/scene.h"
#include "volume/volume.h"

void vbl_emission_lights_free(vbl_emission_lights* lights)
{
    free(lights->blocks);
    free(lights->point_cdf);
    lights->blocks = NULL;
    lights->point_cdf = NULL;
    lights->count = 0;
}

/* Bound of Le (max channel) of medium m over everything its grids hold. */
static double vbl_le_bound(const vbl_medium* m)
{
    double le = 0.0;
    if (m->emission_volume && m->emission_volume->majorant.max_density)
        le += m->emission_scale * vbl_v3_max_component(m->emission_color) * m->emission_volume->majorant.global_max;
    if (m->temperature_volume && m->temperature_volume->majorant.max_density && m->blackbody.rgb) {
        const vbl_majorant_grid* g = &m->temperature_volume->majorant;
        double a = g->global_min * m->temperature_scale + m->temperature_offset;
        double b = g->global_max * m->temperature_scale + m->temperature_offset;
        double hot = fmax(fmax(a, b), 0.0), best = 0.0;
        if (hot >= VBL_BLACKBODY_TABLE_MAX_K) { /* beyond the table: sample the range coarsely */
            for (int k = 0; k <= 64; ++k) best = fmax(best, vbl_v3_max_component(vbl_blackbody_rgb(hot * k / 64.0, m->blackbody.norm)));
            best *= 1.5; /* only importance: a loose bound is fine */
        } else {
            for (int k = 0; k <= (int)ceil(hot) && k <= VBL_BLACKBODY_TABLE_MAX_K; ++k)
                for (int c = 0; c < 3; ++c) best = fmax(best, m->blackbody.rgb[3 * k + c]);
        }
        le += m->blackbody_intensity * best;
    }
    return le;
}

/* At most this many emitters per medium: majorant blocks are grouped f^3 at a time (f a power of
 * two) so that sampling and pdf evaluation, O(emitters) per vertex, stay cheap on big caches. */
#define VBL_EMITTERS_PER_MEDIUM 2048

static int vbl_group_factor(const vbl_majorant_grid* g)
{
    int f = 1;
    for (;;) {
        int64_t n = 1;
        for (int a = 0; a < 3; ++a) n *= (g->dims[a] + f - 1) / f;
        if (n <= VBL_EMITTERS_PER_MEDIUM) return f;
        f *= 2;
    }
}

vbl_result vbl_emission_lights_build(vbl_emission_lights* lights, const vbl_scene* scene)
{
    vbl_emission_lights_free(lights);
    size_t total = 0;
    for (int i = 0; i < scene->media_count; ++i)
        if (scene->media[i].emissive && scene->media[i].volume->majorant.max_density) total += VBL_EMITTERS_PER_MEDIUM;
    if (total == 0) return VBL_SUCCESS;
    lights->blocks = malloc(total * sizeof *lights->blocks);
    if (!lights->blocks) return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory for emission blocks", scene->path);
    for (int i = 0; i < scene->media_count; ++i) {
        const vbl_medium* m = &scene->media[i];
        const vbl_volume* v = m->volume;
        const vbl_majorant_grid* g = &v->majorant;
        if (!m->emissive || !g->max_density) continue;
        const vbl_vec3 amin = m->albedo_volume[0] ? m->albedo_min : m->albedo; /* albedo grid: its least value */
        double absorb = fmax(1.0 - amin.x, fmax(1.0 - amin.y, 1.0 - amin.z));
        double le = vbl_le_bound(m) * absorb * m->density_scale;
        if (!(le > 0.0)) continue;
        const int f = vbl_group_factor(g);
        int gd[3];
        for (int a = 0; a < 3; ++a) gd[a] = (g->dims[a] + f - 1) / f;
        for (int gz = 0; gz < gd[2]; ++gz)
            for (int gy = 0; gy < gd[1]; ++gy)
                for (int gx = 0; gx < gd[0]; ++gx) {
                    /* the group's blocks [g f, min((g+1) f, dims)) and their density bound */
                    const int lo[3] = {gx * f, gy * f, gz * f};
                    int hi[3];
                    for (int a = 0; a < 3; ++a) hi[a] = lo[a] + f < g->dims[a] ? lo[a] + f : g->dims[a];
                    double dmax = 0.0;
                    for (int bz = lo[2]; bz < hi[2]; ++bz)
                        for (int by = lo[1]; by < hi[1]; ++by)
                            for (int bx = lo[0]; bx < hi[0]; ++bx)
                                dmax = fmax(dmax, g->max_density[((size_t)bz * g->dims[1] + by) * g->dims[0] + bx]);
                    if (!(dmax > 0.0)) continue;
                    /* its index box [o + lo B, o + hi B], corners to scene space */
                    vbl_vec3 corners[8], c = vbl_v3(0.0, 0.0, 0.0);
                    for (int k = 0; k < 8; ++k) {
                        double idx[3];
                        for (int a = 0; a < 3; ++a) idx[a] = g->origin[a] + (double)(((k >> a) & 1) ? hi[a] : lo[a]) * g->block;
                        vbl_vec3 w = vbl_affine_point(&v->index_to_world, vbl_v3(idx[0], idx[1], idx[2]));
                        corners[k] = vbl_affine_point(&m->volume_to_scene, w);
                        c = vbl_v3_madd(c, corners[k], 0.125);
                    }
                    double r = 0.0;
                    for (int k = 0; k < 8; ++k) r = fmax(r, vbl_v3_length(vbl_v3_sub(corners[k], c)));
                    r *= 1.0 + 1e-9; /* rounding: the sphere must contain the box */
                    vbl_emission_block* e = &lights->blocks[lights->count++];
                    e->center = c;
                    e->radius = r;
                    e->power = le * dmax * (4.0 / 3.0) * VBL_PI * r * r * r;
                    e->medium = i;
                    for (int a = 0; a < 3; ++a) {
                        e->index_lo[a] = g->origin[a] + (double)lo[a] * g->block;
                        e->index_hi[a] = g->origin[a] + (double)hi[a] * g->block;
                    }
                    e->bound = le * dmax;
                    /* the parallelepiped on the edges from corner 0 (corners 1, 2, 4: +x, +y, +z) */
                    vbl_vec3 ex = vbl_v3_sub(corners[1], corners[0]), ey = vbl_v3_sub(corners[2], corners[0]);
                    vbl_vec3 ez = vbl_v3_sub(corners[4], corners[0]);
                    e->volume = fabs(vbl_v3_dot(ex, vbl_v3_cross(ey, ez)));
                }
    }
    if (lights->count == 0) return VBL_SUCCESS;
    lights->point_cdf = malloc(((size_t)lights->count + 1) * sizeof *lights->point_cdf);
    if (!lights->point_cdf) {
        vbl_emission_lights_free(lights);
        return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory for emission blocks", scene->path);
    }
    lights->point_cdf[0] = 0.0;
    for (int i = 0; i < lights->count; ++i) {
        double w = lights->blocks[i].bound * lights->blocks[i].volume;
        lights->point_cdf[i + 1] = lights->point_cdf[i] + (w > 0.0 && isfinite(w) ? w : 0.0);
    }
    return VBL_SUCCESS;
}

int vbl_emission_lights_pick_point(const vbl_emission_lights* lights, const vbl_scene* scene, double u,
                                   const double u3[3], vbl_vec3* x, double* prob)
{
    if (lights->count == 0 || !lights->point_cdf) return -1;
    const double total = lights->point_cdf[lights->count];
    if (!(total > 0.0)) return -1;
    /* the first block whose cdf passes u total (binary search), skipping empty ones */
    const double target = u * total;
    int lo = 0, hi = lights->count - 1;
    while (lo < hi) {
        int mid = (lo + hi) >> 1;
        if (lights->point_cdf[mid + 1] > target) hi = mid;
        else lo = mid + 1;
    }
    while (lo > 0 && !(lights->point_cdf[lo + 1] > lights->point_cdf[lo])) --lo;
    const double w = lights->point_cdf[lo + 1] - lights->point_cdf[lo];
    if (!(w > 0.0)) return -1;
    const vbl_emission_block* b = &lights->blocks[lo];
    const vbl_medium* m = &scene->media[b->medium];
    double idx[3];
    for (int a = 0; a < 3; ++a) idx[a] = b->index_lo[a] + u3[a] * (b->index_hi[a] - b->index_lo[a]);
    vbl_vec3 wp = vbl_affine_point(&m->volume->index_to_world, vbl_v3(idx[0], idx[1], idx[2]));
    *x = vbl_affine_point(&m->volume_to_scene, wp);
    *prob = w / total;
    return lo;
}

/* Selection weight of a block at x: power / max(d^2, r^2). */
static double vbl_block_weight(const vbl_emission_block* b, vbl_vec3 x, double* d2)
{
    vbl_vec3 d = vbl_v3_sub(b->center, x);
    *d2 = vbl_v3_dot(d, d);
    return b->power / fmax(*d2, b->radius * b->radius);
}

/* Direction density of one block's cone (inside the sphere: uniform over all directions). */
static double vbl_block_pdf(const vbl_emission_block* b, vbl_vec3 x, double d2, vbl_vec3 wi)
{
    if (d2 <= b->radius * b->radius) return vbl_uniform_sphere_pdf();
    double d = sqrt(d2);
    vbl_vec3 axis = vbl_v3_scale(vbl_v3_sub(b->center, x), 1.0 / d);
    double cos_max = sqrt(fmax(0.0, 1.0 - b->radius * b->radius / d2));
    return vbl_uniform_cone_pdf(axis, cos_max, wi);
}

double vbl_emission_lights_pdf(const vbl_emission_lights* lights, vbl_vec3 x, vbl_vec3 wi)
{
    double total = 0.0, pdf = 0.0;
    for (int i = 0; i < lights->count; ++i) {
        double d2, w = vbl_block_weight(&lights->blocks[i], x, &d2);
        total += w;
        if (w > 0.0) pdf += w * vbl_block_pdf(&lights->blocks[i], x, d2, wi);
    }
    return total > 0.0 ? pdf / total : 0.0;
}

int vbl_emission_lights_sample(const vbl_emission_lights* lights, vbl_vec3 x, double u0, double u1, double u2,
                               vbl_vec3* wi, double* pdf)
{
    double total = 0.0;
    for (int i = 0; i < lights->count; ++i) {
        double d2;
        total += vbl_block_weight(&lights->blocks[i], x, &d2);
    }
    if (!(total > 0.0)) return 0;
    double target = u0 * total, acc = 0.0;
    int pick = -1;
    for (int i = 0; i < lights->count; ++i) {
        double d2, w = vbl_block_weight(&lights->blocks[i], x, &d2);
        if (!(w > 0.0)) continue;
        pick = i;
        acc += w;
        if (target < acc) break;
    }
    if (pick < 0) return 0;
    const vbl_emission_block* b = &lights->blocks[pick];
    vbl_vec3 d = vbl_v3_sub(b->center, x);
    double d2 = vbl_v3_dot(d, d), p = 0.0;
    if (d2 <= b->radius * b->radius) {
        *wi = vbl_sample_uniform_sphere(u1, u2, &p);
    } else {
        double dist = sqrt(d2);
        double cos_max = sqrt(fmax(0.0, 1.0 - b->radius * b->radius / d2));
        *wi = vbl_sample_uniform_cone(vbl_v3_scale(d, 1.0 / dist), cos_max, u1, u2, &p);
    }
    if (!(p > 0.0)) return 0;
    *pdf = vbl_emission_lights_pdf(lights, x, *wi);
    return *pdf > 0.0;
}
