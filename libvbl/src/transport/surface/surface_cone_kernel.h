/* The VSL gather kernel of the surface transports (Novak et al. 2012 (VBL), section 3.1, eq. 9;
 * Hasan et al.'s virtual spherical lights for surface-to-surface, VBL section 3.4):
 *     K_R(x, c) = 1 / (pi R^2) * integral over omega in Omega_vsl of A(omega) B(omega) d omega,
 * Omega_vsl the cone of sampling/vsl_cone.h (the VSL of radius R centred at c seen from the
 * receiver x, half-angle asin(min(1, R / w)), the hemisphere for w <= R), omega the LIGHT-TRAVEL
 * direction (from the VSL towards x). A is the receiver's lobe, B the sender's: each one of
 *   - PHASE:    HG(g, m . omega)   (sender VRL point: m = VRL direction; receiver camera point:
 *                                    m = -camera direction);
 *   - RECEIVER: f(w, -omega) max(0, n . -omega)   (surface point x seen along w = wo; the light
 *                                    arrives from wi = -omega; f from material/material.h);
 *   - SENDER:   f(omega, w) max(0, n . omega)     (surface VSL: light arrived from w = wi, the
 *                                    photon's incident direction, and leaves along omega).
 * Properties: -> A B / w^2 (the singular VRL/VPL integrand) as R / w -> 0; bounded by
 * 2 max_cone(A B) / R^2 for every w (finite as w -> 0); R == 0 returns A B / w^2 exactly along
 * the axis (0 at w == 0).
 *
 * Integration over the cone: `n` directions per strategy from a randomly shifted rank-1 lattice
 * (shift = jitter[0..2] in [0,1)^3), balance heuristic over up to three strategies: uniform in
 * the cone, lobe A sampling, lobe B sampling (a lobe is used when its maximum in the cone times
 * the cone's solid angle is >= 0.01, the chance a lobe sample lands in the cone; PHASE lobes also
 * need |g| >= 0.2; lobe samples outside the cone contribute 0). For uniformly random jitter the
 * result is an UNBIASED estimate of K_R (the estimators draw the jitter from their rng); a fixed
 * jitter gives a deterministic quadrature (tests). n < 1 is read as 1; 8..32 suffice for the
 * materials of the papers (Phong 60..100, GGX >= 0.1). */
#ifndef VBL_TRANSPORT_SURFACE_CONE_KERNEL_H
#define VBL_TRANSPORT_SURFACE_CONE_KERNEL_H

#include "core/math.h"
#include "material/material.h"
#include "sampling/vsl_cone.h"

typedef enum vbl_surface_lobe_kind {
    VBL_SURFACE_LOBE_PHASE = 0,
    VBL_SURFACE_LOBE_RECEIVER = 1,
    VBL_SURFACE_LOBE_SENDER = 2
} vbl_surface_lobe_kind;

typedef struct vbl_surface_lobe {
    vbl_surface_lobe_kind kind;
    double g;                     /* PHASE */
    vbl_vec3 m;                   /* PHASE: unit */
    const vbl_material* material; /* RECEIVER / SENDER */
    vbl_vec3 n, w;                /* RECEIVER / SENDER: unit normal, fixed unit direction */
} vbl_surface_lobe;

vbl_surface_lobe vbl_surface_lobe_phase(double g, vbl_vec3 m);
vbl_surface_lobe vbl_surface_lobe_receiver(const vbl_material* material, vbl_vec3 n, vbl_vec3 wo);
vbl_surface_lobe vbl_surface_lobe_sender(const vbl_material* material, vbl_vec3 n, vbl_vec3 wi);

/* A(omega) per channel (PHASE: grey). */
vbl_vec3 vbl_surface_lobe_eval(const vbl_surface_lobe* l, vbl_vec3 omega);
/* Channel mean of an upper bound of the lobe over the cone (PHASE: exact HG maximum,
 * vsl_cone.h; materials: vbl_material_max_in_cone; R == 0: the value on the axis). */
double vbl_surface_lobe_max_in_cone(const vbl_surface_lobe* l, const vbl_vsl_cone* cone);
/* Density (solid angle of omega) of vbl_surface_lobe_sample. */
double vbl_surface_lobe_pdf(const vbl_surface_lobe* l, vbl_vec3 omega);
/* Samples omega from the lobe's own sampling routine; returns 0 when no direction was drawn. */
int vbl_surface_lobe_sample(const vbl_surface_lobe* l, double u0, double u1, double u2, vbl_vec3* omega,
                            double* pdf);

/* K_R(x, c) (per channel) for the receiver lobe `a` at x and the sender lobe `b` at c. */
vbl_vec3 vbl_surface_cone_kernel(const vbl_surface_lobe* a, const vbl_surface_lobe* b, vbl_vec3 x, vbl_vec3 c,
                                 double radius, int n, const double jitter[3]);

#endif
