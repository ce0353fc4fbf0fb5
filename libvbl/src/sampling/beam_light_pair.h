/* Virtual beam lights, media-to-media (Novak et al. 2012 (VBL), section 3.2, eq. 10): the two-stage
 * sampler of a camera-segment x VRL pair whose points are inflated into volumetric VSLs of
 * radius R, and the VSL contribution kernel that replaces the VRL's f_s f_s / w^2.
 *
 * Camera segment: c_o + u c_d, u in [u0, u1]; VRL: l_o + v l_d, v in [v0, v1]; unit directions.
 * Phase conventions as in sampling/vrl_pair.h: light travels along l_d, scatters at the VSL
 * towards the camera point (light-travel direction omega), and scatters there towards the camera
 * (along -c_d): f_l = HG(g_light, l_d . omega), f_c = HG(g_camera, -c_d . omega).
 *
 * Sampling target. The kernel (below) behaves like f_s f_s / w^2 for w >> R and is bounded by
 * ~2 max(f_s f_s) / R^2 for w <= R, so both stages target the softened inverse squared distance
 * 1 / (w^2 + R^2) (R = 0: exactly the VRL sampler's 1 / w^2):
 *   stage 1 (VSL location v): the marginal of 1 / (w^2 + R^2) over the INFINITE camera line,
 *       integral_R du / (w(u, v)^2 + R^2) = pi / sqrt(h(v)^2 + R^2),
 *     h(v) the distance of l(v) to the camera line, i.e. VRL eq (10) with h^2 -> h^2 + R^2:
 *     sampling/sinh_marginal.h with its closest-approach distance h replaced by hypot(h, R)
 *     (eqs 11-13 unchanged; the floor on h is no longer needed once R > 0);
 *   stage 2 (camera point u given v): a piecewise-linear density (sampling/piecewise_linear.h,
 *     VBL_BEAM_LIGHT_PAIR_VERTICES vertices) in the angle phi about the VSL, u = u_p + D' tan(phi),
 *     D' = hypot(D, R) (D the distance of the VSL centre to the camera line, floored as in the VRL
 *     sampler when R == 0), so pdf(u) = pdf(phi) D' / (D'^2 + (u - u_p)^2) ~ 1 / (w^2 + R^2).
 *     Vertex values: f_l f_c at the best of the cone's axis and the least-rotation directions to
 *     the two lobe peaks (sampling/vsl_cone.h, section 3.1's omega'_max rule; the axis alone for
 *     cones thinner than VBL_BEAM_LIGHT_PAIR_THIN); vertices
 *     cosine-warped (VRL appendix eq 19) with one moved onto the light lobe's peak on the arc.
 * The returned pdf is the joint density in (u, v); it is exactly what vbl_beam_light_pair_density gives.
 * Degenerate geometry: parallel lines give the uniform stage-1 limit, crossing lines are smooth
 * (R > 0), R = 0 reproduces the VRL sampler's targets.
 * Isotropic media (both g exactly 0) take the analytic path: the vertex values are all
 * 1 / (4 pi)^2, so the piecewise-linear density is uniform in phi (a Cauchy / equiangular density
 * in u about the VSL, as the VRL sampler's isotropic case) and is used directly, and the kernel
 * is geometry / (4 pi)^2 without quadrature: the same densities and values as the general path
 * (tested), without the 12 cone maxima and the 16-48 kernel directions. */
#ifndef VBL_SAMPLING_VBL_PAIR_H
#define VBL_SAMPLING_VBL_PAIR_H

#include "core/math.h"
#include "sampling/sinh_marginal.h"

