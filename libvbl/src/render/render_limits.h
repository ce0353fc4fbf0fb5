/* The documented limits of the virtual-light and beam estimators (docs/readme/render.md
 * "Limits of the methods at the extremes"): the thresholds, shared by vbl_render_limits
 * (warnings the CLI prints) and the render's validation (the one refusal). */
#ifndef VBL_RENDER_RENDER_LIMITS_H
#define VBL_RENDER_RENDER_LIMITS_H

#include "scene/scene.h"

/* |g| above this: vpl, vrl, vbl and beams connect a light-path vertex to a camera-ray point
 * through two phase-function evaluations (or one across a fixed beam), which a near-delta
 * lobe almost never satisfies (warning). */
#define VBL_LIMIT_CONNECT_G 0.95
/* An explicit beams.radius0 below this fraction of the media's bounding-sphere diameter is
 * refused (the lower end of the default R0, radius_schedule.h): the 1D beam kernel is then narrower than any realistic spacing of camera rays and
 * beams (no overlap is ever found: exactly 0), and below ~1e-16 of the scene the kernel's
 * distance is rounding noise. */
#define VBL_LIMIT_BEAMS_RADIUS_MIN 1e-4
/* An explicit beams.radius0 or vbl.radius0 above this fraction of the diameter blurs light
 * into empty space (warning; the default R0 is clamped to at most this). */
#define VBL_LIMIT_RADIUS_MAX 0.1

/* beams and vbl: a kernel radius (the explicit radius0, else the default's floor 1e-4 x the
 * diameter) more than this many mean free paths at the densest point (radius x the global
 * majorant) blurs light between lit and unlit depths of an optically thick medium (warning). */
#define VBL_LIMIT_THICK_RADIUS_MFP 10.0
#define VBL_LIMIT_DEFAULT_RADIUS_MIN 1e-4
/* vpl: media more than this many mean free paths across (global majorant x diameter) light only
 * a skin a tiny fraction of a camera ray's chord; equiangular camera points rarely land in it and
 * the 1/w^2 near field makes the estimate heavy-tailed: a finite render comes out too dark
 * (warning). */
#define VBL_LIMIT_THICK_VPL_MFP 1e4

/* Diameter of the media's bounding sphere (0 without media). */
double vbl_limits_media_diameter(const vbl_scene* scene);

/* VBL_ERROR_INVALID_ARGUMENT (message naming the scene file and the option) when beams.radius0 is
 * below VBL_LIMIT_BEAMS_RADIUS_MIN x the diameter for a method that uses it (beams; vbl with
 * single_scattering = beams); `method` is the estimator's name. */
vbl_result vbl_limits_check_radius(const vbl_scene* scene, const vbl_render_options* options, const char* method);

#endif
