/* 3D DDA (Amanatides & Woo 1987) over the majorant blocks, in block units of index space, with
 * a coarse level on top (hierarchical DDA, Museth 2014, "Hierarchical digital differential
 * analyzer for efficient ray-marching in OpenVDB", sec. 3: walk the coarse nodes, descend only
 * into the ones that need the fine level). The ray parameter t is the caller's (affine maps
 * preserve it). Boundaries are recomputed from the ray at every step (no accumulated drift); a
 * component of the direction that is exactly 0 never crosses a boundary (t_next = +inf), so there
 * is no division by zero and no leak through faces. Each step moves one cell monotonically along
 * one axis, so the work is bounded by the sum of the grid dimensions, whatever the voxel size or
 * ray.
 *
 * A coarse cell is crossed in one step (one segment) when it is empty, or, with coarse_tau > 0,
 * when it is constant or its majorant x length is <= coarse_tau. Its exit boundary is computed
 * with the same formula as the block boundary on that plane, and the block cell after the jump
 * is the one the block-by-block walk would reach (every block boundary before the exit, ties
 * broken towards the lower axis as in the block walk), so the segments that follow are
 * bit-identical to the block walk's. The step itself: one compare pair for the axis, one
 * subtract and multiply for the next boundary, an integer index update (no division, no
 * per-step multiply of the linear index). */
#include "volume/majorant_iter.h"

#include <math.h>

static inline double vbl_dda_boundary_t(const vbl_majorant_iter* it, int axis)
{
    if (it->step[axis] == 0) return INFINITY;
    return vbl_majorant_iter_boundary(it, axis);
}

void vbl_majorant_iter_init(vbl_majorant_iter* it, const vbl_volume* volume, vbl_vec3 origin, vbl_vec3 direction,
                            double tmin, double tmax)
{
    vbl_majorant_iter_init_coarse(it, &volume->majorant, &volume->world_to_index, origin, direction, tmin, tmax, 0.0, 0.0);
}

void vbl_majorant_iter_init_grid(vbl_majorant_iter* it, const vbl_majorant_grid* g, const vbl_affine* world_to_index,
                                 vbl_vec3 origin, vbl_vec3 direction, double tmin, double tmax)
{
    vbl_majorant_iter_init_coarse(it, g, world_to_index, origin, direction, tmin, tmax, 0.0, 0.0);
}

/* The ray in block units and its clip to the grid's box: fills org, inv_dir, step and t_delta and
 * the world-space direction in block units (dir_out); returns 1 with the overlap [*t_enter,
 * *t_exit] of [tmin, tmax] with the box, 0 if there is none (or the ray is not finite). The one
 * slab test of vbl_majorant_iter_init_coarse and vbl_majorant_iter_clip (same arithmetic). */
static inline int vbl_dda_setup(vbl_majorant_iter* it, const vbl_majorant_grid* g, const vbl_affine* world_to_index,
                                vbl_vec3 origin, vbl_vec3 direction, double tmin, double tmax, double dir_out[3],
                                double* t_enter, double* t_exit)
{
    if (g->dims[0] <= 0 || g->dims[1] <= 0 || g->dims[2] <= 0 || !g->max_density) return 0;
    if (!(tmin < tmax)) return 0; /* zero-length, reversed or NaN interval: no segments */

    vbl_vec3 o = vbl_affine_point(world_to_index, origin);
    vbl_vec3 d = vbl_affine_vector(world_to_index, direction);
    const double inv_block = 1.0 / (double)g->block;
    double oa[3] = {o.x, o.y, o.z}, da[3] = {d.x, d.y, d.z};
    double t0 = tmin, t1 = tmax;
    for (int a = 0; a < 3; ++a) {
        it->org[a] = (oa[a] - (double)g->origin[a]) * inv_block;
        double dir = da[a] * inv_block;
        dir_out[a] = dir;
        if (!isfinite(it->org[a]) || !isfinite(dir)) return 0;
        if (dir == 0.0) {
            it->step[a] = 0;
            it->inv_dir[a] = 0.0;
            it->t_delta[a] = INFINITY;
            if (it->org[a] < 0.0 || it->org[a] > (double)g->dims[a]) return 0;
            continue;
        }
        it->step[a] = dir > 0.0 ? 1 : -1;
        it->inv_dir[a] = 1.0 / dir; /* may be inf for subnormal dir: handled below */
        it->t_delta[a] = fabs(it->inv_dir[a]);
        double ta = (0.0 - it->org[a]) * it->inv_dir[a];
        double tb = ((double)g->dims[a] - it->org[a]) * it->inv_dir[a];
        if (ta > tb) {
            double s = ta;
            ta = tb;
            tb = s;
        }
        if (isnan(ta) || isnan(tb)) return 0;
        if (ta > t0) t0 = ta;
        if (tb < t1) t1 = tb;
    }
    if (!(t0 < t1)) return 0;
    *t_enter = t0;
    *t_exit = t1;
    return 1;
}

int vbl_majorant_iter_clip(const vbl_majorant_grid* g, const vbl_affine* world_to_index, vbl_vec3 origin,
                           vbl_vec3 direction, double tmin, double tmax, double* t_enter, double* t_exit)
{
    vbl_majorant_iter it;
    double dir[3];
    return vbl_dda_setup(&it, g, world_to_index, origin, direction, tmin, tmax, dir, t_enter, t_exit);
}

