/* Progressive render driver: passes with their own seed streams, OpenMP over 16x16 tiles
 * (dynamic schedule; every pixel's stream is vbl_rng_make(seed, pass, pixel) so the image never
 * depends on the thread count), running-mean film, alpha/Z AOVs, time limit and cancel. */
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "core/memory_limit.h"
#include "film/film.h"
#include "render/render_internal.h"
#include "render/render_limits.h"
#include "sampling/sobol.h"
#include "transport/common/estimator.h"
#include "render/hybrid.h"
#include "transport/path_tracing/pt.h"
#include "transport/path_tracing/pt_guide.h"
#include "transport/path_tracing/pt_light_focus.h"
#include "transport/path_tracing/pt_shadow_control.h"
#include "render/pixel_focus.h"
#include "transport/common/photon_trace.h"

#define VBL_TILE 16

/* The options table's validator (render/options.c) plus the scene. */
static vbl_result vbl_render_validate(const vbl_scene* scene, const vbl_render_options* o)
{
    if (!scene || !o) return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_render: NULL argument");
    return vbl_render_options_validate(o);
}

/* Single estimates of T need an uncached estimator; the cached kinds map to their counterparts
 * (both unbiased) and stay in options.transmittance for methods that build caches. */
/* The estimators that transport the light of emissive media (docs/readme/emission.md): pt, and
 * the virtual-light and beam methods through photons from the media and
 * vbl_camera_media_emission. Others (test estimators) refuse emissive scenes. */
static int vbl_estimator_renders_emission(const vbl_estimator* est)
{
    static const char* const names[] = {"pt", "vpl", "vrl", "vbl", "beams"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; ++i)
        if (strcmp(est->name, names[i]) == 0) return 1;
    return 0;
}

static vbl_transmittance_estimator vbl_uncached(vbl_transmittance_estimator e)
{
    if (e == VBL_TRANSMITTANCE_CACHED_DELTA) return VBL_TRANSMITTANCE_DELTA_TRACKING;
    if (e == VBL_TRANSMITTANCE_CACHED_RATIO) return VBL_TRANSMITTANCE_RATIO_TRACKING;
    return e;
}

