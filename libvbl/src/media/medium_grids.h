/* Per-point medium properties from role grids (docs/readme/emission.md "Grids by role"): the
 * albedo grid (sigma_s = albedo(x) sigma_t) and the advection of every role grid at a path's
 * time (motion blur). */
#ifndef VBL_MEDIA_MEDIUM_GRIDS_H
#define VBL_MEDIA_MEDIUM_GRIDS_H

#include "media/medium.h"

/* Where medium i's grids are read for scene point p at time t (seconds): its file-world point
 * scene_to_volume(p), advected by its velocity when t != 0. */
vbl_vec3 vbl_medium_grid_point(const vbl_scene* scene, int i, vbl_vec3 p, double time);

/* Medium i's albedo at scene point p, time t: albedo * A(x) with an albedo grid, else albedo. */
vbl_vec3 vbl_medium_albedo_at(const vbl_scene* scene, int i, vbl_vec3 p, double time);

/* Replaces the lobes' constant albedo by vbl_medium_albedo_at and recomputes sigma_s. Nothing
 * (bit for bit) when the scene has no albedo grid. */
void vbl_medium_point_apply_grids(const vbl_scene* scene, vbl_vec3 p, double time, vbl_medium_point* mp);

#endif
