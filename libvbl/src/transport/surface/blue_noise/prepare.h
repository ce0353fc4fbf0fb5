/* The whole virtual-light preparation of Li et al. 2022, sections 3.1-3.3 (Figure 4, Table 1's
 * "VSL placement, sample elimination, photon tracing, convert") in one call, for the renderer:
 *   camera candidates (camera_placement.h) -> N blue-noise lights, radius alpha r_max
 *   (blue_noise_lights.h) -> light paths split into incident fields (photon_paths.h) ->
 *   emission profiles (photon_splitting.h) -> a light set for sampling (light_sampling.h).
 * Deterministic for a given scene and options at any thread count. */
#ifndef VBL_BLUE_NOISE_PREPARE_H
#define VBL_BLUE_NOISE_PREPARE_H

#include <stddef.h>

#include "transport/surface/blue_noise/blue_noise_lights.h"
#include "transport/surface/blue_noise/light_sampling.h"
#include "transport/surface/blue_noise/photon_paths.h"

typedef struct vbl_bn_prepare_options {
    size_t size;
    vbl_bn_placement_options placement;     /* .candidates = M */
    size_t lights;                          /* N (kept: min(N, candidates found)) */
    double alpha;                           /* VSL radius = alpha r_max */
    vbl_bn_elimination_options elimination;
    vbl_bn_photon_options photons;
    int resolution;                         /* octahedral map */
    int (*stop)(void* user); /* may be NULL (never stop); copied into the placement, elimination and
                                photon steps' hooks: non-zero ends vbl_bn_prepare with
                                VBL_ERROR_INTERRUPTED and *out empty (cancel, time limit) */
    void* stop_user;
} vbl_bn_prepare_options;

#define VBL_BN_PREPARE_DEFAULT                                                                       \
    {sizeof(vbl_bn_prepare_options), VBL_BN_PLACEMENT_DEFAULT, 10000, VBL_BN_VSL_ALPHA_DEFAULT,      \
     VBL_BN_ELIMINATION_DEFAULT, VBL_BN_PHOTON_DEFAULT, VBL_BN_OCT_RESOLUTION_DEFAULT, NULL, NULL}

typedef struct vbl_bn_prepared {
    vbl_bn_light* lights;
    size_t light_count;
    vbl_bn_incident_field field; /* kept for vbl_bn_export_vsls and diagnostics */
    vbl_bn_emission emission;
    vbl_bn_light_set set;        /* power-based selection uses emission.power */
    vbl_bn_placement_stats placement;
    vbl_bn_photon_stats photons;
} vbl_bn_prepared;

/* Errors from the steps (each names its field); on error *out is left empty (safe to free).
 * options->stop saying stop (asked every few hundred sub-paths, samples or paths) gives
 * VBL_ERROR_INTERRUPTED; not stopped, the result is the same as without a hook. */
vbl_result vbl_bn_prepare(const vbl_scene* scene, const vbl_bn_prepare_options* options, vbl_bn_prepared* out);
void vbl_bn_prepared_free(vbl_bn_prepared* p);

/* For rendering with vbl_bn_gather: eq 3's photon light has RADIANCE L_j(y, w) = I_j(w) / A_j
 * over its disc A_j = pi r_j^2 (a light's profile is the intensity of the flux it gathered by
 * photon splitting; with the partition of unity, sum_{i containing y} Phi_i f / A_i is the
 * density estimate of the reflected radiance at y). Divides each light's profile and P_j by
 * pi r_j^2 and rebuilds the power-based selection (eq 4) from the new P_j. */
vbl_result vbl_bn_prepared_to_radiance(vbl_bn_prepared* p);

#endif
