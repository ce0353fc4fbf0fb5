/* Uniform direction sampling on the sphere and in a cone. */
#ifndef VBL_SAMPLING_SPHERE_H
#define VBL_SAMPLING_SPHERE_H

#include "core/math.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Uniform over the unit sphere, pdf 1/(4 pi) per steradian (pdf may be NULL). */
vbl_vec3 vbl_sample_uniform_sphere(double u1, double u2, double* pdf);
double vbl_uniform_sphere_pdf(void);

/* Uniform over the cone of directions within acos(cos_max) of unit `axis`,
 * pdf 1 / (2 pi (1 - cos_max)). A cone with cos_max >= 1 has no solid angle: the axis is
 * returned with *pdf = 0 (callers treat pdf 0 as "no sample"). cos_max < -1 is read as -1. */
vbl_vec3 vbl_sample_uniform_cone(vbl_vec3 axis, double cos_max, double u1, double u2, double* pdf);
/* Density of `dir` under the cone sampler: 1/(2 pi (1 - cos_max)) inside, 0 outside. */
double vbl_uniform_cone_pdf(vbl_vec3 axis, double cos_max, vbl_vec3 dir);

#ifdef __cplusplus
}
#endif

#endif
