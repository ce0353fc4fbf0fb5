/* 3D DDA over the majorant grid along a ray: piecewise-constant majorant segments that skip
 * empty blocks (pbrt-v4 style `next(&iter, &segment)` loop shared by every tracking estimator). */
#ifndef VBL_VOLUME_MAJORANT_ITER_H
#define VBL_VOLUME_MAJORANT_ITER_H

#include "volume/volume.h"

/* A ray-parameter interval with constant bounds on the (unscaled) grid value. */
typedef struct vbl_majorant_segment {
    double t0, t1;
    double majorant;   /* >= every trilinear sample in the interval */
    double minorant;   /* <= every trilinear sample in the interval (residual tracking control) */
} vbl_majorant_segment;

typedef struct vbl_majorant_iter {
    const vbl_majorant_grid* grid;
    double t, t_end;
    int cell[3], step[3], done;
    double t_next[3], t_delta[3];
    double org[3], inv_dir[3]; /* ray in block units: (index - grid origin) / block */
} vbl_majorant_iter;

/* Ray in *world* space of the volume: origin + t * direction, t in [tmin, tmax]. Segments come
 * in increasing t, are contiguous where the ray is inside the grid's support and cover exactly
 * the overlap of [tmin, tmax] with it; empty blocks (majorant 0) are returned too, so callers
 * see continuous coverage of non-empty space only when they skip majorant == 0 themselves. */
void vbl_majorant_iter_init(vbl_majorant_iter* iter, const vbl_volume* volume, vbl_vec3 origin,
                            vbl_vec3 direction, double tmin, double tmax);
/* The same on any majorant grid (e.g. a dilated copy) placed by `world_to_index`. */
void vbl_majorant_iter_init_grid(vbl_majorant_iter* iter, const vbl_majorant_grid* grid, const vbl_affine* world_to_index,
                                 vbl_vec3 origin, vbl_vec3 direction, double tmin, double tmax);
/* Returns 1 and fills `segment`, or 0 when the ray has left the grid or passed tmax. */
int vbl_majorant_iter_next(vbl_majorant_iter* iter, vbl_majorant_segment* segment);

#endif
