/* Piecewise-linear 1D density (VRL paper section 4.2): M <= 16 vertices (x_i, f_i) with
 * increasing x_i; the density is the linear interpolant of f normalised over [x_0, x_{M-1}],
 * sampled by inverting the piecewise-quadratic CDF.
 *
 * Vertex values must be >= 0; negative or NaN values are read as 0. When the interpolant has no
 * usable mass (all values zero, or an integral that is not a positive finite number, e.g. all
 * values below ~1e-300) the density falls back to uniform over [x_0, x_{M-1}] — documented, and
 * the pdf reports that uniform density, so estimators stay unbiased. A zero vertex value means
 * zero density there: callers who need full support must pass positive values. */
#ifndef VBL_SAMPLING_PIECEWISE_LINEAR_H
#define VBL_SAMPLING_PIECEWISE_LINEAR_H

#ifdef __cplusplus
extern "C" {
#endif

#define VBL_PWL_MAX_VERTICES 16

typedef struct vbl_pwl {
    int count;                          /* vertices M, 2..16 */
    int uniform;                        /* 1: no usable mass, uniform fallback */
    double x[VBL_PWL_MAX_VERTICES];     /* positions, non-decreasing */
    double f[VBL_PWL_MAX_VERTICES];     /* values (sanitised) */
    double cdf[VBL_PWL_MAX_VERTICES];   /* unnormalised integral up to vertex i */
    double total;                       /* integral over [x_0, x_{M-1}] */
} vbl_pwl;

/* Builds the density; returns 0 (and leaves an unusable distribution) if count is outside
 * [2, 16], positions are not non-decreasing/finite, or the domain has zero width. */
int vbl_pwl_init(vbl_pwl* p, const double* x, const double* f, int count);
/* Samples x in [x_0, x_{M-1}]; *pdf (may be NULL) is the normalised density there. */
double vbl_pwl_sample(const vbl_pwl* p, double xi, double* pdf);
double vbl_pwl_pdf(const vbl_pwl* p, double x);
/* Probability mass of [a, b] (exact integral of the density; used by tests). */
double vbl_pwl_mass(const vbl_pwl* p, double a, double b);

#ifdef __cplusplus
}
#endif

#endif
