/* Piecewise-constant 1D density on [x_0, x_n]: value y_k on [x_k, x_{k+1}), normalised; sampled
 * by inverting its piecewise-linear CDF. Used to draw the camera-ray point of a VRL pair in
 * proportion to the cached camera transmittance (a step function, volume/transmittance_cache.h;
 * transport/virtual_lights/vrl.c).
 *
 * Values must be >= 0 (negative or NaN read as 0). Without usable mass (all zero, or a total that
 * is not a positive finite number) the density is uniform over [x_0, x_n] and the pdf reports
 * that uniform density, so estimators stay unbiased. `defensive` in [0, 1) mixes in that much of
 * the uniform density everywhere (full support where values are 0). */
#ifndef VBL_SAMPLING_STEP_PDF_H
#define VBL_SAMPLING_STEP_PDF_H

#ifdef __cplusplus
extern "C" {
#endif

#define VBL_STEP_PDF_MAX_PIECES 260

typedef struct vbl_step_pdf {
    int count;                               /* pieces n, 1..VBL_STEP_PDF_MAX_PIECES */
    double defensive;                        /* uniform share */
    double x[VBL_STEP_PDF_MAX_PIECES + 1];   /* breakpoints, non-decreasing */
    double y[VBL_STEP_PDF_MAX_PIECES];       /* values (sanitised) */
    double cdf[VBL_STEP_PDF_MAX_PIECES + 1]; /* unnormalised mass of the step part up to x_k */
} vbl_step_pdf;

/* x: n + 1 breakpoints, y: n values. Returns 0 (unusable) if n is outside [1, MAX], the
 * breakpoints are not finite / non-decreasing, the domain has zero width or defensive is outside
 * [0, 1). */
int vbl_step_pdf_init(vbl_step_pdf* p, const double* x, const double* y, int n, double defensive);
/* Samples x in [x_0, x_n]; *pdf (may be NULL) is the normalised density there. */
double vbl_step_pdf_sample(const vbl_step_pdf* p, double xi, double* pdf);
/* Density at x (0 outside [x_0, x_n]). */
double vbl_step_pdf_pdf(const vbl_step_pdf* p, double x);

#ifdef __cplusplus
}
#endif

#endif
