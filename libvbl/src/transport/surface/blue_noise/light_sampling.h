/* Rendering-side pieces of Li et al. 2022, section 4, as pure functions over a set
 * of blue-noise lights with emission profiles (photon_splitting.h), for the renderer to call:
 *  - eq 4: pick light j with probability P_j / sum P (P_j: mean over RGB of the emitted power),
 *    then a direction uniform in the cone from x that contains the light's sphere,
 *    pdf 1 / (2 pi (1 - cos theta_j)), sin theta_j = r_j / |x - y_j| (x inside the sphere: the
 *    whole sphere, 1 / (4 pi));
 *  - eq 5: the power heuristic;
 *  - eq 3 / section 4.1 BSDF sampling: the lights whose sphere contains a hit point y
 *    (|y - y_j| <= r_j), each contributing I_j^e(-omega_r);
 *  - eq 8: rho_i = alpha^2 / (2 sqrt(3) r_i^2) (= the light density of eq 1 when r_i = alpha
 *    r_max), averaged over the lights containing y;
 *  - eqs 7 and 9: footprint a = |x - y|^2 / (p_BSDF |cos theta_r|) and the blend weight
 *    w_v = clamp((a rho - n_min) / (n_max - n_min), 0, 1) (n_min = 40, n_max = 80), with
 *    w_v = 0 where no light covers y (the path is extended) and no division by zero. */
#ifndef VBL_BLUE_NOISE_LIGHT_SAMPLING_H
#define VBL_BLUE_NOISE_LIGHT_SAMPLING_H

#include <stddef.h>

#include "transport/surface/blue_noise/kd_tree.h"
#include "transport/surface/blue_noise/photon_splitting.h"
#include "core/math.h"
#include "vbl/vbl_core.h"

#define VBL_BN_N_MIN_DEFAULT 40.0
#define VBL_BN_N_MAX_DEFAULT 80.0

typedef struct vbl_bn_light_set {
    const vbl_bn_light* lights; /* not owned */
    size_t count;
    double alpha;        /* radius = alpha r_max (eq 8) */
    double* cdf;         /* count + 1 running sums of the selection power */
    double total;
    vbl_vec3* positions; /* the tree's points */
    vbl_bn_kdtree tree;
    double max_radius;
} vbl_bn_light_set;

/* power: per-light emitted power (vbl_bn_emission.power; NULL: uniform selection). Errors: alpha
 * not finite and > 0, a power not finite and >= 0, out of memory. */
vbl_result vbl_bn_light_set_init(vbl_bn_light_set* set, const vbl_bn_light* lights, size_t count,
                                 const vbl_vec3* power, double alpha);
void vbl_bn_light_set_free(vbl_bn_light_set* set);

/* Eq 4's first factor: the light whose cdf interval holds u * total (u in [0, 1)), and its
 * probability; returns set->count when no light has power. */
size_t vbl_bn_pick_light(const vbl_bn_light_set* set, double u, double* prob);
double vbl_bn_light_prob(const vbl_bn_light_set* set, size_t j);

/* Eq 4's second factor: direction uniform in the cone from x around the sphere (c, r). Returns 1
 * with *w (unit) and *pdf (solid angle). */
int vbl_bn_sample_cone(vbl_vec3 x, vbl_vec3 c, double r, double u1, double u2, vbl_vec3* w, double* pdf);
/* Its density at unit w (0 outside the cone). */
double vbl_bn_cone_pdf(vbl_vec3 x, vbl_vec3 c, double r, vbl_vec3 w);

/* Eq 5: a^2 / (a^2 + b^2), 0 when both are 0. */
static inline double vbl_bn_power_heuristic(double a, double b)
{
    double a2 = a * a, s = a2 + b * b;
    return s > 0.0 ? a2 / s : 0.0;
}

/* Calls visit(ctx, j, squared distance) for every light with |y - y_j| <= r_j. */
void vbl_bn_lights_containing(const vbl_bn_light_set* set, vbl_vec3 y, vbl_bn_kdtree_visit_fn visit, void* ctx);

/* Eq 8 for one light, and its mean over the lights containing y (0 and *n = 0 when none). */
double vbl_bn_light_density(double radius, double alpha);
double vbl_bn_density_at(const vbl_bn_light_set* set, vbl_vec3 y, size_t* n);

/* Eqs 7 and 9: w_v from dist2 = |x - y|^2, the BSDF pdf of omega_r, cos theta_r at y and the
 * density rho(y). density <= 0 (no light covers y): 0. p_BSDF |cos| = 0: 1 (infinite footprint).
 * n_max <= n_min: a step at n_min. Never NaN. */
double vbl_bn_virtual_light_weight(double dist2, double pdf_bsdf, double cos_r, double density, double n_min,
                                   double n_max);

#endif
