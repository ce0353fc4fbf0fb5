/* Piecewise-linear density with piecewise-quadratic CDF inversion (VRL paper section 4.2). */
#include "sampling/piecewise_linear.h"

#include <float.h>

#include "core/math.h"

int vbl_pwl_init(vbl_pwl* p, const double* x, const double* f, int count)
{
    p->count = 0;
    p->uniform = 1;
    p->total = 0.0;
    if (count < 2 || count > VBL_PWL_MAX_VERTICES) return 0;
    for (int i = 0; i < count; ++i) {
        if (!isfinite(x[i]) || (i > 0 && x[i] < x[i - 1])) return 0;
        p->x[i] = x[i];
        p->f[i] = (f[i] > 0.0 && isfinite(f[i])) ? f[i] : 0.0; /* NaN/negative/Inf -> 0 */
    }
    if (!(x[count - 1] > x[0])) return 0;
    p->count = count;
    p->cdf[0] = 0.0;
    for (int i = 0; i + 1 < count; ++i)
        p->cdf[i + 1] = p->cdf[i] + 0.5 * (p->f[i] + p->f[i + 1]) * (p->x[i + 1] - p->x[i]);
    p->total = p->cdf[count - 1];
    p->uniform = !(p->total > DBL_MIN) || !isfinite(p->total);
    return 1;
}

double vbl_pwl_pdf(const vbl_pwl* p, double x)
{
    if (p->count < 2) return 0.0;
    int n = p->count;
    if (x < p->x[0] || x > p->x[n - 1]) return 0.0;
    if (p->uniform) return 1.0 / (p->x[n - 1] - p->x[0]);
    int i = 0;
    while (i + 2 < n && x >= p->x[i + 1]) ++i; /* segment [x_i, x_{i+1}] containing x */
    double w = p->x[i + 1] - p->x[i];
    double a = w > 0.0 ? vbl_clamp((x - p->x[i]) / w, 0.0, 1.0) : 0.0;
    return ((1.0 - a) * p->f[i] + a * p->f[i + 1]) / p->total;
}

double vbl_pwl_sample(const vbl_pwl* p, double xi, double* pdf)
{
    if (p->count < 2) {
        if (pdf) *pdf = 0.0;
        return 0.0;
    }
    int n = p->count;
    xi = vbl_clamp(xi, 0.0, 1.0);
    double x;
    if (p->uniform) {
        x = p->x[0] + xi * (p->x[n - 1] - p->x[0]);
    } else {
        double target = xi * p->total;
        /* First segment whose CDF end exceeds the target; zero-mass segments are never chosen. */
        int i = 0;
        while (i + 2 < n && !(p->cdf[i + 1] > target)) ++i;
        while (i > 0 && !(p->cdf[i + 1] > p->cdf[i])) --i; /* rounding past the last massive one */
        double r = fmax(0.0, target - p->cdf[i]);
        double w = p->x[i + 1] - p->x[i];
        double f0 = p->f[i], f1 = p->f[i + 1];
        /* Solve f0 s + (f1 - f0) s^2 / (2 w) = r for s in [0, w] in the cancellation-free form
         * s = 2 r / (f0 + sqrt(f0^2 + 2 (f1 - f0) r / w)). */
        double disc = fmax(0.0, f0 * f0 + 2.0 * (f1 - f0) * r / w);
        double den = f0 + sqrt(disc);
        double s = den > 0.0 ? 2.0 * r / den : 0.0;
        x = vbl_clamp(p->x[i] + vbl_clamp(s, 0.0, w), p->x[0], p->x[n - 1]);
    }
    if (pdf) *pdf = vbl_pwl_pdf(p, x);
    return x;
}

/* Integral of the (unnormalised) interpolant from x_0 to x. */
static double pwl_cumulative(const vbl_pwl* p, double x)
{
    int n = p->count;
    if (x <= p->x[0]) return 0.0;
    if (x >= p->x[n - 1]) return p->total;
    int i = 0;
    while (i + 2 < n && x >= p->x[i + 1]) ++i;
    double w = p->x[i + 1] - p->x[i];
    double s = x - p->x[i];
    double fx = w > 0.0 ? p->f[i] + (p->f[i + 1] - p->f[i]) * s / w : p->f[i];
    return p->cdf[i] + 0.5 * (p->f[i] + fx) * s;
}

double vbl_pwl_mass(const vbl_pwl* p, double a, double b)
{
    if (p->count < 2 || !(b > a)) return 0.0;
    int n = p->count;
    a = vbl_clamp(a, p->x[0], p->x[n - 1]);
    b = vbl_clamp(b, p->x[0], p->x[n - 1]);
    if (p->uniform) return (b - a) / (p->x[n - 1] - p->x[0]);
    return (pwl_cumulative(p, b) - pwl_cumulative(p, a)) / p->total;
}
