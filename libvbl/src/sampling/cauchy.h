/* Truncated Cauchy distribution of VRL paper eq (14): density over uhat in [uhat0, uhat1]
 * proportional to 1 / (h^2 + uhat^2), i.e. inverse squared distance along a line whose closest
 * approach to a point is h at uhat = 0 (Kulla & Fajardo's equiangular sampling). */
#ifndef VBL_SAMPLING_CAUCHY_H
#define VBL_SAMPLING_CAUCHY_H

#ifdef __cplusplus
extern "C" {
#endif

/* Relative floor on closest-approach distances: h is raised to at least this times the segment
 * scale (largest |endpoint|), so h = 0 exactly (point on the line) stays finite. Sampler and pdf
 * use the same floored h, so the density returned is exactly the density sampled. */
#define VBL_SAMPLING_H_FLOOR_REL 1e-9

/* Eq (14): uhat = h tan(lerp(B(uhat0), B(uhat1), xi)), B(x) = atan(x / h).
 * Returns uhat in [uhat0, uhat1]; *pdf = h / ((B1 - B0)(h^2 + uhat^2)) (may be NULL).
 * A zero-length interval (uhat1 <= uhat0) has no support: returns uhat0 with *pdf = 0. */
double vbl_cauchy_sample(double h, double uhat0, double uhat1, double xi, double* pdf);
double vbl_cauchy_pdf(double h, double uhat0, double uhat1, double uhat);

#ifdef __cplusplus
}
#endif

#endif
