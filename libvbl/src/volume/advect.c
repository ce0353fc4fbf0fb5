/* Eulerian advection through a velocity grid (advect.h). */
#include "volume/advect.h"

#include <math.h>

vbl_vec3 vbl_velocity_advect(const vbl_velocity_field* f, vbl_grid_accessor* acc, vbl_vec3 x, double time)
{
    if (!f->v[0] || time == 0.0) return x;
    vbl_grid_accessor local[3];
    if (!acc) {
        for (int a = 0; a < 3; ++a) vbl_grid_accessor_init(&local[a], f->v[a]);
        acc = local;
    }
    double v[3];
    for (int a = 0; a < 3; ++a) v[a] = vbl_grid_sample_world(&acc[a], x, VBL_FILTER_TRILINEAR);
    const double s = f->scale * time;
    return vbl_v3(x.x - s * v[0], x.y - s * v[1], x.z - s * v[2]);
}

double vbl_velocity_max_speed(const vbl_velocity_field* f)
{
    if (!f->v[0]) return 0.0;
    /* Components on the same block grid (a split vec3s grid): per block, |v| <= sqrt(sum_a
     * max(|max_a|, |min_a|)^2) over the values trilinear interpolation reads there; the largest
     * over the blocks (tighter than the global per-component extremes, which may lie apart). */
    const vbl_majorant_grid* g0 = &f->v[0]->majorant;
    int same = g0->max_density != NULL;
    for (int a = 1; a < 3 && same; ++a) {
        const vbl_majorant_grid* g = &f->v[a]->majorant;
        same = g->max_density && g->block == g0->block;
        for (int b = 0; b < 3 && same; ++b) same = g->dims[b] == g0->dims[b] && g->origin[b] == g0->origin[b];
    }
    if (same) {
        const size_t n = (size_t)g0->dims[0] * (size_t)g0->dims[1] * (size_t)g0->dims[2];
        double best = 0.0;
        for (size_t i = 0; i < n; ++i) {
            double s2 = 0.0;
            for (int a = 0; a < 3; ++a) {
                const vbl_majorant_grid* g = &f->v[a]->majorant;
                double m = fmax(fabs((double)g->max_density[i]), fabs((double)g->min_density[i]));
                s2 += m * m;
            }
            if (s2 > best) best = s2;
        }
        /* the background (read outside the blocks) */
        double bg2 = 0.0;
        for (int a = 0; a < 3; ++a) {
            vbl_grid_accessor acc;
            vbl_grid_accessor_init(&acc, f->v[a]);
            double far = vbl_grid_sample_index_nearest(&acc, vbl_v3(-1e9, -1e9, -1e9));
            bg2 += far * far;
        }
        return fabs(f->scale) * sqrt(fmax(best, bg2));
    }
    /* |v| <= sqrt(sum_a max |v_a|^2): a bound from the per-component extremes of the voxels */
    double s2 = 0.0;
    for (int a = 0; a < 3; ++a) {
        const vbl_volume_info* info = &f->v[a]->info;
        double m = fmax(fabs(info->value_min), fabs(info->value_max));
        if (f->v[a]->majorant.max_density)
            m = fmax(m, fmax(fabs(f->v[a]->majorant.global_max), fabs(f->v[a]->majorant.global_min)));
        s2 += m * m;
    }
    return fabs(f->scale) * sqrt(s2);
}
