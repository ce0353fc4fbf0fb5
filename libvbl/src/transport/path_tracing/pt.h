/* Volumetric path tracer, the reference method: delta tracking for free paths, next-event
 * estimation with the render's transmittance estimator for shadow rays, MIS (light vs phase
 * sampling) for quad and environment lights, equiangular NEE for point/spot lights MIS-combined
 * with the collision's NEE (pt_equiangular.h), Russian roulette on throughput, unlimited bounces
 * unless options.max_bounces >= 0. Contributions are classified by scattering events. */
#ifndef VBL_TRANSPORT_PT_H
#define VBL_TRANSPORT_PT_H

#include "transport/common/estimator.h"

extern const vbl_estimator vbl_estimator_pt;

/* One camera path (the estimator's camera_sample). */
void vbl_pt_camera_sample(const vbl_render_context* ctx, const void* store, vbl_thread_state* ts,
                          const vbl_camera_sample* sample, vbl_rng* rng, vbl_sample_value* out);

#endif
