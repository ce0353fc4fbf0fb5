/* Numerical quadrature for tests: adaptive Gauss-Legendre on [a, b]. */
#ifndef VBL_TEST_QUAD_H
#define VBL_TEST_QUAD_H

#ifdef __cplusplus
extern "C" {
#endif

typedef double (*vbl_quad_fn)(double x, void* ctx);

/* Fixed 16-point Gauss-Legendre on [a, b]. */
double vbl_quad_gl16(vbl_quad_fn f, void* ctx, double a, double b);
/* Adaptive: splits until 16-point GL on an interval agrees with the sum over its halves within
 * max(abs_tol, rel_tol |estimate|) per interval, depth <= 50 (a jump converges only in
 * depth, so split integrals at known discontinuities). */
double vbl_quad_adaptive(vbl_quad_fn f, void* ctx, double a, double b, double abs_tol, double rel_tol);

#ifdef __cplusplus
}
#endif

#endif