static void vbl_render_pixel(const vbl_render_context* ctx, const vbl_estimator* est, const void* store,
                             vbl_thread_state* ts, int px, int py, vbl_pixel_accum* acc)
{
    const vbl_camera* cam = &ctx->scene->camera;
    uint64_t pixel_index = (uint64_t)py * (uint64_t)cam->width + (uint64_t)px;
    vbl_rng rng = vbl_rng_make(ctx->options.seed, ctx->pass, pixel_index);
    const int spp = ctx->options.spp;
    double pass_beauty[3] = {0.0, 0.0, 0.0};
    /* pt.sampler = sobol: the pixel position is pair 0 of the pixel's Sobol sequence (sobol.h) */
    const int sobol = ctx->options.pt.sampler == VBL_PT_SAMPLER_SOBOL && est->camera_sample == vbl_pt_camera_sample;
    const uint64_t pixel_key = sobol ? vbl_sobol_key(ctx->options.seed, pixel_index, 0u, 0u) : 0u;
    /* the estimator's own AOVs (pt's camera walk) instead of a transmittance and a flight here */
    const int est_aovs = est->camera_aovs && est->camera_aovs(ctx, store);
    /* pixel_focus: this pixel holds a point light's image (pixel_focus.h) */
    const vbl_pixel_focus* focus = ctx->pixel_foci ? vbl_pixel_foci_find(ctx->pixel_foci, px, py) : NULL;
    for (int s = 0; s < spp; ++s) {
        if ((s & 15) == 15 && vbl_render_stop_requested(ctx)) return; /* the driver drops the pass */
        vbl_camera_sample cs;
        cs.px = px;
        cs.py = py;
        cs.pixel_index = pixel_index;
        cs.sample_index = (uint32_t)((uint64_t)ctx->pass * (uint64_t)spp + (uint64_t)s);
        double u, v, weight = 1.0; /* weight: 1 / the position's density (pixel_focus) */
        if (sobol) {
            vbl_sobol_pair(pixel_key, cs.sample_index, &u, &v);
        } else {
            u = vbl_rng_uniform(&rng);
            v = vbl_rng_uniform(&rng);
        }
        cs.sx = px + u;
        cs.sy = py + v;
        if (focus) weight = vbl_pixel_focus_sample(focus, vbl_rng_uniform(&rng), u, v, &rng, &cs.sx, &cs.sy);
        if (ctx->scene->motion && ctx->options.motion_blur) {
            /* motion blur: the path's time, stratified over the pixel's spp samples of the pass */
            const vbl_scene* sc = ctx->scene;
            double u = ((double)s + vbl_rng_uniform(&rng)) / (double)spp;
            ts->cursor.time = sc->shutter_open + (sc->shutter_close - sc->shutter_open) * u;
            ts->emission.time = ts->cursor.time;
        }
        /* media transport along the camera ray stops at the first surface (cs.t_max) */
        const int surface_hit = vbl_camera_sample_ray(ctx->scene, &cs);

        /* AOVs: alpha = 1 on opaque surfaces, else 1 - T(camera ray); Z = the delta-tracked
         * first collision or the surface hit, whichever comes first */
        if (!est_aovs && (ctx->extinction->count > 0 || surface_hit)) {
            acc->alpha += weight * (surface_hit ? 1.0 : 1.0 - vbl_ctx_transmittance(ctx, ts, cs.origin, cs.direction,
                                                                                    INFINITY, &rng));
            double t = 0.0;
            const vbl_segment ray = vbl_segment_make(cs.origin, cs.direction, 0.0, cs.t_max);
            vbl_medium_point mp;
            if (ctx->extinction->count > 0 && vbl_ctx_free_flight_medium(ctx, ts, &ray, &rng, &t, &mp)) {
                acc->depth += weight * t;
                acc->depth_hits += weight;
            } else if (surface_hit) {
                acc->depth += weight * cs.t_max;
                acc->depth_hits += weight;
            }
        }

        vbl_sample_value value;
        memset(&value, 0, sizeof value);
        if (weight > 0.0) est->camera_sample(ctx, store, ts, &cs, &rng, &value);
        if (weight != 1.0) /* pixel_focus: the sample's weight (0 on the image itself, a null set) */
            for (int c = 0; c < VBL_CLASS_COUNT; ++c) value.L[c] = vbl_v3_scale(value.L[c], weight);
        if (est_aovs && weight > 0.0) {
            acc->alpha += weight * value.aovs.alpha;
            if (value.aovs.depth_hit) {
                acc->depth += weight * value.aovs.depth;
                acc->depth_hits += weight;
            }
        }
        double beauty[3] = {0.0, 0.0, 0.0};
        for (int c = 0; c < VBL_CLASS_COUNT; ++c) {
            acc->L[c][0] += value.L[c].x;
            acc->L[c][1] += value.L[c].y;
            acc->L[c][2] += value.L[c].z;
            if (!vbl_film_class_in_beauty(c, ctx->options.transparent)) continue; /* variance of the beauty */
            beauty[0] += value.L[c].x;
            beauty[1] += value.L[c].y;
            beauty[2] += value.L[c].z;
        }
        acc->samples += 1.0;
        if (est->correlated_samples) {
            for (int k = 0; k < 3; ++k) pass_beauty[k] += beauty[k];
        } else {
            for (int k = 0; k < 3; ++k) {
                acc->var_sum[k] += beauty[k];
                acc->var_sq[k] += beauty[k] * beauty[k];
            }
            acc->var_n += 1.0;
        }
    }
    if (est->correlated_samples) {
        for (int k = 0; k < 3; ++k) {
            double m = pass_beauty[k] / spp;
            acc->var_sum[k] += m;
            acc->var_sq[k] += m * m;
        }
        acc->var_n += 1.0;
    }
}

/* The cancel flag is set or the time limit has passed (estimator.h). */
int vbl_render_stop_requested(const vbl_render_context* ctx)
{
    const vbl_render_options* o = &ctx->options;
    if (ctx->stop_latch && *ctx->stop_latch) return 1;
    int stop = (o->cancel && *o->cancel) || (ctx->deadline > 0.0 && omp_get_wtime() >= ctx->deadline);
    if (stop && ctx->stop_latch) *ctx->stop_latch = 1;
    return stop;
}

