/* libvbl films beyond reading a render's: the transport classes (one layer each), films built
 * from pixels (an EXR read back, a checkpoint), and merging films of disjoint pass ranges into
 * the film one render of all their passes gives (split rendering, farms, resume).
 *
 *   const vbl_film* parts[2] = {passes_0_to_3, passes_4_to_7};
 *   vbl_film* all;  vbl_film_merge(parts, 2, &all);   // = vbl_render of passes 0..7, to float rounding
 *
 * Layer names (docs/readme/output.md, "Layers", maps them to Cycles passes and LPE AOVs): "" the
 * beauty R,G,B,A; one layer per transport class (vbl_transport_class_name); "Z"; "samples" (Y);
 * "variance" (R,G,B). Included by vbl.h. */
#ifndef VBL_FILM_H
#define VBL_FILM_H

#include "vbl/vbl_render.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- transport classes ----------------------------------------------------------------- */

/* Light-transport classes = film layers; they sum to the beauty, in this order. A class is named
 * by the last two path vertices before the camera: `surface_*` classes end on a surface seen by
 * the camera, `volume_*` on a medium vertex. */
typedef enum vbl_transport_class {
    VBL_CLASS_EMISSION = 0,             /* lights/environment seen directly (attenuated) */
    VBL_CLASS_SURFACE_DIRECT = 1,       /* camera-visible surface lit directly */
    VBL_CLASS_VOLUME_DIRECT = 2,        /* scattered exactly once in the media */
    VBL_CLASS_SURFACE_FROM_SURFACE = 3, /* camera-visible surface lit by a surface bounce */
    VBL_CLASS_SURFACE_FROM_VOLUME = 4,  /* camera-visible surface lit by medium scattering */
    VBL_CLASS_VOLUME_FROM_SURFACE = 5,  /* medium vertex lit by a surface bounce */
    VBL_CLASS_VOLUME_FROM_VOLUME = 6,   /* scattered two or more times, last two in the media */
    VBL_CLASS_VOLUME_EMISSION = 7,      /* light emitted by the media seen directly (attenuated) */
    VBL_CLASS_COUNT = 8
} vbl_transport_class;

/* The layer name of a class ("emission", "surface_direct", "volume_direct", ...); NULL out of range. */
VBL_API const char* vbl_transport_class_name(vbl_transport_class transport_class);
/* The class of a layer name; VBL_ERROR_INVALID_ARGUMENT for names that are not a class. */
VBL_API vbl_result vbl_transport_class_parse(const char* name, vbl_transport_class* out);

/* ---- films from pixels ----------------------------------------------------------------- */

/* An empty width x height film with these stats (stats->size set; passes >= 1, first_pass >= 0)
 * to fill with vbl_film_add_layer before it is shared (films are immutable once in use). */
VBL_API vbl_result vbl_film_create(int width, int height, const vbl_film_stats* stats, vbl_film** out_film);
/* Adds a layer: `channels` (1..4) interleaved floats per pixel, copied; channel_names like
 * {"R","G","B"} (NULL: "R","G","B","A" / "Y" for one channel, "Z" for the layer "Z"). Fails for a
 * name the film already has and for a film that is shared (retained). */
VBL_API vbl_result vbl_film_add_layer(vbl_film* film, const char* name, int channels,
                                      const char* const* channel_names, const float* pixels);

/* ---- merging --------------------------------------------------------------------------- */

/* How a layer combines over films i with pass counts n_i (N = sum n_i):
 *   transport layers, beauty A, other colour layers: sum n_i x_i / N (pass-weighted mean)
 *   samples:  sum x_i
 *   variance: sum n_i^2 x_i / N^2 (variance of the mean; the pass ranges are independent)
 *   Z:        sum n_i A_i Z_i / sum n_i A_i over films with Z_i > 0 (collision counts are not
 *             stored: approximate; no such film: sum n_i Z_i / N)
 *   beauty R,G,B: the float sum of the merged transport layers in class order, so they still sum
 *             to it exactly.
 * Sums are in double, so the result is the single render's film to float rounding (each value
 * within a few float ulps), not bit-identical. The films must have the same size, layers and
 * channels, method, spp, light paths and seed, and disjoint pass ranges (first_pass .. first_pass
 * + passes - 1), else VBL_ERROR_INVALID_ARGUMENT naming the film and what differs. The result's
 * stats: passes = N, first_pass = the smallest, render_seconds summed, cancelled / time_limited if
 * any film's is. Ranges with gaps merge (an unbiased image of fewer passes). */
VBL_API vbl_result vbl_film_merge(const vbl_film* const* films, int count, vbl_film** out_film);

/* The same, one film at a time (memory: the running double sums plus the film being added):
 * create, add each film, finish (the merger is then empty), destroy. */
typedef struct vbl_film_merger vbl_film_merger;
/* An empty merger. */
VBL_API vbl_result vbl_film_merger_create(vbl_film_merger** out_merger);
/* Adds one film's pixels to the running sums (checked against the films added before). */
VBL_API vbl_result vbl_film_merger_add(vbl_film_merger* merger, const vbl_film* film);
/* The merged film of everything added so far, as vbl_film_merge; the merger is then empty. */
VBL_API vbl_result vbl_film_merger_finish(vbl_film_merger* merger, vbl_film** out_film);
/* Frees the merger (NULL is fine). */
VBL_API void vbl_film_merger_destroy(vbl_film_merger* merger);

/* ---- checkpoint / resume --------------------------------------------------------------- */

/* Continues `base` (a film of this scene and options: same method, spp, light paths and seed,
 * base.first_pass == options->first_pass, fewer passes than options->passes; a checkpoint from
 * vbl_render_snapshot, an interrupted or time-limited render, or a file read back) to
 * options->passes passes: renders the passes it lacks with the single render's seeds and merges
 * (vbl_film_merge). The result equals vbl_render of all the passes to float rounding. A base with
 * all the passes already is returned retained. The pass callback sees only the passes rendered now
 * (progress->first_pass = where they start). Errors: VBL_ERROR_INVALID_ARGUMENT naming what differs;
 * vbl_render's. */
VBL_API vbl_result vbl_render_resume(const vbl_scene* scene, const vbl_render_options* options,
                                     const vbl_film* base, vbl_film** out_film);

#ifdef __cplusplus
}
#endif

#endif /* VBL_FILM_H */
