/* Film: per-pixel double accumulators during a render (one RGB sum per transport class plus
 * AOV sums), turned into the float layers of the public vbl_film at the end. */
#ifndef VBL_RENDER_FILM_H
#define VBL_RENDER_FILM_H

#include "transport/common/estimator.h"

typedef struct vbl_pixel_accum {
    double L[VBL_CLASS_COUNT][3]; /* sums over camera samples */
    double alpha;                 /* sum of 1 - T(camera ray) estimates */
    double depth, depth_hits;     /* sum of first-collision distances, and their count */
    double var_sum[3], var_sq[3]; /* beauty sums / squared sums over independent units */
    double var_n;                 /* number of independent units */
    double samples;               /* camera samples */
} vbl_pixel_accum;

#define VBL_FILM_MAX_LAYERS 32

typedef struct vbl_film_layer_data {
    char name[32];
    int channels;
    const char* channel_names[4]; /* into channel_storage */
    char channel_storage[4][16];
    float* pixels;
} vbl_film_layer_data;

struct vbl_film {
    int refcount;
    int width, height;
    int layer_count;
    vbl_film_layer_data layers[VBL_FILM_MAX_LAYERS];
    vbl_film_stats stats;
};

/* Which layers a scene + options can produce. */
typedef struct vbl_film_layout {
    int transport[VBL_CLASS_COUNT];
    int depth;
    int transparent;  /* options.transparent: the beauty leaves out the background class */
    int opaque_alpha; /* a background is in the beauty: A = 1 everywhere */
} vbl_film_layout;

void vbl_film_layout_for(const vbl_scene* scene, const vbl_render_options* options, vbl_film_layout* layout);

/* 1 if class c enters the beauty of a film (transparent: not the background). */
static inline int vbl_film_class_in_beauty(int c, int transparent)
{
    return !(transparent && c == VBL_CLASS_BACKGROUND);
}

/* The totals (VBL_FILM_TOTAL_*): name and member classes. */
#define VBL_FILM_TOTAL_COUNT 2
const char* vbl_film_total_name(int total);
int vbl_film_total_has_class(int total, int transport_class);
/* Adds (or, for a film that has them, recomputes) the total layers as float sums, in class
 * order, of the film's class layers; a total none of whose classes the film has is left out. */
vbl_result vbl_film_compute_totals(vbl_film* film);

/* Builds the float film from the accumulators (image = running mean). Beauty RGB is the float
 * sum, in class order, of the produced transport layers' float values (without the background
 * when layout->transparent), so they add up to it exactly; beauty A is alpha (1 with
 * layout->opaque_alpha); Z of pixels without a hit is VBL_FILM_Z_MISS; then the totals. */
vbl_result vbl_film_build(const vbl_pixel_accum* accum, int width, int height, const vbl_film_layout* layout,
                          const vbl_film_stats* stats, vbl_film** out_film);

#endif
