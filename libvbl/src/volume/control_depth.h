/* A deterministic approximation of the optical depth along a ray from the majorant segments
 * alone (no density lookups): tau_c(t0, t) = sum over segments of (majorant + minorant) / 2 times
 * the length inside [t0, t] (exact in homogeneous segments, where majorant == minorant). pt uses
 * it for MIS weights only (an approximate free-flight pdf sigma_t(t) exp(-tau_c)), which need a
 * deterministic function of t, not the exact transmittance, to stay unbiased. */
#ifndef VBL_VOLUME_CONTROL_DEPTH_H
#define VBL_VOLUME_CONTROL_DEPTH_H

#include "volume/extinction.h"

/* Same ray parameterization as vbl_extinction_iter (origin + t direction); 0 for t <= t0. */
double vbl_control_optical_depth(const vbl_extinction* ext, vbl_vec3 origin, vbl_vec3 direction, double t0,
                                 double t, int use_global_majorant);

#endif
