/* The driver with an explicit estimator (tests compare estimators through the same film). */
#ifndef VBL_RENDER_RENDER_INTERNAL_H
#define VBL_RENDER_RENDER_INTERNAL_H

#include "transport/common/estimator.h"

/* vbl_render with `estimator` in place of the method's (options.method is only recorded). */
vbl_result vbl_render_with_estimator(const vbl_scene* scene, const vbl_render_options* options,
                                     const vbl_estimator* estimator, vbl_film** out_film);

/* options.light_groups on a scene with light groups: one render per group, combined
 * (render/light_groups.c). */
vbl_result vbl_render_light_groups(const vbl_scene* scene, const vbl_render_options* options,
                                   const vbl_estimator* estimator, vbl_film** out_film);

#endif
