/* Initial virtual-light placement from camera sub-paths (Li et al. 2022,
 * section 3.1, Figure 6): candidate k traces a primary ray through a jittered position of pixel
 * floor(k W H / M) (every pixel gets M / (W H) candidates, as the paper's equal samples per
 * screen tile), samples the BSDF at the primary hit x and places the candidate y at the next hit.
 * When the sampled direction is a specular reflection on a highly specular material the camera
 * path is extended: the ray continues from that hit (up to max_specular_depth times) and the
 * candidate is placed at the hit after the last extension.
 *
 * "Highly specular": Phong with exponent >= phong_exponent (200) and a specular lobe, or GGX with
 * roughness <= ggx_roughness (0.1). "Specular reflection": the sampled direction's BRDF value is
 * dominated by the specular lobe, mean(f) > 2 mean(kd / pi) (the diffuse part is kd / pi for
 * Phong and at most that for GGX), so a diffuse-lobe sample on a glossy material ends the path.
 *
 * Randomness: vbl_rng_make(seed, VBL_BN_PLACEMENT_STREAM, k); OpenMP over k with results
 * compacted in k order, so the candidates do not depend on the thread count. Candidates carry
 * the hit's shading normal facing the arriving ray (the side the light gathers from). */
#ifndef VBL_BLUE_NOISE_CAMERA_PLACEMENT_H
#define VBL_BLUE_NOISE_CAMERA_PLACEMENT_H

#include <stddef.h>
#include <stdint.h>

#include "core/math.h"
#include "material/material.h"
#include "scene/scene.h"
#include "vbl/vbl_core.h"

#define VBL_BN_PLACEMENT_STREAM 0x424E504Cull /* "BNPL": the pass key of the placement streams */

typedef struct vbl_bn_placement_options {
    size_t size;
    uint64_t seed;
    size_t candidates;      /* M: camera sub-paths traced (each gives at most one candidate) */
    int max_specular_depth; /* extensions through highly specular bounces */
    double phong_exponent;  /* Phong exponent at or above which a material is highly specular */
    double ggx_roughness;   /* GGX roughness at or below which a material is highly specular */
    int (*stop)(void* user); /* may be NULL; asked every few hundred sub-paths: non-zero ends the step
                                with VBL_ERROR_INTERRUPTED (cancel, time limit; issue #18) */
    void* stop_user;
} vbl_bn_placement_options;

#define VBL_BN_PLACEMENT_DEFAULT {sizeof(vbl_bn_placement_options), 1, 100000, 4, 200.0, 0.1, NULL, NULL}

typedef struct vbl_bn_candidate {
    vbl_vec3 position; /* y */
    vbl_vec3 normal;   /* unit shading normal at y facing the ray that found it */
    vbl_vec3 from;     /* x: the camera sub-path vertex the ray to y left from */
    int material;      /* index into scene->materials */
    int surface;
    int depth;         /* specular extensions before y (0: y is the secondary hit) */
    uint32_t pixel;    /* row-major pixel index of the primary ray */
} vbl_bn_candidate;

typedef struct vbl_bn_placement_stats {
    size_t traced;          /* camera sub-paths */
    size_t primary_misses;  /* primary ray left the scene */
    size_t secondary_misses;/* the BSDF ray (or an extension) left the scene */
    size_t absorbed;        /* the BSDF sample failed (below the surface) */
    size_t extended;        /* candidates placed after >= 1 specular extension */
} vbl_bn_placement_stats;

/* 1 if m is highly specular under the options' thresholds. */
int vbl_bn_highly_specular(const vbl_material* m, const vbl_bn_placement_options* options);

/* Traces options->candidates camera sub-paths; *out (malloc'ed, caller frees) gets *count <= M
 * candidates. The scene must have surfaces. stats may be NULL. Errors:
 * VBL_ERROR_INVALID_ARGUMENT (no surfaces, candidates == 0, bad option), out of memory. */
vbl_result vbl_bn_place_candidates(const vbl_scene* scene, const vbl_bn_placement_options* options,
                                   vbl_bn_candidate** out, size_t* count, vbl_bn_placement_stats* stats);

#endif
