/* Camera-transmittance x geometry sampling of a camera-ray / VRL pair (issue 13, item 3): a
 * third (u, v) technique for eq (7) of Novak et al. 2012 (VRL), MIS-combined with the product
 * sampler of sampling/vrl_pair.h.
 *
 * The technique draws the camera-ray point u first, from
 *     p(u) ~ Tc(u) / dist(c(u), VRL line),
 * a piecewise density: Tc is the camera ray's cached transmittance (a step function,
 * volume/transmittance_cache.h, given as a vbl_step_pdf over [u0, u1]) and 1 / dist is the
 * inverse-distance marginal of the 1 / w^2 term to the infinite VRL line (Novak et al. 2012
 * (VRL), section 4.1, eqs 10-13, with the roles of the two segments swapped; closed form per
 * step, below). Then v given u by the product sampler's second stage with the roles of the
 * segments exchanged (vbl_vrl_pair_swap): the two HG lobes as a piecewise-linear density over the
 * arc the VRL subtends at the camera point (Novak et al. 2012 (VRL), appendix A, eqs 16-20;
 * equiangular, Kulla and Fajardo 2012, when both g are 0). The joint density so follows
 * Tc(u) f_s f_s / w^2 (up to the finite VRL's angular extent in the marginal), unlike the product
 * sampler (blind to Tc) and the camera technique of sampling/vrl_camera_mis.h (u ~ Tc alone,
 * blind to the near-crossing peak of 1 / w^2, v by 1 / w^2 alone).
 *
 * Steps beyond VBL_VRL_TC_MAX_PIECES are merged (length-weighted mean of Tc): any positive
 * density is unbiased, the merge only coarsens the shape. The one-sample MIS (Veach 1997,
 * section 9.2.4, balance heuristic) picks the product sampler with probability
 * VBL_VRL_TC_PAIR_SHARE; the pdf returned is the mixture at the drawn (u, v), so f / pdf is
 * unbiased wherever either technique has support (the product sampler covers the whole pair). */
#ifndef VBL_SAMPLING_VRL_TC_PAIR_H
#define VBL_SAMPLING_VRL_TC_PAIR_H

#include "sampling/step_pdf.h"
#include "sampling/vrl_pair.h"

#ifdef __cplusplus
extern "C" {
#endif

#define VBL_VRL_TC_MAX_PIECES 16
#define VBL_VRL_TC_PAIR_SHARE 0.5

/* The u marginal p(u) ~ Tc(u) / dist(u) of one pair. With dist(t) = sqrt(h^2 + (beta + s t)^2),
 * t = u - u0 (eq 10's geometry), 1 / dist integrates over a piece to (A(t1) - A(t0)) / s,
 * A(t) = asinh((beta + s t) / h) (eq 12): one asinh per breakpoint. Nearly parallel lines
 * (s L / h < 1e-4 over the whole segment, where 1 / dist varies by < 1e-8) take 1 / dist at each
 * piece's midpoint instead (a plain step density, uniform within pieces). */
typedef struct vbl_vrl_tc_marginal {
    int count;                             /* pieces */
    int flat;                              /* 1: the near-parallel step form */
    double beta, s, h, u0;                 /* dist(u) = sqrt(h^2 + (beta + s (u - u0))^2), h floored */
    double x[VBL_VRL_TC_MAX_PIECES + 1];   /* breakpoints in u */
    double a[VBL_VRL_TC_MAX_PIECES + 1];   /* A(x[k]) (flat: unused) */
    double cdf[VBL_VRL_TC_MAX_PIECES + 1]; /* unnormalised mass up to x[k], in units of 1 / s (flat: 1) */
    double y[VBL_VRL_TC_MAX_PIECES];       /* Tc of the piece (flat: Tc / dist(midpoint)) */
    vbl_vrl_pair swapped;                  /* the pair with roles exchanged: v given u (vbl_vrl_pair_swap) */
    int valid;
} vbl_vrl_tc_marginal;

/* Builds the marginal of the pair p (camera segment [p->u0, p->u1]) and the camera density
 * `camera` (its step values are read as Tc; its domain should be [p->u0, p->u1]). drops = 0:
 * p(u) ~ Tc(u) / dist(u). drops = 1: each step's weight is the drop of Tc at its end, spread over
 * the step, instead of Tc times its length: for a ratio-tracking cache (tentative collisions at
 * the majorant rate, each multiplying T by 1 - sigma_t / majorant) the expected drop per unit
 * length is sigma_t(u) Tc(u), the free-flight density along the camera ray, so p(u) follows
 * sigma_t Tc / dist (the last step, with no drop at its end, gets no mass; the product sampler
 * covers it). Returns m->valid (0: no mass, e.g. Tc == 0 everywhere or a degenerate pair). */
int vbl_vrl_tc_marginal_init(vbl_vrl_tc_marginal* m, const vbl_vrl_pair* p, const vbl_step_pdf* camera, int drops);
/* u in [x_0, x_n] and its density (*pdf may be NULL). */
double vbl_vrl_tc_marginal_sample(const vbl_vrl_tc_marginal* m, double xi, double* pdf);
double vbl_vrl_tc_marginal_pdf(const vbl_vrl_tc_marginal* m, double u);

/* The technique alone: p(u) x p(v | u) (the swapped pair's conditional). */
double vbl_vrl_tc_technique_pdf(const vbl_vrl_pair* p, const vbl_vrl_tc_marginal* m, double u, double v);
/* The MIS mixture c p_product + (1 - c) p_technique at (u, v) (what the draw returns as pdf). */
double vbl_vrl_tc_pair_density(const vbl_vrl_pair* p, const vbl_vrl_tc_marginal* m, double u, double v);
/* xi_choice picks the technique, xi1 and xi2 drive it. m may be invalid (then the product
 * sampler alone, pdf its density). Returns 0 (out->pdf 0) if the draw has no density. */
int vbl_vrl_tc_pair_draw(const vbl_vrl_pair* p, const vbl_vrl_tc_marginal* m, double xi_choice, double xi1,
                         double xi2, vbl_vrl_pair_sample* out);

#ifdef __cplusplus
}
#endif

#endif