/* What vbl_render_snapshot needs from inside the pass loop. */
typedef struct vbl_render_driver {
    const vbl_scene* scene;
    const vbl_render_options* options;
    const vbl_pixel_accum* accum;
    int passes_done;
    int threads;
    double start;
    const vbl_hybrid_plan* hybrid; /* render.hybrid, else NULL */
} vbl_render_driver;

static void vbl_render_fill_stats(const vbl_render_driver* d, vbl_film_stats* stats)
{
    memset(stats, 0, sizeof *stats);
    stats->size = sizeof *stats;
    stats->method = d->options->method;
    stats->passes = d->passes_done;
    stats->spp = d->options->spp;
    stats->light_paths = d->options->light_paths;
    stats->seed = d->options->seed;
    stats->threads = d->threads;
    stats->render_seconds = omp_get_wtime() - d->start;
    stats->first_pass = d->options->first_pass;
    stats->transparent = d->options->transparent != 0;
    if (d->hybrid) {
        stats->hybrid = (int)d->options->hybrid;
        stats->hybrid_pt_classes = (int)d->hybrid->pt_classes;
        stats->hybrid_pt_spp = d->hybrid->pt_spp;
    }
}

vbl_result vbl_render_snapshot(const vbl_render_progress* progress, vbl_film** out_film)
{
    if (out_film) *out_film = NULL;
    if (!progress || !out_film || !progress->driver)
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_render_snapshot: call it inside the pass callback");
    const vbl_render_driver* d = progress->driver;
    vbl_film_layout layout;
    vbl_film_layout_for(d->scene, d->options, &layout);
    vbl_film_stats stats;
    vbl_render_fill_stats(d, &stats);
    return vbl_film_build(d->accum, d->scene->camera.width, d->scene->camera.height, &layout, &stats, out_film);
}

vbl_result vbl_render(const vbl_scene* scene, const vbl_render_options* options, vbl_film** out_film)
{
    if (out_film) *out_film = NULL;
    vbl_result r = vbl_render_validate(scene, options);
    if (r) return r;
    const vbl_estimator* est = vbl_estimator_for(options->method);
    if (!est)
        return vbl_error(VBL_ERROR_UNSUPPORTED, "%s: render method '%s' is not implemented yet", scene->path,
                         vbl_render_method_name(options->method));
    return vbl_render_with_estimator(scene, options, est, out_film);
}

