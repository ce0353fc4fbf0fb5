/* 3D DDA over the majorant grid along a ray: piecewise-constant majorant segments that skip
 * empty blocks (pbrt-v4 style `next(&iter, &segment)` loop shared by every tracking estimator). */
#ifndef VBL_VOLUME_MAJORANT_ITER_H
#define VBL_VOLUME_MAJORANT_ITER_H

#include <stddef.h>

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
    /* Hierarchical DDA state (majorant_iter.c): */
    size_t index;          /* linear block index of `cell` */
    ptrdiff_t stride[3];   /* change of `index` for one step along each axis */
    int coarse_check;      /* 1: `cell` has just entered a coarse cell not examined yet */
    double coarse_tau;     /* a coarse cell with majorant x length <= coarse_tau is one segment */
    double coarse_ratio;   /* ... and one whose max is <= coarse_ratio x its smallest block max */
    int coarse_merge;      /* coarse_tau > 0 or coarse_ratio >= 1 */
    unsigned long steps;   /* DDA steps taken (block and coarse-cell crossings), for benchmarks */
} vbl_majorant_iter;

/* Ray in *world* space of the volume: origin + t * direction, t in [tmin, tmax]. Segments come
 * in increasing t, are contiguous where the ray is inside the grid's support and cover exactly
 * the overlap of [tmin, tmax] with it; empty blocks (majorant 0) are returned too, so callers
 * see continuous coverage of non-empty space only when they skip majorant == 0 themselves.
 * A run of empty blocks inside one empty coarse cell (VBL_MAJORANT_COARSE^3 blocks) comes as
 * one segment; non-empty blocks come one segment each, exactly as a block-by-block walk. */
void vbl_majorant_iter_init(vbl_majorant_iter* iter, const vbl_volume* volume, vbl_vec3 origin,
                            vbl_vec3 direction, double tmin, double tmax);
/* The same on any majorant grid (e.g. a dilated copy) placed by `world_to_index`. */
void vbl_majorant_iter_init_grid(vbl_majorant_iter* iter, const vbl_majorant_grid* grid, const vbl_affine* world_to_index,
                                 vbl_vec3 origin, vbl_vec3 direction, double tmin, double tmax);
/* As vbl_majorant_iter_init_grid, and a coarse cell comes as one segment with the coarse cell's
 * bounds (fewer, looser segments; still true bounds) when its (unscaled) majorant times the
 * ray's length in it is <= coarse_tau, or its max is <= coarse_ratio times the smallest max of
 * its blocks, or its blocks all hold the same constant value. coarse_tau == 0 and coarse_ratio
 * < 1: only empty coarse cells are merged (the segments of vbl_majorant_iter_init_grid);
 * coarse_tau < 0: no coarse level at all (the plain block walk, same non-empty segments). */
void vbl_majorant_iter_init_coarse(vbl_majorant_iter* iter, const vbl_majorant_grid* grid,
                                   const vbl_affine* world_to_index, vbl_vec3 origin, vbl_vec3 direction, double tmin,
                                   double tmax, double coarse_tau, double coarse_ratio);
/* The interval the iterator above would walk, without walking: 1 with the overlap [*t_enter,
 * *t_exit] of [tmin, tmax] with the grid's box (the `t` and `t_end` of a fresh iterator; the same
 * arithmetic), 0 when the iterator would have no segments. */
int vbl_majorant_iter_clip(const vbl_majorant_grid* grid, const vbl_affine* world_to_index, vbl_vec3 origin,
                           vbl_vec3 direction, double tmin, double tmax, double* t_enter, double* t_exit);
/* Returns 1 and fills `segment`, or 0 when the ray has left the grid or passed tmax. */
int vbl_majorant_iter_next(vbl_majorant_iter* iter, vbl_majorant_segment* segment);

/* ---- internals: the step, inline for the tracking loops (extinction.c) -------------------- */

/* The coarse cell of `cell`: crossed in one step if it qualifies (majorant_iter.c).
 * Returns -1 (descend: walk its blocks), 0 (crossed, zero length) or 1 (segment filled). */
int vbl_majorant_iter_coarse_step(vbl_majorant_iter* it, vbl_majorant_segment* segment);

/* The t of the next block boundary along `axis` (step[axis] != 0), from the ray (no drift). */
static inline double vbl_majorant_iter_boundary(const vbl_majorant_iter* it, int axis)
{
    return ((double)(it->cell[axis] + (it->step[axis] > 0)) - it->org[axis]) * it->inv_dir[axis];
}

/* vbl_majorant_iter_next. A step: the nearest boundary's axis (ties to the lower axis), an
 * integer index update, one boundary. (A branchless axis choice measured no faster.) */
static inline int vbl_majorant_iter_next_inline(vbl_majorant_iter* it, vbl_majorant_segment* segment)
{
    const vbl_majorant_grid* g = it->grid;
    while (!it->done) {
        if (it->coarse_check) {
            it->coarse_check = 0;
            /* inline pre-check: without merging only an empty coarse cell is crossed whole */
            int cross = it->coarse_merge;
            if (!cross) {
                const int L = VBL_MAJORANT_COARSE_LOG2;
                const size_t ci = (size_t)(it->cell[0] >> L) +
                                  (size_t)g->coarse_dims[0] * ((size_t)(it->cell[1] >> L) +
                                                               (size_t)g->coarse_dims[1] * (size_t)(it->cell[2] >> L));
                cross = g->coarse_max[ci] == 0.0f && g->coarse_min[ci] == 0.0f;
            }
            if (cross) {
                int r = vbl_majorant_iter_coarse_step(it, segment);
                if (r == 1) return 1;
                if (r == 0) continue;
            }
        }
        /* the axis of the nearest boundary, ties to the lower axis */
        int axis = 0;
        if (it->t_next[1] < it->t_next[axis]) axis = 1;
        if (it->t_next[2] < it->t_next[axis]) axis = 2;
        const double t_cross = it->t_next[axis];
        double t1 = t_cross < it->t_end ? t_cross : it->t_end;
        if (t1 < it->t) t1 = it->t;
        const size_t index = it->index;
        const double t0 = it->t;
        it->steps++;
        if (t_cross < it->t_end) {
            const int old = it->cell[axis];
            const int cell = old + it->step[axis];
            it->cell[axis] = cell;
            if ((unsigned)cell >= (unsigned)g->dims[axis]) {
                it->done = 1;
            } else {
                it->index = index + (size_t)it->stride[axis];
                /* step[axis] != 0 here (a zero component never has the nearest boundary) */
                it->t_next[axis] = vbl_majorant_iter_boundary(it, axis);
                /* a new coarse cell is examined before its first block */
                it->coarse_check = (old >> VBL_MAJORANT_COARSE_LOG2) != (cell >> VBL_MAJORANT_COARSE_LOG2) &&
                                   g->coarse_max != NULL;
            }
            /* A boundary that rounding placed behind the current t is crossed at once. */
            it->t = t1;
        } else {
            it->done = 1;
            it->t = it->t_end;
        }
        if (t1 > t0) {
            segment->t0 = t0;
            segment->t1 = t1;
            segment->majorant = g->max_density[index];
            segment->minorant = g->min_density[index];
            return 1;
        }
    }
    return 0;
}


#endif
