/* Surface caustics by progressive photon mapping (issue 6): light that reached a diffuse/glossy
 * surface straight from a highly specular surface vertex (light -> ... -> mirror-like Phong/GGX ->
 * surface seen by the camera), where a surface VSL at the specular vertex would be a near-delta
 * lobe.
 *
 * The split (no double counting, nothing missing), for a camera-visible surface point x and the
 * vertex y before it on the light path:
 *   - y highly specular (vbl_material_is_highly_specular), x not: a CAUSTIC PHOTON at x. Photon
 *     tracing (photon_trace.c) stores one at every surface hit z that is not highly specular and
 *     whose previous vertex was a highly specular surface vertex (a medium collision in between
 *     ends the segment, so no photon: that light belongs to the VRLs/VPLs). The VSL stored at y is
 *     NOT gathered at such x (surface_gather.c).
 *   - y not highly specular (surface or medium): the VSLs / VRLs / VPLs as before.
 *   - x highly specular itself: no caustic gather (a near-delta BRDF makes density estimation
 *     hopeless); every VSL, specular ones included, is gathered at x as before. The camera path is
 *     not continued through the specular bounce (a limitation: mirror-seen caustics stay noisy).
 *   - volume_from_surface still uses every VSL (volume caustics are not photon mapped).
 * Surface VSLs are therefore still stored at highly specular vertices (their volume_from_surface
 * and specular-receiver gathers need them); caustic photons add to, never replace, the stores.
 *
 * Estimate (progressive photon mapping, radiance at x towards wo):
 *     L(x, wo) = sum_{photons j, |x_j - x| < R} f(wo, wi_j) Phi_j K_R(|x_j - x|),
 *     K_R(d) = 2 / (pi R^2) (1 - d^2 / R^2)   (Epanechnikov; int over the disc of radius R = 1),
 * over photons on the same side (photon normal . n > 1/2; the 3D ball cut by the tangent plane is
 * the disc). R_p = vbl_radius_at_pass(R_0, alpha, 2, pass) (eq 11, d = 2): bias and variance of
 * the pass average vanish. Default R_0: vbl_caustic_default_r0. */
#ifndef VBL_TRANSPORT_SURFACE_CAUSTICS_H
#define VBL_TRANSPORT_SURFACE_CAUSTICS_H

#include <stddef.h>

#include "core/math.h"
#include "material/material.h"
#include "vbl/vbl_core.h"

/* The "highly specular" rule of transport/surface/blue_noise/camera_placement.c (VBL_BN_PLACEMENT_DEFAULT): Phong
 * with a specular lobe (max ks > 0) and exponent >= 200, or GGX with roughness <= 0.1. */
#define VBL_HIGHLY_SPECULAR_PHONG_EXPONENT 200.0
#define VBL_HIGHLY_SPECULAR_GGX_ROUGHNESS 0.1

int vbl_material_is_highly_specular(const vbl_material* m);
/* 1 if any of the count materials is highly specular. */
int vbl_materials_any_highly_specular(const vbl_material* materials, int count);

typedef struct vbl_caustic_photon {
    vbl_vec3 position;
    vbl_vec3 normal;   /* unit shading normal on the incident side */
    vbl_vec3 incident; /* unit wi: towards where the photon came from (the specular vertex) */
    vbl_vec3 power;    /* flux arriving */
    int bounce;        /* scattering events before the photon reached the surface (>= 1) */
} vbl_caustic_photon;

/* Hash grid over the photons of one pass (cells of edge `cell`, hashed into a power-of-two table;
 * photons sorted by bucket). */
typedef struct vbl_caustic_map {
    vbl_caustic_photon* photons;
    size_t count;
    size_t* start;     /* table_size + 1 offsets into photons */
    size_t table_size; /* 0: no grid (count == 0) */
    double cell;
} vbl_caustic_map;

/* Builds the grid over a copy of the count photons with cell edge `cell` (> 0). Errors:
 * VBL_ERROR_OUT_OF_MEMORY. count == 0 gives an empty map. */
vbl_result vbl_caustic_map_build(vbl_caustic_map* map, const vbl_caustic_photon* photons, size_t count, double cell);
void vbl_caustic_map_free(vbl_caustic_map* map);

/* K_R(d) for d^2 = dist2: 2/(pi R^2) (1 - dist2/R^2) inside, 0 outside and for R <= 1e-100. */
double vbl_caustic_kernel(double dist2, double radius);

/* L(x, wo) of the header comment at x (unit shading normal n towards wo, material m), radius R,
 * over the photons with bounce + 1 <= max_bounces (< 0: all). Any R works (R much larger than the cell falls back to a scan). Finite for every R >= 0. */
vbl_vec3 vbl_caustic_gather(const vbl_caustic_map* map, vbl_vec3 x, vbl_vec3 n, vbl_vec3 wo, const vbl_material* m,
                            double radius, int max_bounces);

/* Default R_0: sqrt(10 A / (pi N)) with A half the surface area of the caustic photons' bounding
 * box (about 10 photons in the disc at their mean density) and N the photons of the pass, clamped
 * to [1e-3, 0.05] x the diagonal of the surfaces' bounding box (lo, hi); 0.01 x that diagonal for
 * N < 2. 0 for an empty / non-finite box. */
double vbl_caustic_default_r0(const vbl_caustic_photon* photons, size_t count, vbl_vec3 lo, vbl_vec3 hi);

#endif
