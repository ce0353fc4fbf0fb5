/* 3D DDA (Amanatides & Woo 1987) over the majorant blocks, in block units of index space. The ray
 * parameter t is the caller's (affine maps preserve it). Boundaries are recomputed from the ray
 * at every step (no accumulated drift); a component of the direction that is exactly 0 never
 * crosses a boundary (t_next = +inf), so there is no division by zero and no leak through faces.
 * Each step moves one cell monotonically along one axis, so the work is bounded by the sum of the
 * grid dimensions, whatever the voxel size or ray. */
#include "volume/majorant_iter.h"

#include <math.h>

static double vbl_dda_boundary_t(const vbl_majorant_iter* it, int axis)
{
    if (it->step[axis] == 0) return INFINITY;
    double boundary = (double)(it->cell[axis] + (it->step[axis] > 0 ? 1 : 0));
    return (boundary - it->org[axis]) * it->inv_dir[axis];
}

void vbl_majorant_iter_init(vbl_majorant_iter* it, const vbl_volume* volume, vbl_vec3 origin, vbl_vec3 direction,
                            double tmin, double tmax)
{
    vbl_majorant_iter_init_grid(it, &volume->majorant, &volume->world_to_index, origin, direction, tmin, tmax);
}

void vbl_majorant_iter_init_grid(vbl_majorant_iter* it, const vbl_majorant_grid* g, const vbl_affine* world_to_index,
                                 vbl_vec3 origin, vbl_vec3 direction, double tmin, double tmax)
{
    it->grid = g;
    it->done = 1;
    it->t = tmin;
    it->t_end = tmax;
    if (g->dims[0] <= 0 || g->dims[1] <= 0 || g->dims[2] <= 0 || !g->max_density) return;
    if (!(tmin < tmax)) return; /* zero-length, reversed or NaN interval: no segments */

    vbl_vec3 o = vbl_affine_point(world_to_index, origin);
    vbl_vec3 d = vbl_affine_vector(world_to_index, direction);
    const double inv_block = 1.0 / (double)g->block;
    double oa[3] = {o.x, o.y, o.z}, da[3] = {d.x, d.y, d.z};
    double t0 = tmin, t1 = tmax;
    for (int a = 0; a < 3; ++a) {
        it->org[a] = (oa[a] - (double)g->origin[a]) * inv_block;
        double dir = da[a] * inv_block;
        if (!isfinite(it->org[a]) || !isfinite(dir)) return;
        if (dir == 0.0) {
            it->step[a] = 0;
            it->inv_dir[a] = 0.0;
            it->t_delta[a] = INFINITY;
            if (it->org[a] < 0.0 || it->org[a] > (double)g->dims[a]) return;
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
        if (isnan(ta) || isnan(tb)) return;
        if (ta > t0) t0 = ta;
        if (tb < t1) t1 = tb;
    }
    if (!(t0 < t1)) return;

    /* Entry cell from the point at t0 (clamped: rounding may put it an ulp outside). */
    for (int a = 0; a < 3; ++a) {
        double dir = it->step[a] == 0 ? 0.0 : da[a] * inv_block;
        double q = it->org[a] + dir * t0;
        double c = floor(q);
        if (!(c >= 0.0)) c = 0.0;
        if (c > (double)(g->dims[a] - 1)) c = (double)(g->dims[a] - 1);
        it->cell[a] = (int)c;
    }
    for (int a = 0; a < 3; ++a) it->t_next[a] = vbl_dda_boundary_t(it, a);
    it->t = t0;
    it->t_end = t1;
    it->done = 0;
}

int vbl_majorant_iter_next(vbl_majorant_iter* it, vbl_majorant_segment* segment)
{
    const vbl_majorant_grid* g = it->grid;
    while (!it->done) {
        int axis = 0;
        if (it->t_next[1] < it->t_next[axis]) axis = 1;
        if (it->t_next[2] < it->t_next[axis]) axis = 2;
        double t_cross = it->t_next[axis];
        double t1 = t_cross < it->t_end ? t_cross : it->t_end;
        if (t1 < it->t) t1 = it->t;
        size_t index = (size_t)it->cell[0] + (size_t)g->dims[0] * ((size_t)it->cell[1] + (size_t)g->dims[1] * (size_t)it->cell[2]);
        double t0 = it->t;
        if (t_cross < it->t_end) {
            it->cell[axis] += it->step[axis];
            if (it->cell[axis] < 0 || it->cell[axis] >= g->dims[axis]) it->done = 1;
            else it->t_next[axis] = vbl_dda_boundary_t(it, axis);
            /* A boundary that rounding placed behind the current t is crossed at once. */
            it->t = t1;
        } else {
            it->done = 1;
            it->t = it->t_end;
        }
        if (t1 > t0) {
            segment->t0 = t0;
            segment->t1 = t1;
            segment->majorant = g->max_density[index];
            segment->minorant = g->min_density[index];
            return 1;
        }
    }
    return 0;
}
