/* Estimators of the light emissive media send (docs/readme/emission.md), shared by pt and the
 * camera side of the virtual-light and beam methods:
 *   - the null-collision emission estimator along a free flight: at every tentative collision
 *     (null or real) add beta sigma_a Le / mu, mu the majorant the point was drawn with, an
 *     unbiased estimate of int T sigma_a Le dt along the segment up to the first real collision
 *     (Pharr, Jakob and Humphreys 2023, pbrt-v4, sec. 14.2);
 *   - light sampling of the emissive media at a medium or surface vertex: a direction from the
 *     block cone mixture of scene->emission_lights, the emission along it by one collecting
 *     tracking ray, combined with phase/BRDF sampling by the scene's MIS heuristic unless the
 *     vertex is the path's last (weight 1).
 * The camera-side estimator (vbl_camera_media_emission) is pt's first vertex: the camera ray's
 * own emission (volume_emission) and, at its first real collision or surface, emission light
 * sampling MIS-combined with one phase/BRDF-sampled direction whose collected emission gets the
 * complementary weight (volume_direct, surface_direct), the light that scattered once; the
 * photons the media emit (light_emission.h) carry everything that scattered more often. */
#ifndef VBL_TRANSPORT_EMISSION_ESTIMATE_H
#define VBL_TRANSPORT_EMISSION_ESTIMATE_H

#include "geometry/surfaces.h"
#include "material/material.h"
#include "media/medium.h"
#include "transport/common/estimator.h"

/* Visitor state of the emission estimator along one free flight (vbl_tracking_visit user). */
typedef struct vbl_emission_visit_state {
    const vbl_scene* scene;
    vbl_emission_cursor* cursor;
    vbl_vec3 beta; /* throughput times MIS weight */
    vbl_vec3* L;   /* where beta sigma_a Le / mu goes */
} vbl_emission_visit_state;

void vbl_emission_visit(void* user, vbl_vec3 p, double mu, const double* per_component);

/* Emission arriving at a vertex along unit wi from `origin` (one tracking ray up to the first
 * surface or real collision), times beta into *L. */
void vbl_emission_collect(const vbl_render_context* ctx, vbl_thread_state* ts, vbl_vec3 origin, vbl_vec3 wi,
                          vbl_vec3 beta, vbl_rng* rng, vbl_vec3* L);

/* The density of the direction wi that the path's own sampling at medium point x (reached
 * travelling along `travel`) would draw, for the MIS weight against light sampling; data is the
 * caller's. */
typedef double (*vbl_medium_pdf_fn)(const void* data, const vbl_medium_point* mp, vbl_vec3 x, vbl_vec3 travel,
                                    vbl_vec3 wi);

/* Light sampling of the emissive media at medium vertex x (reached travelling along `travel`,
 * sigma_t and mp there): three uniforms, then the collecting ray; beta kernel / (pdf sigma_t)
 * times the MIS weight (1 when `last`) against dir_pdf(dir_pdf_data, ...) (NULL: phase sampling,
 * vbl_medium_phase_pdf) into *L. */
void vbl_emission_nee_medium(const vbl_render_context* ctx, vbl_thread_state* ts, vbl_vec3 x, vbl_vec3 travel,
                             double sigma_t, const vbl_medium_point* mp, int last, vbl_medium_pdf_fn dir_pdf,
                             const void* dir_pdf_data, vbl_vec3 beta, vbl_rng* rng, vbl_vec3* L);
/* The density of the direction wi that the path's own sampling at a surface hit would draw (for
 * the MIS weight against light sampling); data is the caller's. */
typedef double (*vbl_surface_pdf_fn)(const void* data, const vbl_material* m, const vbl_surface_hit* hit, vbl_vec3 wo,
                                     vbl_vec3 wi);
/* The same at a surface vertex (wo towards the previous vertex): beta f cos / pdf, MIS against
 * dir_pdf(dir_pdf_data, ...) (NULL: the material's BRDF sampling, vbl_material_pdf). */
void vbl_emission_nee_surface(const vbl_render_context* ctx, vbl_thread_state* ts, const vbl_surface_hit* hit,
                              vbl_vec3 wo, int last, vbl_surface_pdf_fn dir_pdf, const void* dir_pdf_data,
                              vbl_vec3 beta, vbl_rng* rng, vbl_vec3* L);

/* What vbl_camera_media_emission adds besides volume_emission (bits). */
#define VBL_EMISSION_DIRECT_VOLUME 1  /* volume_direct: light sampling at the first real collision */
#define VBL_EMISSION_DIRECT_SURFACE 2 /* surface_direct: light sampling at the surface the ray reaches */

/* The camera ray's share of the media's emission (nothing without scene->has_emission): one
 * free flight to sample->t_max collecting the emission seen directly into volume_emission, then
 * the `direct` parts (none when max_bounces is 0), each two collecting rays (light sampling and
 * phase/BRDF sampling, MIS by options.mis). */
void vbl_camera_media_emission(const vbl_render_context* ctx, vbl_thread_state* ts, const vbl_camera_sample* sample,
                               int direct, vbl_rng* rng, vbl_sample_value* out);

#endif