vbl_result vbl_render_with_estimator(const vbl_scene* scene, const vbl_render_options* options,
                                     const vbl_estimator* est, vbl_film** out_film)
{
    if (out_film) *out_film = NULL;
    vbl_result r = vbl_render_validate(scene, options);
    if (r) return r;
    if (!out_film || !est) return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_render: NULL argument");
    if ((r = vbl_limits_check_radius(scene, options, est->name))) return r;
    if (scene->motion && options->motion_blur && strcmp(est->name, "pt") != 0)
        return vbl_error(VBL_ERROR_UNSUPPORTED,
                         "%s: the scene has moving media (a velocity grid), whose motion blur only method 'pt' renders so "
                         "far (not '%s'); render with motion_blur = 0 (--motion-blur 0) for the frame's instant",
                         scene->path, est->name);
    if (scene->has_albedo_grids && strcmp(est->name, "pt") != 0 && (strcmp(est->name, "vrl") != 0 || scene->has_surfaces))
        return vbl_error(VBL_ERROR_UNSUPPORTED,
                         "%s: the scene has an albedo grid, which only methods 'pt' and 'vrl' (media only) render so far "
                         "(not '%s')",
                         scene->path, est->name);
    if (scene->has_emission && !vbl_estimator_renders_emission(est))
        return vbl_error(VBL_ERROR_UNSUPPORTED,
                         "%s: the scene has emissive media, which estimator '%s' does not render (pt, vpl, vrl, vbl "
                         "and beams do)",
                         scene->path, est->name);

    /* render.hybrid = auto (the default) combines where it can: not with pt (nothing to combine)
     * nor with light groups (not combined yet); hybrid = classes there is an error */
    const int pt_method = est->camera_sample == vbl_pt_camera_sample || options->method == VBL_RENDER_PT;
    const int groups = options->light_groups && scene->light_group_count > 0;
    const int hybrid = options->hybrid == VBL_HYBRID_AUTO && (pt_method || groups) ? VBL_HYBRID_OFF : options->hybrid;
    if (groups) {
        if (hybrid != VBL_HYBRID_OFF)
            return vbl_error(VBL_ERROR_UNSUPPORTED, "%s: hybrid and light_groups do not combine yet", scene->path);
        return vbl_render_light_groups(scene, options, est, out_film); /* one render per group */
    }

    vbl_render_context ctx;
    memset(&ctx, 0, sizeof ctx);
    ctx.scene = scene;
    ctx.extinction = &scene->extinction;
    vbl_extinction still; /* motion_blur = 0: the static field (no dilated majorants, no advection) */
    if (scene->motion && !options->motion_blur) {
        still = scene->extinction;
        for (int c = 0; c < still.count; ++c) {
            still.components[c].moving = NULL;
            memset(&still.components[c].velocity, 0, sizeof still.components[c].velocity);
        }
        ctx.extinction = &still;
    }
    ctx.options = *options;
    ctx.options.size = sizeof(vbl_render_options);
    ctx.options.light_paths = vbl_render_light_paths(scene, options); /* 0: the method's default */
    /* pt.sampler is method pt's (its Sobol pattern was measured there, and starts with the pixel
     * position, which only pt's camera samples take from it): the pt paths other methods trace for
     * some classes (pt_camera_classes.h, surface_gather.c's path extension, which may run several
     * times per camera sample and would reuse its Sobol points) keep independent streams */
    if (est->camera_sample != vbl_pt_camera_sample) ctx.options.pt.sampler = VBL_PT_SAMPLER_INDEPENDENT;
    ctx.tracking.estimator = vbl_uncached(options->transmittance);
    ctx.tracking.march_step = 0.0;
    ctx.tracking.use_global_majorant = 0;
    ctx.tracking.majorant_scale = options->transmittance_majorant_scale;
    ctx.threads = options->threads > 0 ? options->threads : omp_get_max_threads();
    if (ctx.threads < 1) ctx.threads = 1;
    /* pt.light_focus: the point/spot lights inside the media, once per render and before the hybrid
     * pilot and pt's pre-pass copy the context (pt_light_focus.h) */
    vbl_pt_light_focus light_focus;
    vbl_pt_light_focus_init(&ctx, &light_focus);
    if (light_focus.fraction > 0.0) ctx.pt_light_focus = &light_focus;
    /* render.hybrid: pt takes some classes (render/hybrid.h); auto runs its pilot here, before any
     * pass, with seeds of its own, so every pass range of a split render makes the same plan */
    vbl_hybrid_plan hybrid_plan;
    const double hybrid_start = omp_get_wtime(); /* the pilot counts towards time_limit and render_seconds */
    if (hybrid != VBL_HYBRID_OFF) {
        if ((r = vbl_hybrid_plan_make(&ctx, est, &hybrid_plan))) return r;
        ctx.hybrid = &hybrid_plan;
        est = &vbl_estimator_hybrid;
    }

    const int width = scene->camera.width, height = scene->camera.height;
    size_t pixel_count = (size_t)width * (size_t)height;
    /* The accumulators and their pass copy (a stoppable render) against the memory limit. */
    {
        char what[128];
        snprintf(what, sizeof what, "the accumulators of a %dx%d film", width, height);
        const uint64_t copies = options->cancel || options->time_limit > 0.0 ? 2u : 1u;
        const uint64_t bytes = (uint64_t)pixel_count * copies * sizeof(vbl_pixel_accum);
        if ((r = vbl_memory_check(bytes, scene->path, what)) != VBL_SUCCESS) return r;
    }
    vbl_pixel_accum* accum = calloc(pixel_count, sizeof *accum);
    if (!accum) return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory for a %dx%d film", scene->path, width, height);

    const int tiles_x = (width + VBL_TILE - 1) / VBL_TILE, tiles_y = (height + VBL_TILE - 1) / VBL_TILE;
    const int tile_count = tiles_x * tiles_y;
    double start = ctx.hybrid ? hybrid_start : omp_get_wtime();
    /* pt.guided_rr: the radiance cache's pre-pass, once per render (pt_guide.h) */
    vbl_pt_guide* guide = NULL;
    if (est->camera_sample == vbl_pt_camera_sample && options->pt.guided_rr) {
        if ((r = vbl_pt_guide_build(&ctx, &guide))) {
            free(accum);
            return r;
        }
        ctx.pt_guide = guide;
    }
    /* pixel_focus: the pixels holding the image of a point or spot light inside the media */
    vbl_pixel_foci pixel_foci;
    if (options->pixel_focus && ctx.extinction->count > 0) {
        vbl_vec3 lo, hi;
        const int has_box = vbl_scene_media_box(scene, &lo, &hi);
        vbl_pixel_foci_build(scene, has_box, lo, hi, &pixel_foci);
        if (pixel_foci.count > 0) ctx.pixel_foci = &pixel_foci;
    }
    /* vrl.light_guide: the camera-importance grid, once per render (photon_trace.h) */
    vbl_light_guide* light_guide = NULL;
    if ((options->method == VBL_RENDER_VRL || options->method == VBL_RENDER_VBL) && options->vrl.light_guide) {
        if ((r = vbl_light_guide_build(&ctx, &light_guide))) {
            free(accum);
            vbl_pt_guide_free(guide);
            vbl_light_guide_free(light_guide);
            return r;
        }
        ctx.light_guide = light_guide;
    }
    /* pt.shadow_control: the transmittance grids towards the distant lights, once per render
     * (pt_shadow_control.h); every method, since vrl, vbl and vpl take their single scattering
     * from pt's paths */
    vbl_sun_grid* sun_grids = NULL;
    if ((r = vbl_pt_shadow_control_build(&ctx, &sun_grids))) {
        free(accum);
        vbl_pt_guide_free(guide);
        vbl_light_guide_free(light_guide);
        return r;
    }
    ctx.sun_grids = sun_grids;
    volatile int stop_latch = 0;
    ctx.stop_latch = &stop_latch;
    int passes_done = 0, cancelled = 0, time_limited = 0, discarded = 0;
    int cut_in_light_phase = 0; /* the dropped pass stopped in pass_begin (light tracing, builds) */
    volatile int tiles_done = 0; /* of the dropped pass, for the message when no pass completed */
    vbl_render_driver driver = {scene, &ctx.options, accum, 0, ctx.threads, start, ctx.hybrid};
    /* Stopping inside a pass (cancel flag, time limit) restores the accumulators of the last
     * complete pass from this copy: the film never holds part of a pass. The time limit applies to
     * the first pass too: one stopped there leaves no complete pass and no film. */
    vbl_pixel_accum* backup = NULL;
    for (int pass = 0; pass < options->passes; ++pass) {
        double pass_start = omp_get_wtime();
        /* the first min_passes passes complete whatever the time */
        ctx.deadline = options->time_limit > 0.0 && passes_done >= options->min_passes ? start + options->time_limit : 0.0;
        const int stoppable = options->cancel || ctx.deadline > 0.0;
        ctx.pass = (uint32_t)(options->first_pass + pass); /* absolute pass: seeds and radii */
        if (stoppable && vbl_render_stop_requested(&ctx)) {
            if (options->cancel && *options->cancel) cancelled = 1;
            else time_limited = 1;
            break;
        }
        if (stoppable && passes_done > 0) {
            if (!backup && !(backup = malloc(pixel_count * sizeof *backup))) {
                free(accum);
                vbl_pt_guide_free(guide);
                vbl_light_guide_free(light_guide);
                vbl_pt_shadow_control_free(sun_grids, scene->light_count);
                return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory for the film's pass copy", scene->path);
            }
            memcpy(backup, accum, pixel_count * sizeof *backup);
        }
        void* store = NULL;
        if (est->pass_begin && (r = est->pass_begin(&ctx, &store))) {
            if (r == VBL_ERROR_INTERRUPTED && stoppable && vbl_render_stop_requested(&ctx)) {
                /* stopped in light tracing or a build: the pass_begin freed its store */
                vbl_clear_error();
                if (passes_done > 0) memcpy(accum, backup, pixel_count * sizeof *backup);
                discarded = 1;
                cut_in_light_phase = 1;
                if (options->cancel && *options->cancel) cancelled = 1;
                else time_limited = 1;
                break;
            }
            free(backup);
            free(accum);
            vbl_pt_guide_free(guide);
            vbl_light_guide_free(light_guide);
            vbl_pt_shadow_control_free(sun_grids, scene->light_count);
            return r;
        }
        volatile int stop_pass = 0;
        tiles_done = 0;
        /* No more workers than tiles: a film of one tile (16x16 or less) renders on one thread,
         * where the idle worker would only spin at the loop's barrier (libgomp's active wait),
         * ~17x the CPU of threads = 1 for small many-pass renders. Pixels do not depend on the
         * thread count, so the image is unchanged. */
        const int tile_threads = ctx.threads < tile_count ? ctx.threads : tile_count;
#pragma omp parallel num_threads(tile_threads)
        {
            vbl_thread_state ts;
            memset(&ts, 0, sizeof ts);
            vbl_extinction_cursor_init(&ts.cursor, ctx.extinction);
            if (scene->has_emission) vbl_emission_cursor_init(&ts.emission, scene);
#pragma omp for schedule(dynamic, 1)
            for (int tile = 0; tile < tile_count; ++tile) {
                int x0 = (tile % tiles_x) * VBL_TILE, y0 = (tile / tiles_x) * VBL_TILE;
                int x1 = x0 + VBL_TILE < width ? x0 + VBL_TILE : width;
                int y1 = y0 + VBL_TILE < height ? y0 + VBL_TILE : height;
                for (int y = y0; y < y1 && !stop_pass; ++y)
                    for (int x = x0; x < x1 && !stop_pass; ++x) {
                        if (stoppable && vbl_render_stop_requested(&ctx)) {
                            stop_pass = 1;
                            break;
                        }
                        vbl_render_pixel(&ctx, est, store, &ts, x, y, &accum[(size_t)y * width + x]);
                    }
                if (!stop_pass) {
#pragma omp atomic
                    tiles_done++;
                }
            }
        }
        /* a stop seen anywhere in the pass (a pixel's samples, a virtual-light loop) may have cut
         * the last pixels short: the latch drops the pass too */
        if (stop_latch) stop_pass = 1;
        if (est->pass_end) est->pass_end(&ctx, store);
        if (stop_pass) { /* drop the part of the pass rendered so far */
            if (passes_done > 0) memcpy(accum, backup, pixel_count * sizeof *backup);
            discarded = 1;
            if (options->cancel && *options->cancel) cancelled = 1;
            else time_limited = 1;
            break;
        }
        passes_done = pass + 1;
        driver.passes_done = passes_done;
        double now = omp_get_wtime();
        if (options->callback) {
            vbl_render_progress progress = {passes_done, options->passes, now - start, now - pass_start,
                                            (uint64_t)passes_done * (uint64_t)options->spp, options->first_pass,
                                            &driver};
            if (options->callback(&progress, options->callback_user_data)) {
                cancelled = pass + 1 < options->passes;
                break;
            }
        }
        if (options->time_limit > 0.0 && now - start >= options->time_limit && pass + 1 < options->passes &&
            passes_done >= options->min_passes) {
            time_limited = 1;
            break;
        }
    }
    free(backup);
    vbl_pt_guide_free(guide);
    vbl_light_guide_free(light_guide);
    vbl_pt_shadow_control_free(sun_grids, scene->light_count);
    if (passes_done == 0) { /* stopped inside the first pass: nothing to return */
        free(accum);
        const char* why = cancelled ? "render cancelled" : "time limit reached";
        if (cut_in_light_phase)
            return vbl_error(VBL_ERROR_INTERRUPTED,
                             "%s: %s during the first pass's light tracing (%d light paths; no pass completed)",
                             scene->path, why, options->light_paths);
        return vbl_error(VBL_ERROR_INTERRUPTED, "%s: %s during its first pass (%d of %d tiles done; no pass completed)",
                         scene->path, why, (int)tiles_done, tile_count);
    }

    vbl_film_layout layout;
    vbl_film_layout_for(scene, options, &layout);
    vbl_film_stats stats;
    vbl_render_fill_stats(&driver, &stats);
    stats.cancelled = cancelled;
    stats.time_limited = time_limited;
    stats.discarded_pass = discarded;
    r = vbl_film_build(accum, width, height, &layout, &stats, out_film);
    free(accum);
    if (r) return r;
    if (cancelled)
        return vbl_error(VBL_ERROR_INTERRUPTED, "%s: render stopped by the caller after %d of %d passes", scene->path,
                         passes_done, options->passes);
    return VBL_SUCCESS;
}
