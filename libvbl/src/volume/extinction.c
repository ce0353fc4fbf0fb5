/* Extinction field of several (possibly overlapping) volumes: sigma_t(x) = sum_c s_c * rho_c(A_c x),
 * and merged majorant segments: on every sub-interval where the active component set is
 * constant, majorant = sum of s_c * block max, minorant = sum of s_c * block min. */
#include "volume/extinction.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"

static vbl_affine vbl_affine_identity(void)
{
    vbl_affine a;
    memset(&a, 0, sizeof a);
    a.m[0][0] = a.m[1][1] = a.m[2][2] = 1.0;
    return a;
}

void vbl_extinction_init(vbl_extinction* ext)
{
    memset(ext, 0, sizeof *ext);
    ext->coarse_depth = VBL_COARSE_DEPTH_DEFAULT;
    ext->coarse_ratio = VBL_COARSE_RATIO_DEFAULT;
}

vbl_result vbl_extinction_add(vbl_extinction* ext, const vbl_volume* volume, double density_scale,
                              const vbl_affine* scene_to_volume)
{
    if (!ext || !volume) return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_extinction_add: NULL argument");
    if (ext->count >= VBL_MAX_MEDIA)
        return vbl_error(VBL_ERROR_UNSUPPORTED, "more than %d media components", VBL_MAX_MEDIA);
    if (!(density_scale >= 0.0) || !isfinite(density_scale))
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "density_scale = %g must be finite and >= 0", density_scale);
    vbl_medium_component* c = &ext->components[ext->count++];
    c->volume = volume;
    c->density_scale = density_scale;
    c->scene_to_volume = scene_to_volume ? *scene_to_volume : vbl_affine_identity();
    ext->max_sigma_t += density_scale * (volume->majorant.max_density ? volume->majorant.global_max : 0.0);
    return VBL_SUCCESS;
}

void vbl_extinction_cursor_init(vbl_extinction_cursor* cursor, const vbl_extinction* ext)
{
    cursor->count = ext->count;
    cursor->time = 0.0;
    for (int c = 0; c < ext->count; ++c) {
        vbl_grid_accessor_init(&cursor->accessors[c], ext->components[c].volume);
        if (ext->components[c].velocity.v[0])
            for (int a = 0; a < 3; ++a) vbl_grid_accessor_init(&cursor->velocity[c][a], ext->components[c].velocity.v[a]);
    }
}

vbl_result vbl_extinction_set_velocity(vbl_extinction* ext, int c, const vbl_velocity_field* velocity, double max_time)
{
    if (!ext || c < 0 || c >= ext->count || !velocity || !velocity->v[0])
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_extinction_set_velocity: bad argument");
    vbl_medium_component* m = &ext->components[c];
    m->velocity = *velocity;
    if (m->moving) {
        vbl_majorant_grid_free(m->moving);
        free(m->moving);
        m->moving = NULL;
    }
    const vbl_volume* vol = m->volume;
    if (!vol->majorant.max_density) return VBL_SUCCESS; /* empty: nothing moves */
    /* world distance r -> index distance per axis: |row a of world_to_index| r */
    const double r = velocity->max_speed * fabs(max_time);
    int k[3];
    for (int a = 0; a < 3; ++a) {
        double row = 0.0;
        for (int b = 0; b < 3; ++b) row += vol->world_to_index.m[a][b] * vol->world_to_index.m[a][b];
        double cells = sqrt(row) * r / (double)vol->majorant.block;
        if (!(cells < 4096.0))
            return vbl_error(VBL_ERROR_UNSUPPORTED,
                             "'%s': motion blur moves the medium by %g world units (%g majorant blocks), too far",
                             vol->info.file_path, r, cells);
        k[a] = (int)ceil(cells);
    }
    m->moving = calloc(1, sizeof *m->moving);
    if (!m->moving) return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "out of memory for a moving majorant grid");
    vbl_result res = vbl_majorant_grid_dilate(&vol->majorant, k, m->moving);
    if (res) {
        free(m->moving);
        m->moving = NULL;
    }
    return res;
}

void vbl_extinction_free(vbl_extinction* ext)
{
    if (!ext) return;
    for (int c = 0; c < ext->count; ++c)
        if (ext->components[c].moving) {
            vbl_majorant_grid_free(ext->components[c].moving);
            free(ext->components[c].moving);
            ext->components[c].moving = NULL;
        }
}

/* The majorant grid tracking uses for component m. */
static const vbl_majorant_grid* vbl_component_majorant(const vbl_medium_component* m)
{
    return m->moving ? m->moving : &m->volume->majorant;
}

uint64_t vbl_extinction_cursor_lookups(const vbl_extinction_cursor* cursor)
{
    uint64_t n = 0;
    for (int c = 0; c < cursor->count; ++c) n += cursor->accessors[c].lookups;
    return n;
}

double vbl_extinction_eval(const vbl_extinction* ext, vbl_extinction_cursor* cursor, vbl_vec3 point,
                           double* per_component)
{
    double sum = 0.0;
    for (int c = 0; c < ext->count; ++c) {
        const vbl_medium_component* m = &ext->components[c];
        double s = 0.0;
        if (m->density_scale > 0.0 && m->volume->majorant.max_density) {
            vbl_vec3 p = vbl_affine_point(&m->scene_to_volume, point);
            if (cursor->time != 0.0 && m->velocity.v[0])
                p = vbl_velocity_advect(&m->velocity, cursor->velocity[c], p, cursor->time);
            s = m->density_scale * vbl_grid_sample_world_trilinear_inline(&cursor->accessors[c], p);
        }
        if (per_component) per_component[c] = s;
        sum += s;
    }
    return sum;
}

