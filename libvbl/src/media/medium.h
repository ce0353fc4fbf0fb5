/* The medium interface, in the spirit of pbrt-v4's Medium and Mitsuba's medium (Pharr et al.
 * 2023, Physically Based Rendering 4th ed., section 11.4; Jakob et al., Mitsuba 3): a point query
 * returns sigma_t, sigma_s and the phase mixture of the overlapping media there (one
 * Henyey-Greenstein lobe per medium, weighted by its sigma_s); the phase function is sampled and
 * evaluated on that result (value and pdf); a segment is (origin, direction, t0, t1).
 *
 * Every estimator that needs "what scatters here, and how" asks a vbl_medium_point instead of
 * indexing scene->media[i] with raw per-component sigma_t arrays. */
#ifndef VBL_MEDIA_MEDIUM_H
#define VBL_MEDIA_MEDIUM_H

#include "core/math.h"
#include "core/rng.h"
#include "core/segment.h" /* vbl_segment */
#include "scene/scene.h"
#include "volume/transmittance.h"

/* One medium's share at a point: its extinction, albedo and HG g (sigma_s = albedo sigma_t). */
typedef struct vbl_phase_lobe {
    int medium;       /* index into scene->media */
    double sigma_t;   /* this medium's extinction here (> 0) */
    vbl_vec3 albedo;  /* its single-scattering albedo (RGB) */
    double g;         /* its HG asymmetry */
} vbl_phase_lobe;

/* The point query's result: totals and the lobes of the media present (media order). */
typedef struct vbl_medium_point {
    double sigma_t;  /* sum of the lobes' sigma_t */
    vbl_vec3 sigma_s; /* sum of albedo_i sigma_t,i (RGB) */
    int count;       /* lobes (media with sigma_t > 0 here); 0: no medium */
    vbl_phase_lobe lobe[VBL_MAX_MEDIA];
} vbl_medium_point;

/* From per-component extinctions (vbl_extinction_eval's `components`, scene->media order). */
void vbl_medium_point_from_components(const vbl_scene* scene, const double* component_sigma_t, vbl_medium_point* out);
/* The point query at p (one extinction evaluation). Returns sigma_t. */
double vbl_medium_query(const vbl_scene* scene, const vbl_extinction* extinction, vbl_extinction_cursor* cursor,
                        vbl_vec3 p, vbl_medium_point* out);

/* sum_i sigma_s,i p_i(cos_theta) per RGB channel: the RTE's in-scattering kernel. cos_theta is
 * between the travel directions before and after scattering (either transport direction: HG is
 * symmetric). */
vbl_vec3 vbl_medium_phase_kernel(const vbl_medium_point* mp, double cos_theta);
/* Pdf of vbl_medium_phase_sample: sum_i q_i p_i(cos_theta), q_i proportional to mean-RGB sigma_s,i. */
double vbl_medium_phase_pdf(const vbl_medium_point* mp, double cos_theta);
/* Picks a lobe by mean-RGB sigma_s (u0), samples its HG lobe around `travel` (u1, u2). Returns 0 if
 * nothing scatters here; otherwise *wi (unit) and its mixture pdf *pdf. */
int vbl_medium_phase_sample(const vbl_medium_point* mp, vbl_vec3 travel, double u0, double u1, double u2,
                            vbl_vec3* wi, double* pdf);
/* The sigma_s-weighted mean g (0 if nothing scatters): a sampling hint only (a mixture of lobes is
 * not an HG lobe of its mean g). */
double vbl_medium_mean_g(const vbl_medium_point* mp);

/* The normalized lobe weights for kernels that take one HG lobe at a time: w_i (RGB) =
 * albedo_i sigma_t,i / sigma_t, so that sigma_s p(cos) = sigma_t sum_i w_i HG(g_i, cos). */
static inline vbl_vec3 vbl_medium_lobe_weight(const vbl_medium_point* mp, int i)
{
    return vbl_v3_madd(vbl_v3(0.0, 0.0, 0.0), mp->lobe[i].albedo, mp->lobe[i].sigma_t / mp->sigma_t);
}

/* The scene's media as lobes weighted by their density scales (sigma_t,i = density_scale_i): the
 * phase mixture of a unit density of every medium, a point-independent sampling hint (the
 * density-weighted mean g of vbl_medium_mean_g, the lobes of the surface samplers). */
void vbl_medium_point_scene(const vbl_scene* scene, vbl_medium_point* out);

/* Delta-tracking free flight along `segment` (vbl_free_flight_sample over [t0, t1]): returns 1
 * with the collision distance *t and the medium there in *out (its sigma_t the tracker's own
 * value), 0 if the ray passes t1 (out untouched). */
int vbl_medium_free_flight(const vbl_scene* scene, const vbl_extinction* extinction, vbl_extinction_cursor* cursor,
                           const vbl_segment* segment, int use_global_majorant, vbl_rng* rng, double* t,
                           vbl_medium_point* out);

/* A walk's scattering at a delta-tracking collision (mp->sigma_t > 0): samples *wi with
 * vbl_medium_phase_sample from u[0..2] (its pdf into *pdf unless NULL) and multiplies *throughput
 * by sigma_s p / (pdf sigma_t) (RGB). Returns 0 (throughput untouched) if nothing scatters here. */
int vbl_medium_scatter(const vbl_medium_point* mp, vbl_vec3 travel, const double u[3], vbl_vec3* wi, double* pdf,
                       vbl_vec3* throughput);

#endif
