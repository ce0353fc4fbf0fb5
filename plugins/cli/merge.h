/* Combining renders of disjoint pass ranges (`vbl merge`, `vbl render --resume`): per-channel
 * rules weighted by pass counts and the identity checks that refuse incompatible files
 * (docs/readme/pipeline.md, "Split and merge"). */
#ifndef VBL_CLI_MERGE_H
#define VBL_CLI_MERGE_H

#include <stddef.h>

#include "vbl_exr.h"

/* How a channel combines over inputs i with pass counts n_i (N = sum n_i, w_i = n_i / N). */
typedef enum vbl_merge_kind {
    VBL_MERGE_MEAN = 0,     /* transport layers, beauty A: sum w_i x_i */
    VBL_MERGE_SUM = 1,      /* samples: sum x_i */
    VBL_MERGE_VARIANCE = 2, /* variance of the mean: sum w_i^2 x_i (ranges independent) */
    VBL_MERGE_DEPTH = 3,    /* Z: weighted by n_i A_i over inputs with Z > 0 (collision counts are not
                               stored; the expected count is proportional to n_i A_i): approximate */
    VBL_MERGE_BEAUTY = 4    /* beauty R,G,B: recomputed as the float sum of the transport layers */
} vbl_merge_kind;

/* The kind of an EXR channel by full name ("R", "A", "Z", "samples.Y", "variance.G", "emission.B"). */
vbl_merge_kind vbl_merge_kind_of(const char* channel);

/* A channel's values with a stride in floats (planar: 1; interleaved: the channel count). */
typedef struct vbl_merge_view {
    const float* data;
    size_t stride;
} vbl_merge_view;

/* Combines `count` views of n values into out (stride out_stride) by `kind` (not BEAUTY).
 * `alpha` (DEPTH only, may be NULL or hold NULL data) are the inputs' beauty A channels. */
void vbl_merge_channel(vbl_merge_kind kind, int count, const int* passes, const vbl_merge_view* in,
                       const vbl_merge_view* alpha, size_t n, float* out, size_t out_stride);

/* The transport layers in film order; the beauty is their float sum in this order. */
#define VBL_MERGE_TRANSPORT_COUNT 7
extern const char* const vbl_merge_transport_order[VBL_MERGE_TRANSPORT_COUNT];

/* beauty[i*stride + k] = float sum over c (film order) of transport[c][k] (views with NULL data are
 * absent layers), for k = 0..2. */
void vbl_merge_resum_beauty(const vbl_merge_view transport[VBL_MERGE_TRANSPORT_COUNT][3], size_t n, float* beauty,
                            size_t stride);

/* Attributes that must agree between files of one render (scene hash, method, seed, spp, light
 * paths, render options hash, frame, media, colour space). */
#define VBL_MERGE_IDENTITY_COUNT 9
extern const char* const vbl_merge_identity_keys[VBL_MERGE_IDENTITY_COUNT];

typedef struct vbl_merge_identity {
    char values[VBL_MERGE_IDENTITY_COUNT][1024];
    int has[VBL_MERGE_IDENTITY_COUNT];
    int width, height;
} vbl_merge_identity;

void vbl_merge_identity_from_image(const vbl_exr_image* image, vbl_merge_identity* out);
void vbl_merge_identity_from_attributes(const vbl_exr_attribute* attrs, int count, int width, int height,
                                        vbl_merge_identity* out);
/* 1 for the keys other tools drop when they rewrite a file (oiio:ColorSpace): a file that lacks
 * one is not refused for it, a different value is. */
int vbl_merge_identity_droppable(int key);
/* 0 if equal (a droppable key may be absent on one side, an absent key equals ""); else 1 and "<path_b>: <key> = X but <path_a> has Y" in msg. */
int vbl_merge_identity_compare(const vbl_merge_identity* a, const char* path_a, const vbl_merge_identity* b,
                               const char* path_b, char* msg, size_t size);

#endif
