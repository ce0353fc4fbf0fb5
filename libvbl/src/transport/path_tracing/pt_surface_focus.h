/* pt's scattered directions at surface vertices, partly focused on point lights in media (option
 * pt.surface_focus = c, issue 14).
 *
 * A ray leaving a surface that passes a point (or spot) light at distance h inside a medium picks
 * up single scattering ~ 1/h on its segment (pt's equiangular NEE, Kulla and Fajardo 2012, sec.
 * 4.1). Under the BRDF's bounded density the chance of passing within h is ~ h^2, so the second
 * moment ~ int (1/h)^2 h dh diverges: rare bright samples (fireflies) in every layer whose paths
 * leave a surface through the smoke around a lamp (race_room: 233 pixels of surface_from_volume
 * and 51 of surface_from_surface above 10x the reference). The camera's vertex has the same
 * singularity and pixel_focus for it; this is the same cure at surface vertices.
 *
 * With c > 0 a surface vertex draws its direction from the one-sample mixture
 *   p(w) = (1 - c) p_brdf(w) + (c / N) sum_i p_i(w)
 * (Veach 1997, sec. 9.2.4, one-sample MIS with the balance heuristic), over the N point/spot
 * lights inside the media's box that lie above the vertex's surface (N = 0: the BRDF alone), p_i
 * the focus cone about the direction to light i (sampling/focus_cone.h: density ~ 1/angle) with
 * half-angle psi_i = atan(rho / R_i), rho the media box's half-diagonal and R_i the distance to the
 * light. f cos / p stays bounded as h -> 0, and p >= (1 - c) p_brdf keeps the estimator unbiased
 * wherever the BRDF is. Every MIS weight that uses the density of a surface vertex's direction
 * (the light and emission NEEs, lights hit by the scattered ray) uses p(w) instead. */
#ifndef VBL_TRANSPORT_PT_SURFACE_FOCUS_H
#define VBL_TRANSPORT_PT_SURFACE_FOCUS_H

#include "geometry/surfaces.h"
#include "material/material.h"
#include "transport/common/estimator.h"

#define VBL_PT_SURFACE_FOCUS_MAX 16

typedef struct vbl_pt_surface_focus {
    double fraction; /* c; 0: BRDF sampling only (pt.surface_focus 0, no surfaces, media or lights in them) */
    double radius;   /* rho, the media box's half-diagonal */
    int count;
    vbl_vec3 light[VBL_PT_SURFACE_FOCUS_MAX];
} vbl_pt_surface_focus;

/* From options.pt.surface_focus, the scene's media box (vbl_scene_media_box) and its lights. */
void vbl_pt_surface_focus_init(const vbl_render_context* ctx, vbl_pt_surface_focus* sf);

/* The mixture's density of wi at the hit (wo towards the previous vertex). */
double vbl_pt_surface_focus_pdf(const vbl_pt_surface_focus* sf, const vbl_material* m, const vbl_surface_hit* hit,
                                vbl_vec3 wo, vbl_vec3 wi);

/* Samples wi from the mixture (u0 picks the strategy and the light and is reused, rescaled, by
 * the BRDF; u1, u2 the direction): 1 with *wi, *pdf = p(wi) > 0 and *f = f(wo, wi), or 0. */
int vbl_pt_surface_focus_sample(const vbl_pt_surface_focus* sf, const vbl_material* m, const vbl_surface_hit* hit,
                                vbl_vec3 wo, double u0, double u1, double u2, vbl_vec3* wi, double* pdf,
                                vbl_vec3* f);

/* vbl_surface_pdf_fn form of vbl_pt_surface_focus_pdf (data: the vbl_pt_surface_focus), for the
 * emission NEE's MIS (transport/common/emission_estimate.h). */
double vbl_pt_surface_focus_pdf_fn(const void* data, const vbl_material* m, const vbl_surface_hit* hit, vbl_vec3 wo,
                                   vbl_vec3 wi);

#endif
