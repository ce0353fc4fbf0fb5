/* Emissive media as light sources (docs/readme/emission.md "Light sampling"): the blocks of each
 * emissive medium's majorant grid with a bound on their emitted power, and a direction sampler
 * at a shading point: pick a block with probability proportional to power / distance^2, then a
 * direction uniformly in the cone of its bounding sphere. The radiance arriving along the
 * direction is then estimated by a tracking ray that collects emission (pt.c), so the estimator
 * integrates over directions (finite variance, unlike sampling emitting points, whose 1/r^2
 * weight has infinite variance inside the fire) and combines with phase/BRDF sampling by MIS. */
#ifndef VBL_SCENE_EMISSION_LIGHTS_H
#define VBL_SCENE_EMISSION_LIGHTS_H

#include "core/math.h"
#include "vbl/vbl_core.h"

typedef struct vbl_scene vbl_scene;

typedef struct vbl_emission_block {
    vbl_vec3 center; /* scene space bounding sphere of the block */
    double radius;
    double power;    /* bound on max(sigma_a Le) (max channel) times the sphere's volume */
    /* for photon emission (emitting points, transport/common/light_emission.h): the block
     * group's box in index space of its medium's density grid, mapped to the scene by
     * volume_to_scene o index_to_world (affine, so uniform there is uniform in the scene) */
    int medium;         /* scene->media index */
    double index_lo[3], index_hi[3];
    double bound;       /* bound on max-channel sigma_a Le of this medium in the box */
    double volume;      /* the box's scene-space volume */
} vbl_emission_block;

typedef struct vbl_emission_lights {
    vbl_emission_block* blocks;
    int count;
    /* photon emission: cdf[i + 1] - cdf[i] = bound_i volume_i (count + 1 entries, NULL when
     * count is 0); cdf[count] = sum of the bounds on int sigma_a Le dV (max channel) */
    double* point_cdf;
} vbl_emission_lights;

/* Rebuilds the blocks of every emissive medium of `scene` (none: count 0). */
vbl_result vbl_emission_lights_build(vbl_emission_lights* lights, const vbl_scene* scene);
void vbl_emission_lights_free(vbl_emission_lights* lights);

/* Samples a direction at x (u0 picks the block, u1/u2 the direction). Returns 0 if nothing can
 * be sampled; else *wi (unit) and its density *pdf (per steradian, the full mixture). */
int vbl_emission_lights_sample(const vbl_emission_lights* lights, vbl_vec3 x, double u0, double u1, double u2,
                               vbl_vec3* wi, double* pdf);
/* The mixture density of direction wi (unit) at x. */
double vbl_emission_lights_pdf(const vbl_emission_lights* lights, vbl_vec3 x, vbl_vec3 wi);

/* A block for an emitting point: block i with probability bound_i volume_i / cdf[count] (u in
 * [0, 1)), *prob that probability; then u3 (three uniforms) gives a uniform point *x of its box
 * (density 1 / volume_i in the scene). Returns the block index, -1 if nothing emits. */
int vbl_emission_lights_pick_point(const vbl_emission_lights* lights, const vbl_scene* scene, double u,
                                   const double u3[3], vbl_vec3* x, double* prob);

#endif
