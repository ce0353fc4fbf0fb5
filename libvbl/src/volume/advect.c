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
