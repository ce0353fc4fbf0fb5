/* Angular-domain sampler of a segment about a point (VRL paper section 4.3; VBL sections 3.1, 3.3). */
#include "transport/surface/surface_line_sampler.h"

#include <stddef.h>

#include "sampling/cauchy.h"

int vbl_surface_line_init(vbl_surface_line_sampler* s, vbl_vec3 o, vbl_vec3 d, double t0, double t1, vbl_vec3 q,
                          double radius)
{
    s->valid = 0;
    s->defensive = 1.0;
    s->pwl.count = 0;
    s->o = o;
    s->d = d;
    s->q = q;
    s->t0 = t0;
    s->t1 = t1;
    double r = (radius > 0.0 && isfinite(radius)) ? radius : 0.0;
    if (!(t1 > t0) || !isfinite(t0) || !isfinite(t1)) return 0;
    vbl_vec3 oq = vbl_v3_sub(q, o);
    s->tp = vbl_v3_dot(oq, d);
    vbl_vec3 perp = vbl_v3_madd(oq, d, -s->tp);
    s->dist = vbl_v3_length(perp);
    if (s->dist > 0.0) {
        s->a = vbl_v3_scale(perp, 1.0 / s->dist);
    } else {
        vbl_vec3 b;
        vbl_v3_basis(d, &s->a, &b);
    }
    double scale = fmax(fabs(t0 - s->tp), fabs(t1 - s->tp));
    double floor_h = VBL_SAMPLING_H_FLOOR_REL * scale;
    s->h = hypot(fmax(s->dist, floor_h), r);
    if (!(s->h > 0.0) || !isfinite(s->h)) return 0;
    s->phi0 = atan((t0 - s->tp) / s->h);
    s->phi1 = atan((t1 - s->tp) / s->h);
    s->valid = s->phi1 > s->phi0;
    return s->valid;
}

vbl_vec3 vbl_surface_line_point(const vbl_surface_line_sampler* s, double t) { return vbl_v3_madd(s->o, s->d, t); }

/* True angle psi (tan psi = (t - tp) / dist) to the mapping's phi, clamped to the segment. */
static double phi_of_psi(const vbl_surface_line_sampler* s, double psi)
{
    double lim = 0.5 * VBL_PI;
    double phi;
    if (psi >= lim) phi = lim;
    else if (psi <= -lim) phi = -lim;
    else phi = atan(s->dist * tan(psi) / s->h);
    return vbl_clamp(phi, s->phi0, s->phi1);
}

int vbl_surface_line_angle_toward(const vbl_surface_line_sampler* s, vbl_vec3 dir, double* phi)
{
    if (!s->valid || !(s->dist > 0.0)) return 0;
    /* Direction from q to the point at true angle psi: -cos(psi) a + sin(psi) d. */
    double psi = atan2(vbl_v3_dot(dir, s->d), -vbl_v3_dot(dir, s->a));
    *phi = phi_of_psi(s, psi);
    return 1;
}

int vbl_surface_line_angle_horizon(const vbl_surface_line_sampler* s, vbl_vec3 n, double* phi)
{
    if (!s->valid || !(s->dist > 0.0)) return 0;
    double na = vbl_v3_dot(n, s->a), nd = vbl_v3_dot(n, s->d);
    if (nd == 0.0) return 0;
    /* n . (-cos psi a + sin psi d) = 0 <=> tan psi = na / nd */
    double p = phi_of_psi(s, atan(na / nd));
    if (!(p > s->phi0 && p < s->phi1)) return 0;
    *phi = p;
    return 1;
}

static double t_of_phi(const vbl_surface_line_sampler* s, double phi)
{
    return vbl_clamp(s->tp + s->h * tan(phi), s->t0, s->t1);
}

void vbl_surface_line_fit(vbl_surface_line_sampler* s, const double* hints, int hint_count,
                          vbl_surface_line_target_fn target, void* ctx)
{
    if (!s->valid) return;
    double x[VBL_SURFACE_LINE_VERTICES], f[VBL_SURFACE_LINE_VERTICES];
    int m = 0;
    if (hint_count > VBL_SURFACE_LINE_MAX_HINTS) hint_count = VBL_SURFACE_LINE_MAX_HINTS;
    if (hint_count < 0) hint_count = 0;
    int fill = VBL_SURFACE_LINE_VERTICES - hint_count; /* endpoints included */
    for (int i = 0; i < fill; ++i) x[m++] = s->phi0 + (s->phi1 - s->phi0) * i / (fill - 1);
    for (int i = 0; i < hint_count; ++i) x[m++] = isfinite(hints[i]) ? vbl_clamp(hints[i], s->phi0, s->phi1) : s->phi0;
    /* insertion sort */
    for (int i = 1; i < m; ++i) {
        double v = x[i];
        int j = i - 1;
        while (j >= 0 && x[j] > v) {
            x[j + 1] = x[j];
            --j;
        }
        x[j + 1] = v;
    }
    x[0] = s->phi0;
    x[m - 1] = s->phi1;
    for (int i = 0; i < m; ++i) {
        double v = target(ctx, vbl_surface_line_point(s, t_of_phi(s, x[i])));
        f[i] = (v > 0.0 && isfinite(v)) ? v : 0.0;
    }
    if (!vbl_pwl_init(&s->pwl, x, f, m)) return; /* keeps the equiangular density */
    s->defensive = VBL_SURFACE_LINE_DEFENSIVE;
}

static double phi_pdf(const vbl_surface_line_sampler* s, double phi)
{
    double p = s->defensive / (s->phi1 - s->phi0);
    if (s->defensive < 1.0) p += (1.0 - s->defensive) * vbl_pwl_pdf(&s->pwl, phi);
    return p;
}

double vbl_surface_line_pdf(const vbl_surface_line_sampler* s, double t)
{
    if (!s->valid || !(t >= s->t0 && t <= s->t1)) return 0.0;
    double dt = t - s->tp;
    double phi = vbl_clamp(atan(dt / s->h), s->phi0, s->phi1);
    return phi_pdf(s, phi) * s->h / (s->h * s->h + dt * dt);
}

double vbl_surface_line_sample(const vbl_surface_line_sampler* s, double xi, double* pdf)
{
    if (!s->valid) {
        if (pdf) *pdf = 0.0;
        return s->t0;
    }
    xi = vbl_clamp(xi, 0.0, 1.0);
    double phi;
    if (xi < s->defensive) {
        phi = s->phi0 + (s->phi1 - s->phi0) * (xi / s->defensive);
    } else {
        double u = (xi - s->defensive) / (1.0 - s->defensive);
        phi = vbl_pwl_sample(&s->pwl, fmin(u, 1.0), NULL);
    }
    double t = t_of_phi(s, phi);
    if (pdf) *pdf = vbl_surface_line_pdf(s, t);
    return t;
}
