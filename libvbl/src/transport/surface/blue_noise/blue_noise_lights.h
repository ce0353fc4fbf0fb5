/* The virtual-light positions of Li et al. 2022, sections 3.1-3.2, in one call:
 * camera candidates (camera_placement.h) -> adaptive sample elimination to N (sample_elimination.h)
 * -> lights with radius alpha r_max (alpha = 2) and the diffuse flag of their material, ready for
 * photon splitting (photon_splitting.h). */
#ifndef VBL_BLUE_NOISE_BLUE_NOISE_LIGHTS_H
#define VBL_BLUE_NOISE_BLUE_NOISE_LIGHTS_H

#include <stddef.h>

#include "transport/surface/blue_noise/camera_placement.h"
#include "transport/surface/blue_noise/photon_splitting.h"
#include "transport/surface/blue_noise/sample_elimination.h"

/* Keeps min(N, count) of the candidates; *out (malloc'ed) gets *out_count lights in candidate
 * order. materials: the scene's (for vbl_material_is_diffuse). elimination NULL: defaults.
 * Errors: alpha not finite and > 0, N == 0, from vbl_bn_eliminate. */
vbl_result vbl_bn_lights_from_candidates(const vbl_bn_candidate* candidates, size_t count, size_t N, double alpha,
                                         const vbl_material* materials, size_t material_count,
                                         const vbl_bn_elimination_options* elimination, vbl_bn_light** out,
                                         size_t* out_count);

#endif
