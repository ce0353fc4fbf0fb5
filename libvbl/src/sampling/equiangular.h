/* Equiangular sampling (Kulla & Fajardo 2012): a distance t in [t0, t1] along the ray o + t d
 * with density proportional to 1 / |o + t d - point|^2. Same truncated Cauchy as VRL eq (14). */
#ifndef VBL_SAMPLING_EQUIANGULAR_H
#define VBL_SAMPLING_EQUIANGULAR_H

#include "core/math.h"

#ifdef __cplusplus
extern "C" {
#endif

/* d must be unit length. Returns t in [t0, t1]; *pdf (per unit t, may be NULL) is the density
 * sampled. A point on the ray line keeps a finite pdf through the relative floor on the
 * perpendicular distance (VBL_SAMPLING_H_FLOOR_REL in cauchy.h). t1 <= t0: returns t0, *pdf = 0. */
double vbl_equiangular_sample(vbl_vec3 o, vbl_vec3 d, double t0, double t1, vbl_vec3 point, double u, double* pdf);
double vbl_equiangular_pdf(vbl_vec3 o, vbl_vec3 d, double t0, double t1, vbl_vec3 point, double t);

#ifdef __cplusplus
}
#endif

#endif
