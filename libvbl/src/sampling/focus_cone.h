/* Directions about a unit axis with the angle psi to it uniform in [0, psi_max] (psi_max in
 * (0, pi]) and the azimuth uniform: the density per steradian
 *   p(w) = 1 / (2 pi psi_max sin psi)   for psi < psi_max, 0 beyond,
 * which grows like 1/psi towards the axis. A ray from x in direction w passes a point at distance
 * R along the axis at distance h = R sin psi, and single scattering from a point light there
 * grows like 1/h (Kulla and Fajardo 2012, sec. 4.1); with this density the ratio stays bounded,
 * where a BRDF's bounded density gives infinite variance (int (1/h)^2 h dh diverges). pt samples
 * scattered directions from it towards point lights in media (pt.light_focus,
 * transport/path_tracing/pt_light_focus.h), the direction-space twin of pixel_focus. */
#ifndef VBL_SAMPLING_FOCUS_CONE_H
#define VBL_SAMPLING_FOCUS_CONE_H

#include "core/math.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Samples w (u1 the angle, u2 the azimuth, in [0, 1)): 1 with *w and *pdf > 0 finite, 0 where the
 * density is not finite (psi = 0) or psi_max is out of range. */
int vbl_focus_cone_sample(vbl_vec3 axis, double psi_max, double u1, double u2, vbl_vec3* w, double* pdf);

/* The density of unit w (0 beyond psi_max, on the axis itself, or for psi_max out of range). */
double vbl_focus_cone_pdf(vbl_vec3 axis, double psi_max, vbl_vec3 w);
/* The same with cos_max = cos(psi_max) given (psi_max in range): no trigonometry per call. */
double vbl_focus_cone_pdf_cos(vbl_vec3 axis, double psi_max, double cos_max, vbl_vec3 w);

#ifdef __cplusplus
}
#endif

#endif
