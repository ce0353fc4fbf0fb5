/* Adaptive Gauss-Legendre quadrature (nodes computed by Newton iteration on P_16). */
#include "quad.h"

#include <math.h>

#define GL_N 16
static double gl_x[GL_N], gl_w[GL_N];
static int gl_ready = 0;

static void gl_init(void)
{
    if (gl_ready) return;
    const double pi = 3.14159265358979323846;
    for (int i = 0; i < GL_N; ++i) {
        double x = cos(pi * (i + 0.75) / (GL_N + 0.5)), dp = 1.0;
        for (int it = 0; it < 100; ++it) {
            double p0 = 1.0, p1 = x; /* Legendre recurrence */
            for (int k = 2; k <= GL_N; ++k) {
                double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
                p0 = p1;
                p1 = p2;
            }
            dp = GL_N * (x * p1 - p0) / (x * x - 1.0);
            double dx = p1 / dp;
            x -= dx;
            if (fabs(dx) < 1e-16) break;
        }
        gl_x[i] = x;
        gl_w[i] = 2.0 / ((1.0 - x * x) * dp * dp);
    }
    gl_ready = 1;
}

double vbl_quad_gl16(vbl_quad_fn f, void* ctx, double a, double b)
{
    gl_init();
    double m = 0.5 * (a + b), r = 0.5 * (b - a), s = 0.0;
    for (int i = 0; i < GL_N; ++i) s += gl_w[i] * f(m + r * gl_x[i], ctx);
    return s * r;
}

static double adapt(vbl_quad_fn f, void* ctx, double a, double b, double whole, double abs_tol, double rel_tol,
                    int depth)
{
    double m = 0.5 * (a + b);
    double left = vbl_quad_gl16(f, ctx, a, m), right = vbl_quad_gl16(f, ctx, m, b);
    double sum = left + right;
    if (depth >= 50 || fabs(sum - whole) <= fmax(abs_tol, rel_tol * fabs(sum)) || !(m > a && m < b)) return sum;
    return adapt(f, ctx, a, m, left, abs_tol, rel_tol, depth + 1) + adapt(f, ctx, m, b, right, abs_tol, rel_tol, depth + 1);
}

double vbl_quad_adaptive(vbl_quad_fn f, void* ctx, double a, double b, double abs_tol, double rel_tol)
{
    if (!(b > a)) return 0.0;
    return adapt(f, ctx, a, b, vbl_quad_gl16(f, ctx, a, b), abs_tol, rel_tol, 0);
}
