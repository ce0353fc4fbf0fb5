/* Product importance sampling of a camera-ray / VRL pair, VRL paper section 4 and appendix A.
 *
 * Camera segment: c_o + u c_d, u in [u0, u1]; VRL segment: l_o + v l_d, v in [v0, v1]; unit
 * directions. The joint density targets eq (15), f_s(theta_u) f_s(theta_v) / w(u, v)^2:
 *   1. v from the inverse-distance marginal to the infinite camera line, eqs (10)-(13)
 *      (sampling/sinh_marginal.h);
 *   2. u given v:
 *      - both g == 0: the truncated Cauchy / equiangular density, eq (14);
 *      - otherwise: a piecewise-linear density in the angle phi about the VRL point (the arc the
 *        camera segment subtends), M = 10 vertices placed as in appendix A, eqs (16)-(20), with
 *        values f_uv(phi) = HG(g_light, l_d . omega) HG(g_camera, -c_d . omega); mapped to u by
 *        u = u_p + D tan(phi), so pdf(u) = pdf(phi) D / dist^2 (dphi/du = D / dist^2).
 * The returned pdf is the joint density in (u, v), the product of the two stages.
 *
 * Phase conventions: at the VRL point light travels along l_d and scatters towards the camera
 * point (direction omega); at the camera point light arriving along omega scatters towards the
 * camera, i.e. along -c_d. Degenerate geometry is handled by construction: parallel lines give
 * the uniform marginal (analytic limit), crossing lines use the relative distance floor
 * VBL_SAMPLING_H_FLOOR_REL (sampling/cauchy.h) in both the sampler and the pdf. */
#ifndef VBL_SAMPLING_VRL_PAIR_H
#define VBL_SAMPLING_VRL_PAIR_H

#include "core/math.h"
#include "core/segment.h"
#include "sampling/sinh_marginal.h"

#ifdef __cplusplus
extern "C" {
#endif

#define VBL_VRL_PAIR_VERTICES 10

typedef struct vbl_vrl_pair_sample {
    double u, v;
    double pdf; /* joint pdf in (u,v) ray-parameter measure */
} vbl_vrl_pair_sample;

/* Geometry prepared once per camera-segment / VRL pair; reusable for many draws. */
typedef struct vbl_vrl_pair {
    vbl_vec3 c_o, c_d, l_o, l_d;
    double u0, u1, v0, v1, g_camera, g_light;
    vbl_sinh_marginal marginal; /* over t = v - v0 */
    int isotropic;
    int valid;
} vbl_vrl_pair;

/* Camera line c_o + u c_d and VRL l_o + v l_d (unit directions): the distance of l(v0 + t) to the
 * camera line is sqrt(h^2 + (beta + s t)^2), s = sin theta (eqs 10-13's geometry). */
void vbl_vrl_line_projection(vbl_vec3 c_o, vbl_vec3 c_d, vbl_vec3 l_o, vbl_vec3 l_d, double v0, double* beta,
                             double* s, double* h);

/* The pair of the camera segment (c_o, c_d, [u0, u1]) and the VRL segment (l_o, l_d, [v0, v1]).
 * Returns 1 if the pair has support (both segments of positive length), 0 otherwise. */
int vbl_vrl_pair_init(vbl_vrl_pair* p, const vbl_segment* camera, const vbl_segment* light, double g_camera,
                      double g_light);
int vbl_vrl_pair_draw(const vbl_vrl_pair* p, double xi1, double xi2, vbl_vrl_pair_sample* out);
double vbl_vrl_pair_density(const vbl_vrl_pair* p, double u, double v);
/* Marginal density of v alone (stage 1) and conditional density of u given v (stage 2). */
double vbl_vrl_pair_marginal_pdf(const vbl_vrl_pair* p, double v);
double vbl_vrl_pair_conditional_pdf(const vbl_vrl_pair* p, double v, double u);

/* Stage 2 alone: u given v (the VRL point) and its density, as inside vbl_vrl_pair_draw (*pdf 0
 * if there is no density). */
double vbl_vrl_pair_draw_conditional(const vbl_vrl_pair* p, double v, double xi, double* pdf);
/* The pair with the roles of the segments exchanged (the VRL as "camera" segment, g values
 * exchanged), for the conditional of v given u: vbl_vrl_pair_conditional_pdf(swapped, u, v) and
 * vbl_vrl_pair_draw_conditional(swapped, u, ...) follow the same two HG lobes, because
 * f_s(theta_u) f_s(theta_v) is symmetric under the exchange (omega -> -omega). Its marginal is
 * invalid: use it for the conditionals only. */
void vbl_vrl_pair_swap(const vbl_vrl_pair* p, vbl_vrl_pair* out);

/* One-call forms. Return 0 / pdf 0 if the pair has no support (e.g. a zero-length segment). */
int vbl_vrl_pair_sample_draw(const vbl_segment* camera, const vbl_segment* light, double g_camera, double g_light,
                             double xi1, double xi2, vbl_vrl_pair_sample* out);
double vbl_vrl_pair_pdf(const vbl_segment* camera, const vbl_segment* light, double g_camera, double g_light,
                        double u, double v);

/* The target of eq (15) without normalisation: f_s(theta_u) f_s(theta_v) / w^2 at (u, v), with the
 * conventions above (0 where w == 0). Used by tests and by estimators that need the integrand. */
double vbl_vrl_pair_phase_geometry(const vbl_vrl_pair* p, double u, double v);

#ifdef __cplusplus
}
#endif

#endif
