/* pt's estimator for the classes of a camera sample that another estimator takes from it
 * (issue 13: each transport class is computed in one place).
 *
 * The virtual-light family (vpl, vrl, vbl) takes the classes of light that scattered at most once
 * in the medium on the way to the camera from pt: emission (visible lights, the environment),
 * volume_emission and volume_direct (single scattering along the camera ray). pt's camera path
 * computes them at its camera segment and first medium vertex: the free flight's collision NEE
 * with the shadow transmittance of pt.shadow_transmittance, the equiangular NEE towards point,
 * spot (and quad) lights MIS-combined with it (Kulla and Fajardo 2012, sec. 4.1-4.2;
 * pt_equiangular.h), pt.direct_strata (pt_direct_strata.h), phase sampling MIS-combined with the
 * NEE of quad and environment lights (Veach 1997, eq. 9.13 / 9.14), the emissive media's light
 * sampling and the null-collision emission estimator (emission_estimate.h), and pt.sampler's
 * dimensions. Running that path with every other class skipped (vbl_render_context.skip_classes)
 * gives the same estimator, value for value in distribution, as pt's own layers: the path stops
 * where every class it could still add to is skipped (vbl_pt_path_skipped), so the cost is pt's
 * camera segment and its first scattering event (with the continuation ray pt traces from it).
 * With max_bounces >= 1 the path runs unlimited (the skipped classes stop it anyway), so that the
 * first vertex also traces its phase-sampled continuation, the other half of the quad and
 * environment lights' NEE / phase MIS that pt drops at its max_bounces vertex: the classes here
 * are then those of pt with max_bounces -1 (unbiased). */
#ifndef VBL_TRANSPORT_PT_CAMERA_CLASSES_H
#define VBL_TRANSPORT_PT_CAMERA_CLASSES_H

#include "transport/common/estimator.h"

/* The classes the virtual-light family takes from pt (bits 1u << vbl_transport_class). */
#define VBL_PT_SINGLE_SCATTER_CLASSES                                                                      \
    ((1u << VBL_CLASS_EMISSION) | (1u << VBL_CLASS_VOLUME_EMISSION) | (1u << VBL_CLASS_VOLUME_DIRECT))

/* Adds pt's estimate of the classes in `classes` (bits) that ctx wants (vbl_ctx_wants) for the
 * camera sample into out->L; other classes of out are left as they are. Draws from rng (and from
 * pt.sampler's Sobol pairs at the sample's index). */
void vbl_pt_camera_classes(const vbl_render_context* ctx, vbl_thread_state* ts, const vbl_camera_sample* sample,
                           unsigned classes, vbl_rng* rng, vbl_sample_value* out);

/* 1 if vbl_pt_camera_classes(ctx, .., classes, ..) traces pt on every camera sample of this render
 * with pt.camera_split, so that it also fills out->aovs (vbl_estimator.camera_aovs). */
int vbl_pt_camera_classes_aovs(const vbl_render_context* ctx, unsigned classes);

#endif
