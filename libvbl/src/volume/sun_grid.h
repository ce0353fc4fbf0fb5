/* A deterministic grid of the media's transmittance towards a distant light: T_c(x) ~ T(x, x +
 * inf w) for every point of the media's box, built once per render by one sweep through the box
 * from the light's side (each node's T is the upstream node's, interpolated on the previous
 * slice, times exp(-tau) of the short segment between them, tau by the midpoint rule; 0 where a
 * surface blocks the light). It is a
 * control, not an estimate: pt's shadow roulette returns T_c where it stops a shadow ray and
 * corrects it by the ray's own estimate where it traces one, so any deterministic T_c keeps the
 * result unbiased and only T_c's error sets the variance the roulette adds (sampling.md, "A
 * control for the shadow roulette"). */
#ifndef VBL_VOLUME_SUN_GRID_H
#define VBL_VOLUME_SUN_GRID_H

#include "core/error.h"
#include "volume/extinction.h"

typedef struct vbl_sun_grid {
    vbl_vec3 lo, hi; /* the box (scene space) the nodes span, corners included */
    vbl_vec3 w;      /* unit direction towards the light */
    int n[3];        /* nodes per axis (>= 2) */
    double h[3];     /* node spacing per axis */
    double inv_h[3]; /* 1 / h */
    float* T;        /* node (i, j, k) at T[((size_t)i * n[1] + j) * n[2] + k]; NULL: no grid */
} vbl_sun_grid;

/* 1 if something other than the media blocks the ray x + t w, t > 0 (surfaces); called from
 * several threads at once. */
typedef int (*vbl_sun_grid_occluded_fn)(void* user, vbl_vec3 x, vbl_vec3 w);

/* Builds g over the box [lo, hi] towards w (unit; the direction the light comes from) with at most
 * max_nodes nodes, spaced no finer than the media's finest voxel; `threads` threads (the result
 * does not depend on them). With `occluded` (NULL: nothing blocks), a blocked node holds 0.
 * VBL_ERROR_INVALID_ARGUMENT for an empty box or a non-unit w, VBL_ERROR_OUT_OF_MEMORY. */
vbl_result vbl_sun_grid_build(vbl_sun_grid* g, const vbl_extinction* ext, vbl_vec3 lo, vbl_vec3 hi, vbl_vec3 w,
                              size_t max_nodes, int threads, vbl_sun_grid_occluded_fn occluded, void* user);

/* T_c at scene point x, in [0, 1]: trilinear in the box; outside it, the value where the ray
 * x + t w enters the box (1 if it never does: no media on the way). */
double vbl_sun_grid_eval(const vbl_sun_grid* g, vbl_vec3 x);

void vbl_sun_grid_free(vbl_sun_grid* g);

#endif
