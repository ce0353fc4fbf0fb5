/* Mid-bound optical depth over the merged majorant segments (control_depth.h). */
#include "volume/control_depth.h"

double vbl_control_optical_depth(const vbl_extinction* ext, vbl_vec3 origin, vbl_vec3 direction, double t0,
                                 double t, int use_global_majorant)
{
    if (!(t > t0) || ext->count == 0) return 0.0;
    vbl_extinction_iter iter;
    vbl_majorant_segment seg;
    double tau = 0.0;
    vbl_extinction_iter_init(&iter, ext, origin, direction, t0, t, use_global_majorant);
    while (vbl_extinction_iter_next(&iter, &seg)) tau += 0.5 * (seg.majorant + seg.minorant) * (seg.t1 - seg.t0);
    return tau;
}
