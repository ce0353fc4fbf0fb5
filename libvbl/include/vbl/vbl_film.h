/* libvbl films beyond reading a render's: the transport classes (one layer each), films built
 * from pixels (an EXR read back, a checkpoint), and merging films of disjoint pass ranges into
 * the film one render of all their passes gives (split rendering, farms, resume).
 *
 *   const vbl_film* parts[2] = {passes_0_to_3, passes_4_to_7};
 *   vbl_film* all;  vbl_film_merge(parts, 2, &all);   // = vbl_render of passes 0..7, to float rounding
 *
 * Layer names (docs/readme/output.md, "Layers", maps them to Cycles passes and LPE AOVs): "" the
 * beauty R,G,B,A; one layer per transport class (vbl_transport_class_name); the totals
 * "volume_indirect" and "surface_indirect" (VBL_FILM_TOTAL_*); "Z"; "samples" (Y); "variance"
 * (R,G,B). Included by vbl.h. */
#ifndef VBL_FILM_H
#define VBL_FILM_H

#include "vbl/vbl_render.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- transport classes ----------------------------------------------------------------- */

/* Light-transport classes = film layers; they sum to the beauty, in this order (with
 * options.transparent the beauty leaves out `background`). A class is named by the last two path
 * vertices before the camera: `surface_*` classes end on a surface seen by the camera, `volume_*`
 * on a medium vertex. Emitted light: `background` holds the light sources seen directly (the
 * environment and visible quad lights, attenuated by the media in front of them: Cycles' Env
 * pass plus lamps seen by the camera); light emitted by the media is `volume_emission` (Cycles'
 * Emit pass of a volume). There is no layer "emission" any more (before 0.x it held what
 * `background` holds). */
typedef enum vbl_transport_class {
    VBL_CLASS_BACKGROUND = 0,           /* environment and visible lights seen directly (attenuated) */
    VBL_CLASS_SURFACE_DIRECT = 1,       /* camera-visible surface lit directly */
    VBL_CLASS_VOLUME_DIRECT = 2,        /* scattered exactly once in the media */
    VBL_CLASS_SURFACE_FROM_SURFACE = 3, /* camera-visible surface lit by a surface bounce */
    VBL_CLASS_SURFACE_FROM_VOLUME = 4,  /* camera-visible surface lit by medium scattering */
    VBL_CLASS_VOLUME_FROM_SURFACE = 5,  /* medium vertex lit by a surface bounce */
    VBL_CLASS_VOLUME_FROM_VOLUME = 6,   /* scattered two or more times, last two in the media */
    VBL_CLASS_VOLUME_EMISSION = 7,      /* light emitted by the media seen directly (attenuated) */
    VBL_CLASS_COUNT = 8
} vbl_transport_class;

/* The old name of VBL_CLASS_BACKGROUND (source compatibility; the layer is "background"). */
#define VBL_CLASS_EMISSION VBL_CLASS_BACKGROUND

/* Totals, film layers of their own computed as exact float sums of their classes (present when
 * one of the classes is): "volume_indirect" = volume_from_surface + volume_from_volume,
 * "surface_indirect" = surface_from_surface + surface_from_volume (Cycles' Volume/Diffuse
 * Indirect). They are not transport classes: do not add them to the beauty. */
#define VBL_FILM_TOTAL_VOLUME_INDIRECT "volume_indirect"   /* volume_from_surface + volume_from_volume */
#define VBL_FILM_TOTAL_SURFACE_INDIRECT "surface_indirect" /* surface_from_surface + surface_from_volume */

/* Z of a pixel where no camera sample hit anything (no collision in the media, no surface): a
 * large depth, as Cycles writes for the background (Nuke's ZDefocus and deep tools read it as
 * infinitely far). */
#define VBL_FILM_Z_MISS 1.0e10f

/* The layer name of a class ("background", "surface_direct", "volume_direct", ...); NULL out of range. */
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
 *   Z:        sum n_i A_i Z_i / sum n_i A_i over films with 0 < Z_i < VBL_FILM_Z_MISS (collision
 *             counts are not stored: approximate); no such film: VBL_FILM_Z_MISS if every film
 *             missed there, else sum n_i Z_i / N
 *   beauty R,G,B: the float sum of the merged transport layers in class order (without
 *             `background` for transparent films), so they still sum to it exactly; the totals
 *             volume_indirect / surface_indirect are re-summed the same way.
 * Sums are in double, so the result is the single render's film to float rounding (each value
 * within a few float ulps), not bit-identical. The films must have the same size, layers and
 * channels, method, spp, light paths, seed and transparency, and disjoint pass ranges (first_pass .. first_pass
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
