/* The cone of directions subtended by a volumetric VSL (Novak et al. 2012 (VBL), section 3.1,
 * figure 5 right): a sphere of radius R centred at c, seen from a point x.
 *
 * Directions are LIGHT-TRAVEL directions omega (from the VSL towards x), the convention of
 * sampling/vrl_pair.h: the gather ray leaves x along -omega. Following the beam radiance estimate
 * the VSL is a disc of radius R facing the gather direction, so the gather ray hits it iff the
 * centre lies ahead of x within distance R of the ray; the set of such omega is the cone about
 * axis a = (x - c) / w, w = |x - c|, with half-angle alpha = asin(min(1, R / w)). For w <= R it
 * is the hemisphere about a (continuous at w = R); the solid angle is 2 pi (1 - cos alpha).
 *
 * R == 0 is the VRL limit (a single direction, no solid angle); w == 0 takes `fallback_axis`. */
#ifndef VBL_SAMPLING_VSL_CONE_H
#define VBL_SAMPLING_VSL_CONE_H

#include "core/math.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct vbl_vsl_cone {
    vbl_vec3 axis;        /* unit, (x - c) / w */
    double w, radius;     /* distance of x from the centre, VSL radius */
    double sin_half, cos_half, half_angle;
    double one_minus_cos; /* 1 - cos alpha without cancellation (sin^2 / (1 + cos)) */
    double solid_angle;   /* 2 pi (1 - cos alpha) */
    /* solid_angle / (pi R^2) = 2 / (max(w, R)^2 (1 + cos alpha)): the BRE's 1/(pi R^2) times the
     * cone's solid angle, -> 1/w^2 for w >> R, 2/R^2 for w <= R; 1/w^2 when R == 0 (0 if w == 0). */
    double geometry;
    int valid;            /* 0: R == 0 and w == 0 (no direction defined) */
} vbl_vsl_cone;

/* d = x - c. radius < 0 or non-finite is read as 0. Returns c->valid. */
int vbl_vsl_cone_init(vbl_vsl_cone* c, vbl_vec3 d, double radius, vbl_vec3 fallback_axis);

/* 1 if unit `dir` lies in the cone (angle to the axis <= half-angle, compared as angles). */
int vbl_vsl_cone_contains(const vbl_vsl_cone* c, vbl_vec3 dir);

/* The direction of the cone with least rotation to unit `target` (figure 5: omega'_max from
 * omega_max): `target` itself when inside, else the axis rotated towards it by the half-angle.
 * target == -axis: a fixed boundary direction (every boundary direction is equally close). */
vbl_vec3 vbl_vsl_cone_closest(const vbl_vsl_cone* c, vbl_vec3 target);

/* Maximum over omega in the cone of HG(g, m . omega) (m unit), exact: HG is monotone in the
 * cosine, so the maximiser is the least-rotation direction to sign(g) m (the axis if g == 0).
 * *argmax may be NULL. */
double vbl_vsl_cone_hg_max(const vbl_vsl_cone* c, double g, vbl_vec3 m, vbl_vec3* argmax);

/* Maximum over the cone of HG(g1, m1 . omega) HG(g2, m2 . omega), the section 3.1/3.2 PDF-vertex
 * value. Evaluated at the least-rotation directions to the two lobe peaks (the paper's
 * omega'_max), the axis, and (cones wider than 0.02 rad) 15 points on the geodesic between the two least-rotation
 * directions (inside the cone: a cap of half-angle <= pi/2 is geodesically convex), where the
 * product's maximum lies when the cone contains or nearly contains the arc between the peaks.
 * Exact when a lobe is isotropic; otherwise a close LOWER estimate of the maximum (tested
 * against brute force). Always > 0 for |g| < 1. *argmax may be NULL. */
double vbl_vsl_cone_hg_product_max(const vbl_vsl_cone* c, double g1, vbl_vec3 m1, double g2, vbl_vec3 m2,
                                   vbl_vec3* argmax);

/* Uniform direction in the cone, precise for thin cones (1 - cos sampled directly);
 * *pdf = 1 / solid_angle (0 when the cone has no solid angle: then the axis is returned). */
vbl_vec3 vbl_vsl_cone_sample(const vbl_vsl_cone* c, double u1, double u2, double* pdf);
double vbl_vsl_cone_pdf(const vbl_vsl_cone* c, vbl_vec3 dir);

#ifdef __cplusplus
}
#endif

#endif
