/* The extinction field of a scene's media: one or more volumes, each with a density scale and
 * an optional affine placement, whose coefficients add where they overlap. Every tracking
 * estimator and the renderer see media only through this interface. Extinction is grey
 * (sigma_t = density_scale * value); colour lives in the albedo. */
#ifndef VBL_VOLUME_EXTINCTION_H
#define VBL_VOLUME_EXTINCTION_H

#include "volume/advect.h"
#include "volume/grid_sample.h"
#include "volume/majorant_iter.h"

#define VBL_MAX_MEDIA 8

typedef struct vbl_medium_component {
    const vbl_volume* volume;
    double density_scale;        /* sigma_t = density_scale * grid value, per world unit */
    vbl_affine scene_to_volume;  /* scene world -> the volume's own world space */
    /* Motion blur (vbl_extinction_set_velocity): sampled at x - v(x) t when the cursor's time is
     * not 0; `moving` is the majorant grid dilated by the largest displacement (NULL: none, the
     * volume's own grid is used) */
    vbl_velocity_field velocity;
    vbl_majorant_grid* moving;
} vbl_medium_component;

typedef struct vbl_extinction {
    vbl_medium_component components[VBL_MAX_MEDIA];
    int count;
    double max_sigma_t;  /* global majorant: sum over components of scale * global max */
    /* Optical depth below which a coarse majorant cell is tracked as one segment (its majorant
     * x the ray's length in it, in sigma_t units): fewer DDA steps for at most this many extra
     * tentative collisions per coarse cell. 0: only empty coarse cells are merged (the block
     * walk's non-empty segments); < 0: no coarse level (the block walk). vbl_extinction_init
     * sets VBL_COARSE_DEPTH_DEFAULT. */
    double coarse_depth;
    /* A coarse cell whose max is <= coarse_ratio x its smallest block max is one segment too
     * (at most coarse_ratio x the block walk's tentative collisions in it). < 1: off.
     * vbl_extinction_init sets VBL_COARSE_RATIO_DEFAULT. */
    double coarse_ratio;
} vbl_extinction;

/* Defaults of vbl_extinction.coarse_depth / coarse_ratio: off, by measurement (docs/readme/volume.md,
 * "Hierarchical majorant walk"): neither the empty-cell skip nor merging paid on the sample scenes. */
#define VBL_COARSE_DEPTH_DEFAULT (-1.0)
#define VBL_COARSE_RATIO_DEFAULT 0.0

/* Builds an extinction field: init empties it; add appends a component (scene_to_volume NULL =
 * identity) and keeps max_sigma_t up to date. Returns VBL_ERROR_UNSUPPORTED past VBL_MAX_MEDIA and
 * VBL_ERROR_INVALID_ARGUMENT for a negative or non-finite density_scale. */
void vbl_extinction_init(vbl_extinction* ext);
vbl_result vbl_extinction_add(vbl_extinction* ext, const vbl_volume* volume, double density_scale,
                              const vbl_affine* scene_to_volume);

/* Gives component c a velocity field for motion blur over shutter times |t| <= max_time seconds:
 * builds its dilated majorant grid (each block the max/min over the blocks within the largest
 * displacement max_speed * max_time, the grid grown by as many blocks), so tracking at any time
 * in the shutter stays unbiased. Fails with VBL_ERROR_OUT_OF_MEMORY / VBL_ERROR_UNSUPPORTED. */
vbl_result vbl_extinction_set_velocity(vbl_extinction* ext, int c, const vbl_velocity_field* velocity, double max_time);
/* Frees what vbl_extinction_set_velocity built (the field stays usable without motion). */
void vbl_extinction_free(vbl_extinction* ext);

/* Per-thread state: one accessor per component, and a lookup counter. `time` (seconds relative
 * to the frame, 0 after init) is the time of the path being traced: with it non-zero, components
 * with a velocity field are sampled advected. */
typedef struct vbl_extinction_cursor {
    vbl_grid_accessor accessors[VBL_MAX_MEDIA];
    int count;
    double time;
    vbl_grid_accessor velocity[VBL_MAX_MEDIA][3];
} vbl_extinction_cursor;

void vbl_extinction_cursor_init(vbl_extinction_cursor* cursor, const vbl_extinction* ext);
uint64_t vbl_extinction_cursor_lookups(const vbl_extinction_cursor* cursor);

/* sigma_t at a scene-space point; if `per_component` is not NULL it receives each component's
 * sigma_t (for mixing albedo and phase functions by sigma_s). */
double vbl_extinction_eval(const vbl_extinction* ext, vbl_extinction_cursor* cursor, vbl_vec3 point,
                           double* per_component);

/* Merged majorant segments over all components along a scene-space ray (t is preserved by the
 * affine maps). Majorant/minorant are in sigma_t units (scaled and summed). */
typedef struct vbl_extinction_iter {
    const vbl_extinction* ext;
    vbl_majorant_iter iters[VBL_MAX_MEDIA];
    vbl_majorant_segment pending[VBL_MAX_MEDIA];
    int has_pending[VBL_MAX_MEDIA];
    double t, t_end;
    int use_global; /* 1: one segment [tmin,tmax] with the global majorant (parity tests) */
} vbl_extinction_iter;

void vbl_extinction_iter_init(vbl_extinction_iter* iter, const vbl_extinction* ext, vbl_vec3 origin,
                              vbl_vec3 direction, double tmin, double tmax, int use_global_majorant);
/* vbl_extinction_iter_next of several components or the global majorant (extinction.c). */
int vbl_extinction_iter_next_merged(vbl_extinction_iter* iter, vbl_majorant_segment* segment);

/* The next merged segment: 1 and `segment` filled, 0 past the end. Inline for the tracking loops:
 * one component is its block walk with the bounds scaled (no merging); several, or the global
 * majorant, go to the merge. */
static inline int vbl_extinction_iter_next(vbl_extinction_iter* iter, vbl_majorant_segment* segment)
{
    const vbl_extinction* ext = iter->ext;
    if (ext->count != 1 || iter->use_global) return vbl_extinction_iter_next_merged(iter, segment);
    const double s = ext->components[0].density_scale;
    if (!vbl_majorant_iter_next_inline(&iter->iters[0], segment)) return 0;
    segment->majorant *= s;
    segment->minorant *= s;
    return 1;
}

/* Conservative parameter interval where the ray overlaps any component's support; returns 0
 * if none. */
int vbl_extinction_ray_bounds(const vbl_extinction* ext, vbl_vec3 origin, vbl_vec3 direction,
                              double tmin, double tmax, double* t_enter, double* t_exit);

#endif
