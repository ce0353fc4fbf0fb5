/* Beam x beam 1D photon beam estimate, Jarosz et al. 2011a, section 7.3, eq. 38. */
#include "transport/photon_beams/photon_beam_kernel.h"

#include "sampling/phase_hg.h"

double vbl_biweight_1d(double x)
{
    if (!(fabs(x) <= 1.0)) return 0.0;
    double a = 1.0 - x * x;
    return (15.0 / 16.0) * a * a;
}

/* Intersects [*lo, *hi] with {u : lower <= a + b u <= upper}; no division by b == 0. */
static void clip_linear(double* lo, double* hi, double a, double b, double lower, double upper)
{
    if (b > 0.0) {
        *lo = fmax(*lo, (lower - a) / b);
        *hi = fmin(*hi, (upper - a) / b);
    } else if (b < 0.0) {
        *lo = fmax(*lo, (upper - a) / b);
        *hi = fmin(*hi, (lower - a) / b);
    } else if (!(a >= lower && a <= upper)) {
        *hi = *lo - 1.0; /* empty */
    }
}

int vbl_photon_beam_eval(vbl_vec3 c_o, vbl_vec3 c_d, double len_c, vbl_vec3 b_o, vbl_vec3 b_d, double len_b, double r,
                         vbl_photon_beam_eval_result* out)
{
    out->weight = 0.0;
    out->t_c = 0.0;
    out->t_b = 0.0;
    out->cos_scatter = -vbl_v3_dot(b_d, c_d);
    out->sin_theta = 0.0;
    out->distance = 0.0;
    if (!(r > 0.0) || !(len_c > 0.0) || !(len_b > 0.0) || !isfinite(r)) return 0;
    vbl_vec3 rel = vbl_v3_sub(c_o, b_o);
    vbl_vec3 bxc = vbl_v3_cross(b_d, c_d);
    double s = vbl_v3_length(bxc);
    vbl_vec3 y0 = vbl_v3_cross(b_d, vbl_v3_cross(rel, b_d)); /* camera origin's offset from the beam line */
    double yn, ym0;
    if (s > 0.0) {
        vbl_vec3 n = vbl_v3_scale(bxc, 1.0 / s);
        vbl_vec3 m = vbl_v3_cross(n, b_d); /* unit, along the camera's perpendicular motion */
        if (vbl_v3_dot(m, c_d) < 0.0) m = vbl_v3_scale(m, -1.0);
        yn = vbl_v3_dot(rel, n);
        ym0 = vbl_v3_dot(y0, m);
    } else { /* exactly parallel: m along the (constant) offset */
        yn = 0.0;
        ym0 = vbl_v3_length(y0);
    }
    out->sin_theta = s;
    out->distance = fabs(yn);
    double k = vbl_biweight_1d(yn / r);
    if (!(k > 0.0)) return 0;
    double lo = 0.0, hi = len_c;
    clip_linear(&lo, &hi, ym0, s, -r, r);                                  /* |y_m(u)| <= r */
    clip_linear(&lo, &hi, vbl_v3_dot(rel, b_d), vbl_v3_dot(c_d, b_d), 0.0, len_b); /* on the beam */
    if (!(hi > lo)) return 0;
    /* weight = K_r(y_n) |U| / (2 r); |U| = 2 r / s unclipped (eq 38) */
    out->weight = (k / r) * (hi - lo) / (2.0 * r);
    out->t_c = 0.5 * (lo + hi);
    out->t_b = vbl_v3_dot(vbl_v3_sub(vbl_v3_madd(c_o, c_d, out->t_c), b_o), b_d);
    out->t_b = vbl_clamp(out->t_b, 0.0, len_b);
    return out->weight > 0.0 && isfinite(out->weight);
}

double vbl_photon_beam_estimate(const vbl_segment* camera, const vbl_segment* beam, double r, double power,
                                double sigma_s, double g, vbl_beam_transmittance_fn transmittance, void* ctx)
{
    const vbl_vec3 c_o = vbl_segment_at(camera, camera->t0), c_d = camera->direction;
    const vbl_vec3 b_o = vbl_segment_at(beam, beam->t0), b_d = beam->direction;
    const double len_c = camera->t1 - camera->t0, len_b = beam->t1 - beam->t0;
    vbl_photon_beam_eval_result e;
    if (!vbl_photon_beam_eval(c_o, c_d, len_c, b_o, b_d, len_b, r, &e)) return 0.0;
    double tb = 1.0, tc = 1.0;
    if (transmittance) {
        tb = transmittance(ctx, b_o, b_d, e.t_b);
        tc = transmittance(ctx, c_o, c_d, e.t_c);
    }
    return sigma_s * vbl_hg_eval(g, e.cos_scatter) * power * tb * tc * e.weight;
}
