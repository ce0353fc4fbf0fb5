/* Transmittance-aware sampling of a camera-ray / VRL pair (issue 13, item 3): one-sample multiple
 * importance sampling (Veach 1997, section 9.2.4, balance heuristic) of two techniques for the
 * (u, v) of eq (7) of Novak et al. 2012 (VRL):
 *   1. the product sampler of sampling/vrl_pair.h (v from the inverse-distance marginal, u given
 *      v by the two HG lobes; VRL section 4, appendix A) — blind to the camera transmittance;
 *   2. u from a step density along the camera segment (sampling/step_pdf.h; the estimator passes
 *      the camera ray's cached transmittance, so u stays where light can still reach the camera),
 *      then v given u by equiangular sampling along the VRL (Kulla and Fajardo 2012; density
 *      proportional to 1 / w^2 about the camera point).
 * Technique 1 is chosen with probability VBL_VRL_CAMERA_MIS_SHARE; the returned pdf is the
 * mixture c p1 + (1 - c) p2 at the drawn (u, v), so f / pdf is unbiased wherever either technique
 * has support (technique 1 covers the whole pair). */
#ifndef VBL_SAMPLING_VRL_CAMERA_MIS_H
#define VBL_SAMPLING_VRL_CAMERA_MIS_H

#include "sampling/step_pdf.h"
#include "sampling/vrl_pair.h"

#ifdef __cplusplus
extern "C" {
#endif

#define VBL_VRL_CAMERA_MIS_SHARE 0.5

/* `camera` is a density over [pair->u0, pair->u1]. xi_choice picks the technique, xi1 and xi2
 * drive it. Returns 0 (out->pdf 0) if the draw has no density. */
int vbl_vrl_camera_mis_draw(const vbl_vrl_pair* pair, const vbl_step_pdf* camera, double xi_choice, double xi1,
                            double xi2, vbl_vrl_pair_sample* out);
/* The mixture density at (u, v) (what the draw returns as pdf). */
double vbl_vrl_camera_mis_density(const vbl_vrl_pair* pair, const vbl_step_pdf* camera, double u, double v);
/* Technique 2's density alone: camera(u) x equiangular(v | camera point u). */
double vbl_vrl_camera_technique_pdf(const vbl_vrl_pair* pair, const vbl_step_pdf* camera, double u, double v);

#ifdef __cplusplus
}
#endif

#endif
