/* Photon splitting and emission profiles of the blue-noise virtual lights
 * (Li et al. 2022, section 3.3, eq. 3, and section 5).
 *
 * Photons are not stored: each photon hit (position, normal, unit incident direction pointing
 * back towards where the photon came from, power) is split among the nearby lights i with
 *     d_i < r_i,  n_i . n_hit > 0  and  n_i . incident > 0  (same side),
 * with relative weights 1 - (d_i / r_i)^2 normalised to a partition of unity. Its power is added
 * to each light's incident field: a res x res octahedral map in the light's local frame (normal
 * = +z; octahedral.h), or a single value for Lambertian (diffuse) lights. A hit with no nearby
 * light is counted as lost (lost_power): split_power = sum stored + lost_power.
 *
 * The field is then converted to the outgoing profile (vbl_bn_emission): per light the radiant
 * intensity I(omega) = J(omega) max(0, n . omega) with
 *     J(omega) = sum_cells E_c f(omega, wi_c)  (wi_c the cell's representative direction),
 * the convention of transport/surface/surface_vsl.h (a VSL of power Phi from wi emits Phi f cos); a
 * Lambertian light stores J = E albedo / pi. P_j = int I d omega is the emitted power that the
 * power-based light sampling of eq 4 needs.
 *
 * Splitting is sequential (deterministic order); a caller that traces photons in parallel splits
 * fixed chunks into separate fields and merges them in chunk order (vbl_bn_field_merge). */
#ifndef VBL_BLUE_NOISE_PHOTON_SPLITTING_H
#define VBL_BLUE_NOISE_PHOTON_SPLITTING_H

#include <stddef.h>

#include "transport/surface/blue_noise/kd_tree.h"
#include "transport/surface/blue_noise/octahedral.h"
#include "core/math.h"
#include "material/material.h"
#include "vbl/vbl_core.h"

typedef struct vbl_bn_light {
    vbl_vec3 position;
    vbl_vec3 normal; /* unit, on the side the light gathers from */
    double radius;   /* alpha r_max (sample_elimination.h) */
    int material;    /* index into the scene's materials */
    int diffuse;     /* 1: single-value field (vbl_material_is_diffuse) */
} vbl_bn_light;

typedef struct vbl_bn_photon_hit {
    vbl_vec3 position;
    vbl_vec3 normal;   /* unit surface normal at the hit, on the side the photon arrived from */
    vbl_vec3 incident; /* unit, from the hit towards where the photon came from */
    vbl_vec3 power;
} vbl_bn_photon_hit;

typedef struct vbl_bn_incident_field {
    const vbl_bn_light* lights; /* not owned */
    size_t light_count;
    vbl_oct_table table;
    size_t* offset;      /* light_count + 1: the light's cells are values[offset[i], offset[i+1]) */
    vbl_vec3* values;    /* incident power per cell (diffuse lights: one value) */
    vbl_bn_kdtree tree;  /* over light positions */
    vbl_vec3* positions; /* the tree's points */
    double max_radius;
    vbl_vec3 split_power; /* sum of the powers of all split hits */
    vbl_vec3 lost_power;  /* of hits with no nearby light */
    size_t hits, lost_hits;
} vbl_bn_incident_field;

/* vbl_bn_kdtree_set_radii with the lights' radii (the tree is over the lights' positions, in order). */
vbl_result vbl_bn_tree_set_light_radii(vbl_bn_kdtree* tree, const vbl_bn_light* lights, size_t count);

/* res: octahedral resolution (VBL_BN_OCT_RESOLUTION_DEFAULT), even. Errors name the light or
 * field: non-finite position, non-unit normal, radius not finite and > 0;
 * VBL_ERROR_OUT_OF_MEMORY. lights must outlive the field. */
vbl_result vbl_bn_field_init(vbl_bn_incident_field* field, const vbl_bn_light* lights, size_t light_count, int res);
void vbl_bn_field_free(vbl_bn_incident_field* field);

/* The partition of unity for one hit: the first min(found, capacity) light indices and weights
 * (summing to 1 over all found); returns the number found (0: the hit would be lost). */
size_t vbl_bn_split_weights(const vbl_bn_incident_field* field, const vbl_bn_photon_hit* hit, size_t* lights,
                            double* weights, size_t capacity);
/* Splits hits[0..count) into the field (sequential). Hits with non-finite or negative power are
 * an error naming the hit (nothing of that hit is added). */
vbl_result vbl_bn_split_photons(vbl_bn_incident_field* field, const vbl_bn_photon_hit* hits, size_t count);
/* dst += src (same lights and resolution). */
vbl_result vbl_bn_field_merge(vbl_bn_incident_field* dst, const vbl_bn_incident_field* src);
/* Sum of the power stored in all lights' fields. */
vbl_vec3 vbl_bn_field_stored_power(const vbl_bn_incident_field* field);

typedef struct vbl_bn_emission {
    const vbl_bn_light* lights; /* not owned */
    size_t light_count;
    int resolution;
    size_t* offset;   /* as in the field */
    vbl_vec3* values; /* J per outgoing cell (diffuse: one value) */
    vbl_vec3* power;  /* P_j per light (eq 4) */
    int radiance;     /* 0: values are J (intensity J cos); 1: radiance J / (pi r^2) of eq 3's photon
                         light, no cos (vbl_bn_prepared_to_radiance, prepare.h) */
} vbl_bn_emission;

/* Converts the incident field to outgoing profiles with the lights' materials (OpenMP over
 * lights; deterministic). Errors: a light's material index out of range; out of memory. */
vbl_result vbl_bn_emission_from_field(const vbl_bn_incident_field* field, const vbl_material* materials,
                                      size_t material_count, vbl_bn_emission* out);
void vbl_bn_emission_free(vbl_bn_emission* e);
/* Radiant intensity of light i towards the world direction omega (unit): J(cell of omega) times
 * max(0, n . omega) (eq 3's I_j^e); with e->radiance, the radiance J / (pi r^2) for n . omega > 0
 * (no cos: eq 3's photon light), 0 behind the light. */
vbl_vec3 vbl_bn_emission_intensity(const vbl_bn_emission* e, size_t light, vbl_vec3 omega);

/* World <-> light-local frame (normal = +z, vbl_v3_basis). */
vbl_vec3 vbl_bn_to_local(vbl_vec3 normal, vbl_vec3 w);
vbl_vec3 vbl_bn_to_world(vbl_vec3 normal, vbl_vec3 w);

#endif
