/* Shading a surface point with the blue-noise lights as photon lights
 * (Li et al. 2022, sections 3.3 and 4, eqs. 3-9), one sample of each strategy:
 *
 *   target: int f(wo, w) cos_x w_v(w) L_v(y(w), -w) dw,  L_v(y, -w) = sum_{i: |y - y_i| <= r_i} I_i(-w)
 *
 *  - light sample (eq 4): light j by power, w uniform in its cone; visibility: the first hit y of
 *    the ray must lie in light j's sphere (eq 3); weight p_j^2 / (p_j^2 + p_BSDF^2) (eq 5);
 *  - BSDF sample: w_r from the material, every light i containing the hit y_r adds I_i(-w_r)
 *    with weight p_BSDF^2 / (p_BSDF^2 + p_i^2), p_i = prob_i cone_pdf_i(w_r) (eq 5);
 *  - w_v (eqs 7-9) at both strategies' hits from the footprint with the BSDF pdf and the mean
 *    eq 8 density of the lights containing the hit (the same function for both strategies, so
 *    the MIS pair stays unbiased for the target). w_v = 0 where no light covers y.
 * The caller completes eq 6 by extending the camera path from the BSDF sample's hit with
 * throughput f cos / pdf times (1 - w_v) (bsdf_* fields below). Unbiased for the target; the
 * virtual lights themselves are the (consistent) approximation. No NaN: every division is by a
 * pdf > 0. */
#ifndef VBL_BLUE_NOISE_GATHER_H
#define VBL_BLUE_NOISE_GATHER_H

#include "transport/surface/blue_noise/light_sampling.h"
#include "transport/surface/blue_noise/photon_splitting.h"
#include "material/material.h"

/* First surface hit along origin + t dir (t > 0): 1 with the position and the unit normal. */
typedef int (*vbl_bn_trace_fn)(void* ctx, vbl_vec3 origin, vbl_vec3 dir, vbl_vec3* position, vbl_vec3* normal);

typedef struct vbl_bn_shading {
    vbl_vec3 position;         /* x */
    vbl_vec3 normal;           /* unit shading normal on the viewer's side (surfaces) */
    vbl_vec3 geometric_normal; /* unit, same side (surfaces) */
    vbl_vec3 wo;               /* unit, towards the viewer */
    /* NULL: x is a point in a medium (libvbl's extension beyond the paper, docs/readme/blue_noise.md):
     * the BSDF becomes the phase function, f cos -> medium_f(cos theta) (no cosine, any
     * direction), sampled by HG(phase_g); rays start at x itself. */
    const vbl_material* material;
    double ray_epsilon;        /* offset of spawned rays along the geometric normal */
    /* Scenes with media: an estimate of the transmittance from `from` to `to` (the segment is
     * known to be unoccluded); NULL: 1. Multiplies both strategies' photon-light terms. */
    double (*transmittance)(void* ctx, vbl_vec3 from, vbl_vec3 to);
    void* transmittance_ctx;
    /* medium points (material NULL): the scattering value, RGB (e.g. sigma_s p(cos theta) /
     * sigma_t at a delta-tracking collision) for light arriving from direction w (towards its
     * source) and leaving towards wo, cos theta = dot(-w, wo) (the light's travel directions);
     * and the HG g of the sampling lobe (any |g| < 1 is unbiased). */
    vbl_vec3 (*medium_f)(void* ctx, double cos_theta);
    void* medium_ctx;
    double phase_g;
} vbl_bn_shading;

typedef struct vbl_bn_gather_result {
    vbl_vec3 L;            /* the virtual-light estimate (both strategies) */
    vbl_vec3 L_light, L_bsdf;
    /* the BSDF sample, for the camera path extension (eq 6) */
    int bsdf_valid;        /* a direction above the surface was drawn */
    int bsdf_hit;          /* ... and it hit a surface */
    vbl_vec3 bsdf_dir, bsdf_f, hit_position, hit_normal;
    double bsdf_pdf, cos_x;
    double w_v;            /* eq 9 at the hit (0 without a hit or lights there) */
    size_t lights_at_hit;
} vbl_bn_gather_result;

/* u: 6 uniforms (light pick, 2 cone, 3 BSDF). */
void vbl_bn_gather(const vbl_bn_light_set* set, const vbl_bn_emission* emission, const vbl_bn_shading* sp,
                   vbl_bn_trace_fn trace, void* ctx, const double u[6], double n_min, double n_max,
                   vbl_bn_gather_result* out);

#endif
