/* Combining renders of disjoint pass ranges (`vbl merge`, `vbl render --resume`): the identity
 * checks that refuse incompatible files (docs/readme/pipeline.md, "Split and merge"). The pixels
 * combine in the library (vbl_film_merge, vbl/vbl_film.h; EXR <-> film: exr_film.h). */
#ifndef VBL_CLI_MERGE_H
#define VBL_CLI_MERGE_H

#include <stddef.h>

#include "vbl_exr.h"

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
