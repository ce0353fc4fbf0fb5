/* Light emission for photon tracing (sampling a photon's origin, direction and flux) and the
 * directly visible emission of quad/environment lights along camera rays (the emission layer of
 * the virtual-light methods, the same quantity pt puts there).
 *
 * Emission sampling, per light (u: four uniforms), returning the flux weight
 * Phi = L_e * |cos| / pdf(origin, direction) of the sample (divide by the number of paths and the
 * light-selection probability for a photon's power):
 *   point, spot: direction uniform in a cone of solid angle 2 pi (1 - cos a), the narrowest of
 *                the whole sphere, the spot's outer cone and the cone subtending the media's
 *                bounding sphere (light outside it): Phi = 2 pi (1 - cos a) I falloff
 *                (directions outside that cone carry no light into the media)
 *   distant:     origin uniform on a disc of radius R (the media bounding sphere) perpendicular
 *                to the travel direction, upstream of the sphere, pdf 1/(pi R^2): Phi = E pi R^2
 *   quad:        origin uniform on the quad (pdf 1/A), cosine-weighted direction about its
 *                normal (pdf cos/pi):                                      Phi = L A pi
 *   environment: travel direction uniform on the sphere (pdf 1/(4 pi)), origin uniform on the
 *                disc of radius R perpendicular to it upstream of the bounding sphere
 *                (pdf 1/(pi R^2)):                                         Phi = L 4 pi pi R^2
 * Distant/environment photons that miss the disc's sphere never reach the media, so restricting
 * origins to the disc loses no light that matters.
 *
 * Emissive media (docs/readme/emission.md) emit the power int 4 pi sigma_a Le dV (isotropic
 * radiance per unit length sigma_a Le). An emitting point is sampled from the blocks of
 * scene->emission_lights (the ones pt's light sampling uses): block b with probability
 * P_b = B_b V_b / sum (B_b: the block's bound on max-channel sigma_a Le, V_b its box volume),
 * a uniform point x of its box (pdf P_b / V_b), kept with probability
 * q = min(1, max(e) / B_b) where e = sigma_a,m(x) Le,m(x) of the block's medium m (rejection as
 * Russian roulette: rejected points carry nothing, so the photon power is constant where the
 * bound holds); direction uniform on the sphere (pdf 1/(4 pi)):
 *   Phi = e 4 pi V_b / (P_b q)      (= 4 pi sum_b B_b V_b e / max(e) when q < 1)
 * The estimate is unbiased for any bound; overlapping media each emit from their own blocks. */
#ifndef VBL_TRANSPORT_LIGHT_EMISSION_H
#define VBL_TRANSPORT_LIGHT_EMISSION_H

#include "transport/common/estimator.h"

/* Bounding sphere of all media in scene space (from the volumes' world bounding boxes mapped by
 * their placements). Returns 0 if the scene has no media. */
int vbl_media_bounding_sphere(const vbl_scene* scene, vbl_vec3* center, double* radius);

typedef struct vbl_emission_sample {
    vbl_vec3 origin, direction; /* unit direction of travel */
    vbl_vec3 flux;              /* L_e |cos| / pdf, see above */
} vbl_emission_sample;

/* Samples an emitted photon; returns 0 when the sample carries no light. */
int vbl_light_sample_emission(const vbl_light* light, vbl_vec3 sphere_center, double sphere_radius,
                              const double u[4], vbl_emission_sample* out);

/* Samples an emitting point of the emissive media (u: seven uniforms: block, three for the
 * point, acceptance, two for the direction); 0 when rejected or nothing emits. The cursors are
 * the caller's per-thread ones (the emission cursor initialised for scene). */
int vbl_media_sample_emission(const vbl_scene* scene, const vbl_extinction* extinction, vbl_extinction_cursor* cursor,
                              vbl_emission_cursor* emission, const double u[7], vbl_emission_sample* out);

/* The bound on the media's emitted power the photon source selects them by: 4 pi sum_b B_b V_b
 * (0 without emissive media). */
double vbl_media_emission_power(const vbl_scene* scene);

/* Total emitted flux reaching the bounding sphere's disc, as a scalar (mean of RGB): the expected
 * value of mean(flux) over emission samples. Used to select lights proportionally to power. */
double vbl_light_power(const vbl_light* light, vbl_vec3 sphere_center, double sphere_radius);

/* Adds quad/environment light seen directly along the camera ray, attenuated by the media
 * (one transmittance estimate per visible light), to out->L[VBL_CLASS_EMISSION]. */
void vbl_add_visible_emission(const vbl_render_context* ctx, vbl_thread_state* ts, vbl_vec3 origin,
                              vbl_vec3 direction, vbl_rng* rng, vbl_sample_value* out);

/* Where the photon walks of photon_trace.c and transport/surface/blue_noise/photon_paths.c start: the scene's lights
 * selected by vbl_light_power about a bounding sphere. */
typedef struct vbl_photon_source {
    vbl_vec3 center;
    double radius;
    double cdf[VBL_MAX_LIGHTS + 1]; /* cdf[i + 1] - cdf[i]: light i's power (0 if not finite) */
    double media_power;             /* vbl_photon_source_add_media: the media's (0: lights only) */
} vbl_photon_source;

/* The sphere photons are emitted towards: the media's bounding sphere (with_media) and, with
 * surfaces, the circumsphere of the box around it and the surfaces (widened by 0.1%). Returns 0
 * when there is neither. */
int vbl_photon_emission_sphere(const vbl_scene* scene, int with_media, vbl_vec3* center, double* radius);

/* Fills s for the sphere; returns the total power (0: nothing emits towards it). */
double vbl_photon_source_init(vbl_photon_source* s, const vbl_scene* scene, vbl_vec3 center, double radius);

/* Adds the emissive media to the source (vbl_media_emission_power); returns the new total. */
double vbl_photon_source_add_media(vbl_photon_source* s, const vbl_scene* scene);

/* One photon of `paths` per pass: a light by power (one uniform of rng), its emission (four),
 * *phi = flux / (select_pdf paths). Returns 0 if the photon carries no finite power. Lights only
 * (a source with media_power > 0 needs vbl_photon_emit_with_media). */
int vbl_photon_emit(const vbl_photon_source* s, const vbl_scene* scene, size_t paths, vbl_rng* rng,
                    vbl_emission_sample* es, vbl_vec3* phi);
/* The same with the media as one more source by media_power (their emission sample draws
 * seven numbers, vbl_media_sample_emission); without media_power exactly vbl_photon_emit (the
 * same random numbers). */
int vbl_photon_emit_with_media(const vbl_photon_source* s, const vbl_scene* scene, const vbl_extinction* extinction,
                               vbl_extinction_cursor* cursor, vbl_emission_cursor* emission, size_t paths,
                               vbl_rng* rng, vbl_emission_sample* es, vbl_vec3* phi);

/* Whether a photon walk goes on after a scattering event (photon_trace.c,
 * transport/surface/blue_noise/photon_paths.c): not when Phi has no power left; with `roulette`, Russian roulette
 * with survival q = min(1, max Phi / phi0) (phi0: the max component of the emitted power),
 * survivors divided by q, so no energy is cut off. */
static inline int vbl_photon_continues(vbl_vec3* phi, double phi0, int roulette, vbl_rng* rng)
{
    if (!(vbl_v3_max_component(*phi) > 0.0)) return 0;
    if (!roulette) return 1;
    double q = fmin(1.0, vbl_v3_max_component(*phi) / phi0);
    if (vbl_rng_uniform(rng) >= q) return 0;
    *phi = vbl_v3_scale(*phi, 1.0 / q);
    return 1;
}

#endif
