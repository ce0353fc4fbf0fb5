/* Progressive radius reduction, Novak et al. 2012 (VBL), section 4.1, eq. 11. */
#include "transport/common/radius_schedule.h"

static int params_ok(double alpha, int dim) { return alpha > 0.0 && alpha <= 1.0 && (dim == 1 || dim == 2); }

double vbl_radius_at_pass(double r0, double alpha, int dim, uint64_t pass)
{
    if (!(r0 > 0.0) || !isfinite(r0) || !params_ok(alpha, dim)) return 0.0;
    double p = (double)pass;
    /* log prod_{k=1..p} (k + alpha) / (k + 1) = lgamma(p + 1 + alpha) - lgamma(1 + alpha) - lgamma(p + 2) */
    double lg = lgamma(p + 1.0 + alpha) - lgamma(1.0 + alpha) - lgamma(p + 2.0);
    return r0 * exp(lg / dim);
}

double vbl_radius_next(double r_p, double alpha, int dim, uint64_t pass)
{
    if (!params_ok(alpha, dim)) return 0.0;
    double p = (double)pass;
    double ratio = (p + 1.0 + alpha) / (p + 2.0);
    return r_p * (dim == 2 ? sqrt(ratio) : ratio);
}

double vbl_radius_bias_exponent(double alpha, int dim) { return 2.0 * (alpha - 1.0) / (dim == 1 ? 1.0 : 2.0); }
double vbl_radius_variance_exponent(double alpha) { return -alpha; }
double vbl_radius_rmse_exponent(double alpha, int dim)
{
    return fmax(vbl_radius_bias_exponent(alpha, dim), 0.5 * vbl_radius_variance_exponent(alpha));
}

double vbl_radius_default_r0(vbl_vec3 bounds_min, vbl_vec3 bounds_max, double total_length, double k)
{
    vbl_vec3 e = vbl_v3_sub(bounds_max, bounds_min);
    double diag = vbl_v3_length(e);
    if (!(diag > 0.0) || !isfinite(diag) || !(e.x >= 0.0 && e.y >= 0.0 && e.z >= 0.0)) return 0.0;
    if (!(k > 0.0) || !isfinite(k)) k = VBL_RADIUS_OVERLAP_DEFAULT;
    double volume = e.x * e.y * e.z;
    double r0 = 0.01 * diag;
    if (volume > 0.0 && total_length > 0.0 && isfinite(total_length)) r0 = k * sqrt(volume / total_length);
    return vbl_clamp(r0, 1e-4 * diag, 0.1 * diag);
}
