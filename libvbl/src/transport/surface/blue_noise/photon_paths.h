/* Light paths for photon splitting over the scene's surfaces (Li et al. 2022,
 * section 3.3: "trace many light paths without storing photons").
 *
 * Path i draws from vbl_rng_make(seed, VBL_BN_PHOTON_STREAM, i). A light is chosen proportionally
 * to vbl_light_power about vbl_photon_emission_sphere (the surfaces' bounds and, with
 * options.extinction, the media's: light that the smoke outside the surfaces scatters onto them
 * is traced too), its emission sampled with vbl_photon_emit (transport/common/light_emission.h),
 * Phi_0 = flux / (select_pdf paths). At
 * every surface hit the photon (power arriving, incident = -d, shading normal) is split among the
 * nearby virtual lights (photon_splitting.h) when its bounce count k (surface hits before this
 * one) is <= max_bounce, then continues by BRDF sampling, Phi *= f cos / pdf, with Russian
 * roulette from the third hit on (q = min(1, max Phi / max Phi_0), survivors divided by q: no
 * cut-off bias); max_bounce >= 0 also ends the walk after the last recorded hit.
 * With options.extinction (scenes with media) every segment is first tracked through the media
 * (delta tracking, vbl_free_flight_sample): a collision is a scattering event that counts as a
 * bounce (k) but is not split; the photon scatters by the media's phase function, Phi *= sigma_s
 * p / (pdf sigma_t), with the same Russian roulette; so a split hit's power carries the
 * transmittance of every segment before it, and light scattered by the media onto a surface is
 * in the field too. Without it (NULL) media are ignored. Paths are traced in parallel per chunk, each path's hits kept
 * in path order, then split sequentially: the field does not depend on the thread count. No
 * photon outlives its chunk. */
#ifndef VBL_BLUE_NOISE_PHOTON_PATHS_H
#define VBL_BLUE_NOISE_PHOTON_PATHS_H

#include <stddef.h>
#include <stdint.h>

#include "transport/surface/blue_noise/photon_splitting.h"
#include "scene/scene.h"
#include "volume/extinction.h"

#define VBL_BN_PHOTON_STREAM 0x424E5048ull /* "BNPH" */

typedef struct vbl_bn_photon_options {
    size_t size;
    uint64_t seed;
    size_t paths;     /* light paths */
    int max_bounce;   /* hits with more earlier surface hits are not split; -1: unlimited */
    size_t chunk;     /* paths traced in parallel before their hits are split */
    const vbl_extinction* extinction; /* the scene's media, NULL: ignore media */
    int use_global_majorant;          /* free flights with the global majorant (no majorant grid) */
    int (*stop)(void* user); /* may be NULL; asked every few hundred paths: non-zero ends the step
                                with VBL_ERROR_INTERRUPTED (cancel, time limit; issue #18) */
    void* stop_user;
} vbl_bn_photon_options;

#define VBL_BN_PHOTON_DEFAULT {sizeof(vbl_bn_photon_options), 1, 1000000, -1, 16384, NULL, 0, NULL, NULL}

typedef struct vbl_bn_photon_stats {
    size_t paths;
    size_t hits;        /* split hits */
    size_t lost_hits;   /* of them, with no virtual light nearby */
    vbl_vec3 emitted;   /* sum of Phi_0 over the paths (estimates the lights' flux) */
} vbl_bn_photon_stats;

/* Traces options->paths light paths and splits their hits into `field` (added to what it holds).
 * Errors: no surfaces, paths == 0, out of memory. A scene without lights adds nothing. */
vbl_result vbl_bn_trace_photons(const vbl_scene* scene, const vbl_bn_photon_options* options,
                                vbl_bn_incident_field* field, vbl_bn_photon_stats* stats);

#endif