void vbl_majorant_iter_init_coarse(vbl_majorant_iter* it, const vbl_majorant_grid* g, const vbl_affine* world_to_index,
                                   vbl_vec3 origin, vbl_vec3 direction, double tmin, double tmax, double coarse_tau,
                                   double coarse_ratio)
{
    it->grid = g;
    it->done = 1;
    it->t = tmin;
    it->t_end = tmax;
    it->steps = 0;
    it->coarse_check = 0;
    const int use_coarse = !(coarse_tau < 0.0); /* < 0: the block walk only */
    it->coarse_tau = coarse_tau > 0.0 ? coarse_tau : 0.0; /* NaN: 0 */
    it->coarse_ratio = coarse_ratio >= 1.0 ? coarse_ratio : 0.0;
    it->coarse_merge = (it->coarse_tau > 0.0 || it->coarse_ratio > 0.0) && use_coarse;
    double da[3], t0, t1;
    if (!vbl_dda_setup(it, g, world_to_index, origin, direction, tmin, tmax, da, &t0, &t1)) return;

    /* Entry cell from the point at t0 (clamped: rounding may put it an ulp outside). */
    for (int a = 0; a < 3; ++a) {
        double dir = it->step[a] == 0 ? 0.0 : da[a];
        double q = it->org[a] + dir * t0;
        double c = floor(q);
        if (!(c >= 0.0)) c = 0.0;
        if (c > (double)(g->dims[a] - 1)) c = (double)(g->dims[a] - 1);
        it->cell[a] = (int)c;
    }
    const ptrdiff_t sx = 1, sy = (ptrdiff_t)g->dims[0], sz = (ptrdiff_t)g->dims[0] * (ptrdiff_t)g->dims[1];
    it->stride[0] = it->step[0] * sx;
    it->stride[1] = it->step[1] * sy;
    it->stride[2] = it->step[2] * sz;
    it->index = (size_t)it->cell[0] + (size_t)sy * (size_t)it->cell[1] + (size_t)sz * (size_t)it->cell[2];
    for (int a = 0; a < 3; ++a) it->t_next[a] = vbl_dda_boundary_t(it, a);
    it->t = t0;
    it->t_end = t1;
    it->done = 0;
    it->coarse_check = g->coarse_max != NULL && use_coarse;
    it->coarse_merge &= use_coarse;
}

int vbl_majorant_iter_coarse_step(vbl_majorant_iter* it, vbl_majorant_segment* segment)
{
    const vbl_majorant_grid* g = it->grid;
    const int L = VBL_MAJORANT_COARSE_LOG2;
    const int cc[3] = {it->cell[0] >> L, it->cell[1] >> L, it->cell[2] >> L};
    const size_t ci =
        (size_t)cc[0] + (size_t)g->coarse_dims[0] * ((size_t)cc[1] + (size_t)g->coarse_dims[1] * (size_t)cc[2]);
    const float cmax = g->coarse_max[ci], cmin = g->coarse_min[ci];
    const int empty = cmax == 0.0f && cmin == 0.0f;
    if (!empty && !it->coarse_merge) return -1;
    /* Exit: the first coarse boundary plane, in block units, ties to the lower axis. */
    double t_exit = INFINITY;
    int e = -1, plane = 0;
    for (int a = 0; a < 3; ++a) {
        if (it->step[a] == 0) continue;
        int b = it->step[a] > 0 ? (cc[a] + 1) << L : cc[a] << L;
        if (b > g->dims[a]) b = g->dims[a];
        double tb = ((double)b - it->org[a]) * it->inv_dir[a];
        if (tb < t_exit) {
            t_exit = tb;
            e = a;
            plane = b;
        }
    }
    double t1 = t_exit < it->t_end ? t_exit : it->t_end;
    if (t1 < it->t) t1 = it->t;
    if (!empty && !(cmax == cmin || (double)cmax * (t1 - it->t) <= it->coarse_tau ||
                    (double)g->coarse_spread[ci] <= it->coarse_ratio))
        return -1;
    const double t0 = it->t;
    it->steps++;
    if (t_exit < it->t_end) {
        /* The block cell after the exit crossing, as the block walk reaches it. */
        for (int a = 0; a < 3; ++a) {
            if (a == e || it->step[a] == 0) continue;
            while (it->t_next[a] < t_exit || (it->t_next[a] == t_exit && a < e)) {
                it->cell[a] += it->step[a];
                it->t_next[a] = vbl_dda_boundary_t(it, a);
            }
        }
        it->cell[e] = it->step[e] > 0 ? plane : plane - 1;
        if (it->cell[e] < 0 || it->cell[e] >= g->dims[e]) {
            it->done = 1;
        } else {
            it->t_next[e] = vbl_dda_boundary_t(it, e);
            it->index = (size_t)it->cell[0] +
                        (size_t)g->dims[0] * ((size_t)it->cell[1] + (size_t)g->dims[1] * (size_t)it->cell[2]);
            it->coarse_check = 1;
        }
        it->t = t1;
    } else {
        it->done = 1;
        it->t = it->t_end;
    }
    if (!(t1 > t0)) return 0;
    segment->t0 = t0;
    segment->t1 = t1;
    segment->majorant = cmax;
    segment->minorant = cmin;
    return 1;
}

int vbl_majorant_iter_next(vbl_majorant_iter* it, vbl_majorant_segment* segment)
{
    return vbl_majorant_iter_next_inline(it, segment);
}
