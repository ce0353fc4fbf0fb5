/* Sampling a point on a line segment about a fixed point, in the angular domain (VRL paper
 * section 4.3 "VRL to surface": the second stage of section 4.2 with the surface point fixed;
 * VBL paper sections 3.1 and 3.3): the shared sampler of the surface transports.
 *
 * Segment o + t d, t in [t0, t1], d unit; centre q (the surface point for surface_from_volume,
 * the VSL for volume_from_surface). With tp the parameter of q's projection on the line, D the
 * distance of q to the line and h = hypot(max(D, floor), R) (floor VBL_SAMPLING_H_FLOOR_REL x the
 * segment's scale, as sampling/cauchy.h; R the VSL radius, 0 for VRLs) the segment is mapped to
 *     t = tp + h tan(phi),  phi in [phi0, phi1],  dphi/dt = h / (h^2 + (t - tp)^2),
 * so a density uniform in phi is the equiangular / truncated Cauchy density (VRL eq 14), and with
 * R > 0 it targets the softened 1 / (w^2 + R^2) of the VSL kernels (sampling/beam_light_pair.h).
 *
 * Product-aware part: vbl_surface_line_fit evaluates a caller's target (the integrand without its
 * 1/w^2, i.e. in angular measure) at VBL_SURFACE_LINE_VERTICES angles (endpoints, caller hints
 * such as a BRDF peak or a horizon crossing, and a uniform fill) and builds a piecewise-linear
 * density in phi (sampling/piecewise_linear.h). The density sampled is the defensive mixture
 *     p(phi) = eps / (phi1 - phi0) + (1 - eps) pwl(phi),  eps = VBL_SURFACE_LINE_DEFENSIVE,
 * so every point of the segment keeps a positive density (unbiased for any target, whatever the
 * fit misses); without a fit eps = 1 (pure equiangular). pdf(t) = p(phi(t)) h / (h^2 + (t-tp)^2). */
#ifndef VBL_TRANSPORT_SURFACE_LINE_SAMPLER_H
#define VBL_TRANSPORT_SURFACE_LINE_SAMPLER_H

#include "core/math.h"
#include "sampling/piecewise_linear.h"

#define VBL_SURFACE_LINE_VERTICES 16
#define VBL_SURFACE_LINE_DEFENSIVE 0.1
#define VBL_SURFACE_LINE_MAX_HINTS 6

typedef struct vbl_surface_line_sampler {
    vbl_vec3 o, d, q;
    double t0, t1;
    double tp;          /* projection of q on the line */
    double dist;        /* true distance of q to the line */
    double h;           /* mapping scale hypot(max(dist, floor), R) */
    vbl_vec3 a;         /* unit, from the line towards q (any perpendicular when dist == 0) */
    double phi0, phi1;
    double defensive;   /* eps: 1 before a fit */
    vbl_pwl pwl;
    int valid;
} vbl_surface_line_sampler;

/* Value of the sampling target at a point of the line (angular measure, >= 0). */
typedef double (*vbl_surface_line_target_fn)(void* ctx, vbl_vec3 point);

/* Returns 1 if the segment has support (t1 > t0, finite input, d unit). Equiangular until fitted. */
int vbl_surface_line_init(vbl_surface_line_sampler* s, vbl_vec3 o, vbl_vec3 d, double t0, double t1, vbl_vec3 q,
                          double radius);
/* Angle phi in [phi0, phi1] of the line point whose direction from q, (p - q) / |p - q|, is
 * closest to unit `dir`; returns 0 (no hint) when q lies on the line. */
int vbl_surface_line_angle_toward(const vbl_surface_line_sampler* s, vbl_vec3 dir, double* phi);
/* Angle where the direction from q crosses the plane n . w = 0 (a horizon); 0 if it does not
 * inside the segment. */
int vbl_surface_line_angle_horizon(const vbl_surface_line_sampler* s, vbl_vec3 n, double* phi);
/* Builds the product-aware density from `target` at the endpoints, up to
 * VBL_SURFACE_LINE_MAX_HINTS hint angles (clamped into [phi0, phi1]) and a uniform fill. */
void vbl_surface_line_fit(vbl_surface_line_sampler* s, const double* hints, int hint_count,
                          vbl_surface_line_target_fn target, void* ctx);
/* Samples t in [t0, t1]; *pdf (per unit t, may be NULL) > 0 for a valid sampler. */
double vbl_surface_line_sample(const vbl_surface_line_sampler* s, double xi, double* pdf);
double vbl_surface_line_pdf(const vbl_surface_line_sampler* s, double t);
/* The point o + t d. */
vbl_vec3 vbl_surface_line_point(const vbl_surface_line_sampler* s, double t);

#endif
