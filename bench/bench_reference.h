/* What the error-vs-time benchmarks share (bench_curves.c, bench_blue_noise.c, bench_bn_media.c):
 * the nine compared layers, a long pt reference rendered as two independent halves and cached on
 * disk in one format, its own error (the floor), rMAE, list arguments and scene loading at the
 * bench resolution. Benchmarks only: exits with a message on a library error. */
#ifndef VBL_BENCH_REFERENCE_H
#define VBL_BENCH_REFERENCE_H

#include <stddef.h>

#include "vbl/vbl.h"

/* Paths the bench *.cmake files pass as compile definitions; these defaults (relative to the
 * source tree) serve a build that does not. */
#ifndef VBL_BENCH_DEFAULT_VDB
#define VBL_BENCH_DEFAULT_VDB "build/samples/cloud.vdb"
#endif
#ifndef VBL_BENCH_SOURCE_DIR
#define VBL_BENCH_SOURCE_DIR "."
#endif
#ifndef VBL_BENCH_CACHE_DIR
#define VBL_BENCH_CACHE_DIR "."
#endif

/* beauty, the 7 transport classes in EXR order, "medium" (beauty - emission) */
#define BENCH_LAYERS 9
#define BENCH_LAYER_MEDIUM 8
extern const char* const bench_layer_names[BENCH_LAYERS]; /* film layer names; "" is beauty */
const char* bench_layer_label(int layer);                 /* "beauty" for layer 0 */

typedef struct bench_reference {
    int n, width, height;      /* pixels */
    int present[BENCH_LAYERS]; /* layer in the reference film */
    float* halves;             /* [2][BENCH_LAYERS][n * 3] */
    float* ref;                /* [BENCH_LAYERS][n * 3]: mean of the halves */
    double floor_rmae[BENCH_LAYERS]; /* the reference's own rMAE, NAN where absent */
    double seconds;            /* pt time of both halves together */
    char key[2048];            /* the cache key (first line of the .txt) */
} bench_reference;

/* RGB of a layer into out[n * 3]; 0 (and zeros) when the film lacks it. */
int bench_film_rgb(const vbl_film* film, int layer, int n, float* out);
/* sum |img - ref| / sum |ref|; NAN for an all-zero reference. */
double bench_rmae(const float* img, const float* ref, int count);
/* 1 if `name` is an entry of the comma-separated list. */
int bench_in_list(const char* list, const char* name);
/* Loads source_dir/file with its VDB path replaced by vdb (NULL: as written) at width x height
 * (same field of view). `tool` prefixes the error message. */
vbl_scene* bench_load_scene(const char* tool, const char* source_dir, const char* file, const char* vdb, int width,
                            int height);

typedef struct bench_reference_request {
    const char* tool;      /* message prefix */
    const char* cache_dir; /* cache: cache_dir/bench_curves_ref_NAME_WxH.{raw,txt} */
    const char* name;      /* the scene's short name */
    const char* file;      /* the scene file as given to bench_load_scene */
    const char* vdb;       /* part of the key */
    int width, height, threads;
    double seconds;        /* pt seconds of both halves together */
    int any_cached;        /* 1: accept a cached reference of this file and resolution whatever its
                              VDB path and length (r->key then tells which) */
} bench_reference_request;

/* The cached reference with the request's key, or a new one rendered (pt, 4 spp passes, seeds
 * 4242 and 4242 + 7919) and written to a temporary name then renamed. Fills every field of r;
 * the caller frees r->halves and r->ref. */
void bench_reference_make(const vbl_scene* scene, const bench_reference_request* q, bench_reference* r);

#endif
