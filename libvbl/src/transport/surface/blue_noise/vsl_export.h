/* Hands blue-noise virtual lights to the renderer's surface VSL store (transport/surface/surface_vsl.h).
 *
 * A store entry is (position, normal, incident wi, power Phi, material) emitting Phi f(omega, wi)
 * max(0, n . omega) - exactly one incident cell of a blue-noise light's field. So a light is
 * exported as one entry per non-empty incident cell (wi = the cell's representative direction
 * above the surface, Phi = the cell's power), or one entry (wi = n, Phi = the total) for a
 * Lambertian light; the sum of the entries' emission equals vbl_bn_emission's profile.
 * Not carried over: the per-light radius (the store uses one radius for all VSLs; pass e.g. the
 * median of the lights' radii, vbl_bn_median_radius). Entries get bounce = 1. */
#ifndef VBL_BLUE_NOISE_VSL_EXPORT_H
#define VBL_BLUE_NOISE_VSL_EXPORT_H

#include <stddef.h>

#include "transport/surface/blue_noise/photon_splitting.h"
#include "transport/surface/surface_vsl.h"

/* Appends the field's lights to `store` (whose materials must be the lights' materials); *added
 * (may be NULL) gets the number of entries. Errors from vbl_surface_vsl_store_add. */
vbl_result vbl_bn_export_vsls(const vbl_bn_incident_field* field, vbl_surface_vsl_store* store, size_t* added);
/* Photon hits recorded by the photon tracer as surface VSLs (transport/common/photon_trace.h,
 * store_surface_vsls = 1: position, shading normal on the incident side, incident, power) split
 * into the field (vbl_bn_split_photons; errors name vsls[i]). Until the renderer traces photons
 * without storing them this is how photon splitting gets its light paths. */
vbl_result vbl_bn_split_surface_vsls(vbl_bn_incident_field* field, const vbl_surface_vsl* vsls, size_t count);
/* Median of the lights' radii (0 for no lights). */
double vbl_bn_median_radius(const vbl_bn_light* lights, size_t count);

#endif
