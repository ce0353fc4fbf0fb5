/* Progressive radius reduction (Novak et al. 2012 (VBL), section 4.1, eq. 11; the progressive
 * photon beams reduction it cites).
 *
 * Passes are numbered p = 0, 1, 2, ... (the paper's i = p + 1). With the kernel's blur dimension
 * d (d = 2 for VSLs/VBLs, whose BRE blurs in 2D, eq 11 "applied to the squared radius"; d = 1 for
 * the 1D beam x beam photon-beam estimate, whose width is reduced linearly):
 *     R_p^d = R_0^d prod_{k=1..p} (k + alpha) / (k + 1)
 *           = R_0^d (prod_{k=1..p} (k + alpha) / k) / (p + 1)          (eq 11's product form)
 *           = R_0^d Gamma(p + 1 + alpha) / (Gamma(1 + alpha) Gamma(p + 2)),
 * i.e. the recurrence R_{p+1}^d = R_p^d (p + 1 + alpha) / (p + 2), R_0 used by the first pass.
 * (Eq 11 as printed carries the passes' photon counts M_i, which cancel for a fixed number of
 * VRLs per pass, the only mode libvbl has.) alpha in (0, 1), default 0.7.
 *
 * Asymptotics: R_p^d ~ p^(alpha - 1) / Gamma(1 + alpha). With kernel bias ~ R^2 and per-pass
 * variance ~ 1 / R^d, the bias of the average of p passes falls like p^(2 (alpha - 1) / d) and its
 * variance like p^(-alpha); both -> 0 with fixed memory per pass. */
#ifndef VBL_RENDER_RADIUS_SCHEDULE_H
#define VBL_RENDER_RADIUS_SCHEDULE_H

#include <stdint.h>

#include "core/math.h"

#ifdef __cplusplus
extern "C" {
#endif

#define VBL_RADIUS_ALPHA_DEFAULT 0.7
/* Default R_0 = k * sqrt(V / L) with k = VBL_RADIUS_OVERLAP_DEFAULT: see vbl_radius_default_r0. */
#define VBL_RADIUS_OVERLAP_DEFAULT 1.0

/* R_p for pass p (0-based); 0 if r0 <= 0, alpha outside (0, 1] or dim not 1 or 2.
 * Closed form through lgamma (relative error ~1e-12 for p < 1e9). */
double vbl_radius_at_pass(double r0, double alpha, int dim, uint64_t pass);
/* One step of the recurrence: R_{p+1} from R_p (the product form multiplied out). */
double vbl_radius_next(double r_p, double alpha, int dim, uint64_t pass);
/* Exponents of the pass-averaged estimate (see above): bias ~ p^e_b, variance ~ p^e_v;
 * RMSE ~ p^max(e_b, e_v / 2). */
double vbl_radius_bias_exponent(double alpha, int dim);
double vbl_radius_variance_exponent(double alpha);
double vbl_radius_rmse_exponent(double alpha, int dim);

/* Default initial radius from the scene's scale and the VRL (or photon beam) density:
 *     R_0 = k * sqrt(V / L),
 * V the volume of the media's bounding box, L the total length of the VRLs (beams) of ONE pass,
 * so L / V is the beam length per unit volume and sqrt(V / L) the mean spacing between beams; a
 * point then lies within R_0 of pi k^2 beams on average (k = 1: ~3). The result is clamped to
 * [1e-4, 0.1] x the box diagonal (also when L == 0 or a flat box: 0.01 x diagonal if V or L is
 * 0). Returns 0 for an empty or non-finite box. k <= 0 selects VBL_RADIUS_OVERLAP_DEFAULT. */
double vbl_radius_default_r0(vbl_vec3 bounds_min, vbl_vec3 bounds_max, double total_length, double k);

#ifdef __cplusplus
}
#endif

#endif
