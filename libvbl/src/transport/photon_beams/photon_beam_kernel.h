/* Photon beams, beam x beam 1D radiance estimate (Jarosz et al. 2011a, section 7.3, eq. 38,
 * biweight kernel of section 8.2):
 *     L(x_c <- omega_c) ~= sigma_s(x) f(theta_b) Phi_b T_b(t_b) T_c(t_c) K_r(d) / sin(theta_b),
 * camera ray c(u) = c_o + u c_d, u in [0, len_c]; photon beam b(t) = b_o + t b_d, t in
 * [0, len_b] carrying power Phi_b; d the distance between the two lines, t_c / t_b the
 * parameters of their closest points, theta_b the angle between the lines, and
 * K_r(d) = K(d / r) / r with the 1D biweight K(x) = 15/16 (1 - x^2)^2 on |x| <= 1 (integrates to
 * 1; r is the beam's half-width). Phase convention: light travels along b_d and scatters towards
 * the camera (along -c_d), cos = b_d . (-c_d) (see vbl_photon_beam_eval's cos_scatter).
 *
 * The parallel case, handled by construction. Eq 38 is the limit of a 2D kernel in the beam's
 * cross-section, K_r(y_n) times a delta in y_m, where n = b_d x c_d / |b_d x c_d| is
 * perpendicular to both lines and m the direction the camera ray crosses the beam (the camera
 * ray's offset from the beam line moves along m only, at rate sin theta, with y_n = +-d fixed).
 * Integrating the delta along the camera ray gives 1 / sin theta, which diverges as the lines
 * become parallel, while the closest points run off to infinity. libvbl replaces the delta by a
 * box of the same half-width r (normalised, 1/(2r)), so the weight is
 *     K_r(y_n) * |U| / (2 r),
 * U = {u in [0, len_c] : |y_m(u)| <= r and the beam parameter of c(u) lies in [0, len_b]}
 * (two linear constraints on u, solved without dividing by sin theta), and the transmittances
 * are taken at the midpoint of U and its projection on the beam. When U is not clipped by the
 * segment ends, |U| = 2 r / sin theta and the midpoint is the closest point: eq 38 exactly.
 * Near-parallel and parallel lines (exactly parallel: m taken along the offset, y_n = 0) get
 * |U| <= min(len_c, len_b / |cos theta|) and so a weight <= K(0) len_c / (2 r^2): finite; the
 * kernel is still a normalised 2D cross-section kernel, so the estimate stays consistent as r -> 0.
 * The width reduction of progressive photon beams is transport/common/radius_schedule.h with dim = 1. */
#ifndef VBL_TRANSPORT_PHOTON_BEAM_KERNEL_H
#define VBL_TRANSPORT_PHOTON_BEAM_KERNEL_H

#include "core/math.h"
#include "core/segment.h"

#ifdef __cplusplus
extern "C" {
#endif

/* 1D biweight K(x) = 15/16 (1 - x^2)^2 for |x| <= 1, else 0. */
double vbl_biweight_1d(double x);

typedef struct vbl_photon_beam_eval_result {
    double weight;      /* K_r(d) / sin(theta) (eq 38), or the clipped form above; 0: no contribution */
    double t_c, t_b;    /* where to evaluate T_c (along the camera ray) and T_b (along the beam) */
    double cos_scatter; /* b_d . (-c_d): cosine for the phase function f(theta_b) */
    double sin_theta;   /* |b_d x c_d| */
    double distance;    /* |y_n|: the perpendicular distance entering the kernel */
} vbl_photon_beam_eval_result;

/* Unit c_d, b_d; r > 0. Returns 1 and fills *out when the weight is > 0, else 0 (weight 0). */
int vbl_photon_beam_eval(vbl_vec3 c_o, vbl_vec3 c_d, double len_c, vbl_vec3 b_o, vbl_vec3 b_d, double len_b, double r,
                         vbl_photon_beam_eval_result* out);

/* Transmittance from `origin` along unit `dir` over distance t (caller's medium). */
typedef double (*vbl_beam_transmittance_fn)(void* ctx, vbl_vec3 origin, vbl_vec3 dir, double t);

/* The full eq-38 term for the camera segment and the beam segment (each from its start point,
 * origin + t0 direction, over t1 - t0): sigma_s * phase(cos_scatter) * power * T_b(t_b) * T_c(t_c)
 * * weight, with phase = HG(g); T from each segment's start point. transmittance may be NULL
 * (T = 1). Returns 0 when the beam does not contribute. */
double vbl_photon_beam_estimate(const vbl_segment* camera, const vbl_segment* beam, double r, double power,
                                double sigma_s, double g, vbl_beam_transmittance_fn transmittance, void* ctx);

#ifdef __cplusplus
}
#endif

#endif
