/* Inverse-distance marginal along a VRL, VRL paper eqs (10)-(13), in a cancellation-free form. */
#include "sampling/sinh_marginal.h"

#include "core/math.h"
#include "sampling/cauchy.h"

/* sinh(x)/x and asinh(x)/x, exact limits 1 at 0. */
static double sinhc(double x) { return fabs(x) < 1e-4 ? 1.0 + x * x / 6.0 : sinh(x) / x; }
static double asinhc(double x) { return fabs(x) < 1e-4 ? 1.0 - x * x / 6.0 : asinh(x) / x; }

int vbl_sinh_marginal_init(vbl_sinh_marginal* m, double beta, double sin_theta, double h, double len)
{
    m->valid = 0;
    m->beta = beta;
    m->s = vbl_clamp(fabs(sin_theta), 0.0, 1.0);
    m->len = len;
    m->h = 0.0;
    m->dist0 = 0.0;
    m->norm = 0.0;
    m->width = 0.0;
    if (!(len > 0.0) || !isfinite(len) || !isfinite(beta) || !isfinite(h)) return 0;
    double scale = len + hypot(h, beta);
    m->h = fmax(fabs(h), VBL_SAMPLING_H_FLOOR_REL * scale);
    if (!(m->h > 0.0)) return 0;
    m->dist0 = hypot(m->h, beta);
    /* a = A-argument at both ends (eq 11's A(x) = asinh(x sin theta / h)). */
    double a0 = beta / m->h;
    double a1 = (beta + m->s * len) / m->h;
    if (a0 * a1 >= 0.0) {
        /* Same sign: asinh(a1) - asinh(a0) = asinh(z),
         * z = (a1^2 - a0^2) / (a1 sqrt(1 + a0^2) + a0 sqrt(1 + a1^2)), a1 - a0 = s len / h;
         * G = (asinh z) / s = (len / h) ((a0 + a1) / den) asinhc(z): finite as s -> 0. */
        double den = a1 * hypot(1.0, a0) + a0 * hypot(1.0, a1);
        double ratio = den != 0.0 ? (a0 + a1) / den : 1.0;
        double z = (m->s * len / m->h) * ratio;
        m->norm = (len / m->h) * ratio * asinhc(z);
    } else {
        /* Opposite signs: no cancellation (and s > 0 since a1 != a0). */
        m->norm = (asinh(a1) - asinh(a0)) / m->s;
    }
    m->width = m->s * m->norm;
    if (!(m->norm > 0.0) || !isfinite(m->norm)) return 0;
    m->valid = 1;
    return 1;
}

double vbl_sinh_marginal_pdf_t(const vbl_sinh_marginal* m, double t)
{
    if (!m->valid || t < 0.0 || t > m->len) return 0.0;
    double y = m->beta + m->s * t;
    return 1.0 / (m->norm * hypot(m->h, y));
}

double vbl_sinh_marginal_sample_t(const vbl_sinh_marginal* m, double xi, double* pdf)
{
    if (!m->valid) {
        if (pdf) *pdf = 0.0;
        return 0.0;
    }
    xi = vbl_clamp(xi, 0.0, 1.0);
    double x = xi * m->width; /* eq (13)'s lerp, measured from A(vhat0) */
    double t;
    if (m->width <= 1.0) {
        /* t = [beta (cosh x - 1) + dist0 sinh x] / s (sinh addition theorem applied to eq 13),
         * rewritten with x / s = xi G so that s -> 0 gives t = xi len (uniform). */
        double xg = xi * m->norm;
        double sh = sinhc(0.5 * x);
        t = xg * (m->beta * 0.5 * x * sh * sh + m->dist0 * sinhc(x));
    } else {
        /* Wide angular range (s len > h): eq (13) directly, (h sinh(A0 + x) - beta) / s. */
        double y = m->h * sinh(asinh(m->beta / m->h) + x);
        t = (y - m->beta) / m->s;
    }
    t = vbl_clamp(t, 0.0, m->len);
    if (pdf) *pdf = vbl_sinh_marginal_pdf_t(m, t);
    return t;
}

double vbl_sinh_marginal_sample(double h, double sin_theta, double vhat0, double vhat1, double xi, double* pdf)
{
    vbl_sinh_marginal m;
    if (!vbl_sinh_marginal_init(&m, vhat0 * fabs(sin_theta), sin_theta, h, vhat1 - vhat0)) {
        if (pdf) *pdf = 0.0;
        return vhat0;
    }
    return vhat0 + vbl_sinh_marginal_sample_t(&m, xi, pdf);
}

double vbl_sinh_marginal_pdf(double h, double sin_theta, double vhat0, double vhat1, double vhat)
{
    vbl_sinh_marginal m;
    if (!vbl_sinh_marginal_init(&m, vhat0 * fabs(sin_theta), sin_theta, h, vhat1 - vhat0)) return 0.0;
    return vbl_sinh_marginal_pdf_t(&m, vhat - vhat0);
}