#ifdef __cplusplus
extern "C" {
#endif

#define VBL_BEAM_LIGHT_PAIR_VERTICES 12
/* Stage-2 vertex values take the axis value where R <= this x the distance (beam_light_pair.c). */
#define VBL_BEAM_LIGHT_PAIR_THIN 0.02

typedef struct vbl_beam_light_pair_sample {
    double u, v;
    double pdf; /* joint pdf in (u, v) ray-parameter measure */
} vbl_beam_light_pair_sample;

typedef struct vbl_beam_light_pair {
    vbl_vec3 c_o, c_d, l_o, l_d;
    double u0, u1, v0, v1, g_camera, g_light, radius;
    vbl_sinh_marginal marginal; /* over t = v - v0, h -> hypot(h, R) */
    int valid;
    int isotropic; /* g_camera == g_light == 0: constant stage-2 target, stage 2 uniform in phi */
} vbl_beam_light_pair;

/* Returns 1 if the pair has support (both segments of positive length, radius >= 0 finite). */
int vbl_beam_light_pair_init(vbl_beam_light_pair* p, vbl_vec3 c_o, vbl_vec3 c_d, double u0, double u1, vbl_vec3 l_o,
                      vbl_vec3 l_d, double v0, double v1, double g_camera, double g_light, double radius);
/* xi1 picks v (stage 1), xi2 picks u (stage 2). Returns 0 (pdf 0) without support. */
int vbl_beam_light_pair_draw(const vbl_beam_light_pair* p, double xi1, double xi2, vbl_beam_light_pair_sample* out);
double vbl_beam_light_pair_density(const vbl_beam_light_pair* p, double u, double v);
double vbl_beam_light_pair_marginal_pdf(const vbl_beam_light_pair* p, double v);
double vbl_beam_light_pair_conditional_pdf(const vbl_beam_light_pair* p, double v, double u);

/* ---- The VSL contribution kernel ----
 * K_R(x_c, x_l) = 1/(pi R^2) * integral over omega in Omega_vsl of
 *                 HG(g_light, l_d . omega) HG(g_camera, -c_d . omega) d omega,
 * i.e. L^vsl_m(u, v) / Phi of eq (10): eq (9) with two phase functions, the beam radiance
 * estimate (figure 5 left) of a VSL of radius R centred at x_l gathered from the camera point
 * x_c; Omega_vsl is the cone of sampling/vsl_cone.h (half-angle asin(min(1, R / w)), the
 * hemisphere for w <= R). Properties: -> f_l f_c / w^2 (the VRL integrand) as R / w -> 0; bounded
 * by 2 max(f_l f_c) / R^2 for every w (finite as w -> 0); R == 0 returns f_l f_c / w^2 exactly
 * (0 at w == 0). The eq-(10) estimator of one pair sample is
 *   Phi sigma_s(u) sigma_s(v) T(u) T(v) T(u, v) V K_R(x_c(u), x_l(v)) / pdf(u, v).
 *
 * Numerical integration over the solid angle: `n` directions per strategy from a rank-1
 * (Fibonacci) lattice rotated by (jitter1, jitter2) in [0,1)^2, combined with the balance
 * heuristic over up to three strategies: uniform in the cone; the light lobe HG(g_light) and the
 * camera lobe HG(g_camera), each used only when |g| >= 0.2 and a lobe sample can land in the
 * cone with probability >= ~1% (solid angle x the lobe's maximum in the cone); lobe samples
 * outside the cone contribute 0. For uniformly random jitter the result is an unbiased estimate
 * of K_R; a fixed jitter gives a deterministic quadrature (used by tests). n < 1 is read as 1;
 * n = 16..64 suffices for g up to ~0.9 (the paper uses up to 100). */
double vbl_vsl_kernel(vbl_vec3 x_c, vbl_vec3 c_d, double g_camera, vbl_vec3 x_l, vbl_vec3 l_d, double g_light,
                      double radius, int n, double jitter1, double jitter2);

/* ---- The thin-cone shortcut of K_R (issue 13 item 4) ----
 * For a cone of half-angle alpha about the axis a = (x_c - x_l) / w, K_R = geometry x the mean of
 * F = f_l f_c over the cone (uniform), and the midpoint value geometry x F(a) is the VRL kernel
 * with the BRE's softened geometry (sampling/vsl_cone.h). Along a unit-speed geodesic from a
 * (angle theta <= alpha, stays in the cone): F(theta) = F(0) + theta F'(0) + theta^2 F''(xi) / 2;
 * the linear term averages to 0 over the cone's azimuth, |F''| <= C F and F(xi) <= F(a) e^(alpha B1), so
 *   |mean F / F(a) - 1| <= alpha^2 / 2 x (B2 + B1^2) x e^(alpha B1),
 * with B1 >= |(ln F)'| and B2 + B1^2 >= F'' / F in the cone. For F = A B, A and B positive mixtures
 * of HG lobes (sum_i w_i f_i: |A'| / A <= max_i |f_i'| / f_i, A'' / A <= max_i f_i'' / f_i), B1 and B2 are
 * the sums over the two ends of each end's largest lobe bound. One lobe, c = m . omega,
 * q = 1 + g^2 - 2 g c, h = ln HG: h' = 3 g (m . omega') / q, h'' = 6 g^2 (m . omega')^2 / q^2 - 3 g c / q, so
 *   |h'| <= 3 |g| sqrt(1 - c^2) / q <= 3 |g| / (1 - g^2),
 *   |h''| <= 6 g^2 (1 - c^2) / q^2 + 3 |g| |c| / q <= (1.5 |g| + 3 |g|) / (1 - |g|)^2 (2x / q^2 <= 1 / (4 |g| (1 - |g|)^2)),
 * and, over the cone only, with x = 1 - cos(angle to the peak sign(g) m), q = (1 - |g|)^2 + 2 |g| x,
 * 1 - c^2 <= 2 x: sqrt(2x) / q and 2x / q^2 peak at x* = (1 - |g|)^2 / (2 |g|), so the local bounds take
 * x* clamped to the cone's x range (vbl_vsl_lobe_local_bounds). The bound is on the exact kernel,
 * so the shortcut's relative error is below it for every geometry, and it -> 0 like (R / w)^2, the
 * order of the VBL's own bias. */
double vbl_vsl_lobe_slope_bound(double g);     /* 3 |g| / (1 - g^2): |h'| anywhere */
double vbl_vsl_lobe_curvature_bound(double g); /* 4.5 |g| / (1 - |g|)^2 >= |h''| anywhere (see above) */
/* Local b1 >= |h'|, b2 >= |h''| of one lobe over a cone of half-angle alpha (sin_a, cos_a) whose axis
 * has cosine c with the lobe's direction m (HG(g, m . omega)). */
void vbl_vsl_lobe_local_bounds(double g, double c, double sin_a, double cos_a, double* b1, double* b2);
/* The relative-error bound above for half-angle alpha and summed bounds b1, b2. */
double vbl_vsl_midpoint_error_bound(double alpha, double b1, double b2);
/* sin of the largest half-angle whose bound with the global lobe bounds is <= tolerance (bisection),
 * for two lobes of |g| <= g_max; 0 when tolerance <= 0 (never skip) or g_max >= 1. */
double vbl_vsl_thin_cone_sin(double g_max, double tolerance);
/* K_R by the midpoint where R <= thin_sin x w (R == 0: the VRL integrand), else vbl_vsl_kernel. */
double vbl_vsl_kernel_adaptive(vbl_vec3 x_c, vbl_vec3 c_d, double g_camera, vbl_vec3 x_l, vbl_vec3 l_d, double g_light,
                               double radius, int n, double jitter1, double jitter2, double thin_sin);

/* The sampling target of stage 2 at (u, v) without normalisation (tests, diagnostics):
 * max-in-cone phase product / (w^2 + R^2). */
double vbl_beam_light_pair_target(const vbl_beam_light_pair* p, double u, double v);

#ifdef __cplusplus
}
#endif

#endif
