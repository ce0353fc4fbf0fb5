/* Emissive media (docs/readme/emission.md): the emitted radiance per unit length
 * sum_c sigma_a,c(x) Le_c(x) of overlapping media (sigma_a,c = (1 - albedo_c) sigma_t,c, per RGB
 * channel), the per-thread grid accessors it needs, and the programmatic setter. */
#ifndef VBL_SCENE_MEDIA_EMISSION_H
#define VBL_SCENE_MEDIA_EMISSION_H

#include "scene/scene.h"
#include "volume/grid_sample.h"

typedef struct vbl_emission_cursor {
    vbl_grid_accessor emission[VBL_MAX_MEDIA];
    vbl_grid_accessor temperature[VBL_MAX_MEDIA];
    double time; /* the path's time (motion blur; 0 after init): grids read advected */
} vbl_emission_cursor;

void vbl_emission_cursor_init(vbl_emission_cursor* cursor, const vbl_scene* scene);

/* Le of medium `i` at scene point p (RGB, >= 0 by construction: negative grid values are
 * rejected at load and blackbody colours are clamped to the gamut). */
vbl_vec3 vbl_medium_le(const vbl_scene* scene, vbl_emission_cursor* cursor, int i, vbl_vec3 p);

/* sum_c sigma_a,c(p) Le_c(p); component_sigma_t as from vbl_extinction_eval (media order). */
vbl_vec3 vbl_media_emission(const vbl_scene* scene, vbl_emission_cursor* cursor, vbl_vec3 p,
                            const double* component_sigma_t);

/* Gives medium `index` an emission term (emission NULL: none) and/or a blackbody term
 * (temperature NULL: none); retains the volumes and updates scene->has_emission. Fails with
 * VBL_ERROR_INVALID_ARGUMENT on a negative or non-finite colour, scale or intensity. */
vbl_result vbl_scene_set_medium_emission(vbl_scene* scene, int index, vbl_volume* emission, vbl_vec3 color,
                                         double scale, vbl_volume* temperature, double temperature_scale,
                                         double temperature_offset, double blackbody_intensity,
                                         vbl_blackbody_normalization norm);

#endif
