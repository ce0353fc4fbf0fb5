/* pt's scattered directions partly focused on point lights in media (option pt.light_focus = c,
 * issue 14).
 *
 * A ray that passes a point (or spot) light at distance h inside a medium picks up single
 * scattering ~ 1/h on its segment (pt's equiangular NEE, Kulla and Fajardo 2012, sec. 4.1). Under
 * a BRDF's or phase function's bounded density the chance of passing within h is ~ h^2, so the
 * second moment ~ int (1/h)^2 h dh diverges: rare bright samples (fireflies) in every layer whose
 * paths scatter in the smoke around a lamp or leave a wall through it (race_room: 233 pixels of
 * surface_from_volume and 51 of surface_from_surface above 10x the reference; 58 % of
 * volume_from_volume's error in 1 % of the pixels, around the lamp). The camera's vertex has the
 * same singularity and pixel_focus for it; this is the same cure at the path's vertices.
 *
 * With c > 0 a vertex draws its direction from the one-sample mixture
 *   p(w) = (1 - c) p_s(w) + (c / N) sum_i p_i(w)
 * (Veach 1997, sec. 9.2.4, one-sample MIS with the balance heuristic), p_s the BRDF's or the phase
 * function's density and p_i the focus cone about the direction to light i (sampling/focus_cone.h:
 * density ~ 1/angle) with half-angle psi_i = atan(rho / R_i), rho the media box's half-diagonal and
 * R_i the distance to the light; the N lights are the point/spot lights inside the media's box
 * (at a surface vertex, those above its surface). f / p stays bounded as h -> 0, and
 * p >= (1 - c) p_s keeps the estimator unbiased wherever p_s is. Every MIS weight that uses the
 * density of a vertex's scattered direction (light and emission NEEs, lights hit by the scattered
 * ray, the quad lights' equiangular weights) uses p(w) instead.
 *
 * Medium vertices use the mixture up to the VBL_PT_LIGHT_FOCUS_MEDIUM_EVENTS-th scattering event
 * only: the weight p_s / p varies per bounce (up to 1 / (1 - c)), and over the hundreds of bounces
 * of a dense high-albedo medium the product of such weights has a variance that grows
 * geometrically (what volume path guiding ran into, docs/readme/performance.md, session 12). */
#ifndef VBL_TRANSPORT_PT_LIGHT_FOCUS_H
#define VBL_TRANSPORT_PT_LIGHT_FOCUS_H

#include "geometry/surfaces.h"
#include "material/material.h"
#include "media/medium.h"
#include "transport/common/estimator.h"

#define VBL_PT_LIGHT_FOCUS_MAX 16
#define VBL_PT_LIGHT_FOCUS_MEDIUM_EVENTS 4

typedef struct vbl_pt_light_focus {
    double fraction; /* c; 0: off (pt.light_focus 0, or no media or point/spot light in them) */
    double radius;   /* rho, the media box's half-diagonal */
    int count;
    vbl_vec3 light[VBL_PT_LIGHT_FOCUS_MAX];
} vbl_pt_light_focus;

/* From options.pt.light_focus, the scene's media box (vbl_scene_media_box) and its lights; once
 * per render (render.c, vbl_render_context.pt_light_focus). The functions below take NULL as off. */
void vbl_pt_light_focus_init(const vbl_render_context* ctx, vbl_pt_light_focus* lf);

/* ---- surface vertices ---------------------------------------------------------------------- */

/* The mixture's density of wi at the hit (wo towards the previous vertex). */
double vbl_pt_light_focus_surface_pdf(const vbl_pt_light_focus* lf, const vbl_material* m, const vbl_surface_hit* hit,
                                      vbl_vec3 wo, vbl_vec3 wi);

/* Samples wi from the mixture (u0 picks the strategy and the light and is reused, rescaled, by
 * the BRDF; u1, u2 the direction): 1 with *wi, *pdf = p(wi) > 0 and *f = f(wo, wi), or 0. */
int vbl_pt_light_focus_surface_sample(const vbl_pt_light_focus* lf, const vbl_material* m,
                                      const vbl_surface_hit* hit, vbl_vec3 wo, double u0, double u1, double u2,
                                      vbl_vec3* wi, double* pdf, vbl_vec3* f);

/* vbl_surface_pdf_fn form of vbl_pt_light_focus_surface_pdf (data: the vbl_pt_light_focus), for the
 * emission NEE's MIS (transport/common/emission_estimate.h). */
double vbl_pt_light_focus_surface_pdf_fn(const void* data, const vbl_material* m, const vbl_surface_hit* hit,
                                         vbl_vec3 wo, vbl_vec3 wi);

/* ---- medium vertices ----------------------------------------------------------------------- */

/* The mixture at one medium vertex: the focus and the share c it gets there (0: phase sampling). */
typedef struct vbl_pt_light_focus_vertex {
    const vbl_pt_light_focus* focus;
    double c;
} vbl_pt_light_focus_vertex;

/* The mixture at the medium vertex of scattering event `events` (1: the camera-visible vertex). */
vbl_pt_light_focus_vertex vbl_pt_light_focus_at_event(const vbl_pt_light_focus* lf, int events);

/* The mixture's density of wi at medium point x reached travelling along `travel`. */
double vbl_pt_light_focus_medium_pdf(const vbl_pt_light_focus_vertex* v, const vbl_medium_point* mp, vbl_vec3 x,
                                     vbl_vec3 travel, vbl_vec3 wi);

/* Samples wi at x from the mixture (u0 picks the strategy and the light and is reused, rescaled, by
 * the phase sampler; u1, u2 the direction): 1 with *wi and *pdf = p(wi) > 0, or 0. */
int vbl_pt_light_focus_medium_sample(const vbl_pt_light_focus_vertex* v, const vbl_medium_point* mp, vbl_vec3 x,
                                     vbl_vec3 travel, double u0, double u1, double u2, vbl_vec3* wi, double* pdf);

/* vbl_medium_pdf_fn form of vbl_pt_light_focus_medium_pdf (data: a vbl_pt_light_focus_vertex). */
double vbl_pt_light_focus_medium_pdf_fn(const void* data, const vbl_medium_point* mp, vbl_vec3 x, vbl_vec3 travel,
                                        vbl_vec3 wi);

#endif