/* Global majorant of the field (sum of each component's scaled global max). */
static double vbl_extinction_global_majorant(const vbl_extinction* ext)
{
    double sum = 0.0;
    for (int c = 0; c < ext->count; ++c) {
        const vbl_majorant_grid* g = &ext->components[c].volume->majorant;
        if (g->max_density) sum += ext->components[c].density_scale * g->global_max;
    }
    return sum;
}

static void vbl_extinction_component_ray(const vbl_medium_component* m, vbl_vec3 origin, vbl_vec3 direction,
                                         vbl_vec3* o, vbl_vec3* d)
{
    *o = vbl_affine_point(&m->scene_to_volume, origin);
    *d = vbl_affine_vector(&m->scene_to_volume, direction);
}

int vbl_extinction_ray_bounds(const vbl_extinction* ext, vbl_vec3 origin, vbl_vec3 direction, double tmin,
                              double tmax, double* t_enter, double* t_exit)
{
    double lo = INFINITY, hi = -INFINITY;
    for (int c = 0; c < ext->count; ++c) {
        vbl_vec3 o, d;
        vbl_extinction_component_ray(&ext->components[c], origin, direction, &o, &d);
        double a, b;
        if (!vbl_majorant_iter_clip(vbl_component_majorant(&ext->components[c]),
                                    &ext->components[c].volume->world_to_index, o, d, tmin, tmax, &a, &b))
            continue;
        if (a < lo) lo = a;
        if (b > hi) hi = b;
    }
    if (!(lo < hi)) return 0;
    *t_enter = lo;
    *t_exit = hi;
    return 1;
}

void vbl_extinction_iter_init(vbl_extinction_iter* iter, const vbl_extinction* ext, vbl_vec3 origin,
                              vbl_vec3 direction, double tmin, double tmax, int use_global_majorant)
{
    iter->ext = ext;
    iter->use_global = use_global_majorant;
    iter->t = tmin;
    iter->t_end = tmax;
    if (use_global_majorant) {
        double a, b;
        if (!vbl_extinction_ray_bounds(ext, origin, direction, tmin, tmax, &a, &b)) {
            iter->t = iter->t_end = tmax; /* nothing */
            iter->t = tmax;
            iter->has_pending[0] = 0;
            return;
        }
        iter->t = a;
        iter->t_end = b;
        iter->pending[0].t0 = a;
        iter->pending[0].t1 = b;
        iter->pending[0].majorant = vbl_extinction_global_majorant(ext);
        iter->pending[0].minorant = 0.0;
        iter->has_pending[0] = 1;
        return;
    }
    for (int c = 0; c < ext->count; ++c) {
        vbl_vec3 o, d;
        vbl_extinction_component_ray(&ext->components[c], origin, direction, &o, &d);
        /* coarse_depth in the grid's unscaled units (a component of scale 0 adds nothing: any
         * coarse cell is one segment) */
        const double s = ext->components[c].density_scale;
        const double tau = ext->coarse_depth > 0.0 ? (s > 0.0 ? ext->coarse_depth / s : INFINITY)
                                                   : (ext->coarse_depth < 0.0 ? -1.0 : 0.0);
        vbl_majorant_iter_init_coarse(&iter->iters[c], vbl_component_majorant(&ext->components[c]),
                                      &ext->components[c].volume->world_to_index, o, d, tmin, tmax, tau,
                                      ext->coarse_ratio);
        iter->has_pending[c] = 0;
    }
}

int vbl_extinction_iter_next_merged(vbl_extinction_iter* iter, vbl_majorant_segment* segment)
{
    const vbl_extinction* ext = iter->ext;
    if (iter->use_global) {
        if (!iter->has_pending[0]) return 0;
        *segment = iter->pending[0];
        iter->has_pending[0] = 0;
        return segment->t1 > segment->t0;
    }
    for (;;) {
        /* Refill pending segments; find the next event after t. */
        int any = 0;
        double start = INFINITY;
        for (int c = 0; c < ext->count; ++c) {
            while (!iter->has_pending[c] || iter->pending[c].t1 <= iter->t) {
                if (!vbl_majorant_iter_next(&iter->iters[c], &iter->pending[c])) {
                    iter->has_pending[c] = 0;
                    break;
                }
                iter->has_pending[c] = 1;
            }
            if (!iter->has_pending[c]) continue;
            any = 1;
            if (iter->pending[c].t0 < start) start = iter->pending[c].t0;
        }
        if (!any) return 0;
        if (start > iter->t) iter->t = start; /* gap where no component is present */
        double end = INFINITY, maj = 0.0, min = 0.0;
        for (int c = 0; c < ext->count; ++c) {
            if (!iter->has_pending[c]) continue;
            const vbl_majorant_segment* p = &iter->pending[c];
            if (p->t0 > iter->t) {
                if (p->t0 < end) end = p->t0;
                continue;
            }
            if (p->t1 < end) end = p->t1;
            maj += ext->components[c].density_scale * p->majorant;
            min += ext->components[c].density_scale * p->minorant;
        }
        double t0 = iter->t;
        iter->t = end;
        if (end > t0) {
            segment->t0 = t0;
            segment->t1 = end;
            segment->majorant = maj;
            segment->minorant = min;
            return 1;
        }
    }
}
