/* Henyey-Greenstein phase function: evaluation, pdf and importance sampling.
 *
 * Convention: cos_theta is the cosine between the direction light travels BEFORE scattering and
 * the direction it travels AFTER; g > 0 is forward scattering. Callers validate |g| < 1.
 * g == 0 takes the isotropic path exactly (value 1/(4 pi), uniform sphere sampling). */
#ifndef VBL_SAMPLING_PHASE_HG_H
#define VBL_SAMPLING_PHASE_HG_H

#include "core/math.h"

#ifdef __cplusplus
extern "C" {
#endif

/* f(theta) = (1 - g^2) / (4 pi (1 + g^2 - 2 g cos_theta)^(3/2)), per steradian; equals the pdf. */
double vbl_hg_eval(double g, double cos_theta);
double vbl_hg_pdf(double g, double cos_theta);
/* Inverse-CDF sample of cos_theta for uniform u in [0,1]: monotone increasing in u. */
double vbl_hg_sample_cos(double g, double u);
/* Samples a new travel direction for light that travelled along unit `travel_direction`;
 * *pdf (solid angle) may be NULL. u1 picks the polar angle, u2 the azimuth. */
vbl_vec3 vbl_hg_sample(double g, vbl_vec3 travel_direction, double u1, double u2, double* pdf);

#ifdef __cplusplus
}
#endif

#endif
