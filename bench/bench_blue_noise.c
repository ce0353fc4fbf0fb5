/* Issue-8 benchmark: light-path surface VSLs against blue-noise VSLs
 * (Li et al. 2022), with and without the adaptive camera path
 * extension (eqs 6-9), at equal time and at equal virtual-light count, on the smoky room (media +
 * surfaces) and a surfaces-only glossy room (bench/scenes/glossy_room.json).
 *
 *   build/bench/bench_blue_noise [--budget 30] [--res 96x72] [--threads 2] [--scenes smoky_room,glossy_room]
 *       [--lp-paths 100] [--bn-lights 4096,16384,65536] [--bn-spp S1,S2,S3] [--noext-lights N]
 *       [--counts 1024,4096,16384] [--count-passes 1] [--count-spp 1] [--clamp-fraction 0.05]
 *       [--configs pt,lp,lp_clamp,bn_ext,bn_noext] [--count-configs lp,bn_ext,bn_noext]
 *       [--reference-scale 1] [--no-time] [--no-count] [--vdb build/samples/cloud.vdb]
 *       [--csv build/bench/blue_noise.csv]
 *
 * Configurations (every virtual-light one is method vpl, whose volume classes are the cheapest;
 * all of them use the same light_paths, --lp-paths, for the light-path stores at equal time):
 *   lp          light-path VSLs (vsl_placement light_paths, the default): the surface vertices of
 *               the pass's light paths, gathered as point lights (every VSL, every camera sample);
 *   lp_clamp    the same with vpl_clamp_distance = --clamp-fraction x the surfaces' bounding-box
 *               diagonal (1/w^2 -> 1/max(w^2, c^2): the usual firefly fix, biased);
 *   bn_ext_N    blue-noise VSLs (vsl_placement blue_noise, vsl_lights = N): N lights per pass from
 *               10 N camera candidates by sample elimination, 10 N light paths split among them,
 *               light + BSDF sample with MIS, and the path extension (eq 6, vsl_path_extension
 *               on). In media they also give volume_from_surface (one delta-tracking collision per
 *               camera sample, light + phase sample with MIS, path extension);
 *   bn_noext_N  the same with vsl_path_extension off (virtual lights only, w_v = 1);
 *   pt          path tracing, 4 spp per pass (equal time only): the baseline.
 *
 * Error: rMAE = sum |I - Iref| / sum |Iref| over all pixels and R, G, B of one layer (the
 * definition of bench_curves), for beauty, surface_from_surface (ssf: the layer the placement
 * changes) and volume_from_surface (vfs: media only); "sum ratio" = sum I / sum Iref (bias).
 *
 * Equal time: one progressive vbl_render per configuration; its pass callback takes
 * vbl_render_snapshot, computes the errors and records them with the render's elapsed time minus
 * the time spent in the callback; it stops after the pass that passes --budget seconds, or
 * earlier when one more pass would end past 1.25 x budget (large N: a pass of 65536 lights takes
 * most of the budget). The table gives the error at budget/8, /4, /2 and 1 (log-log interpolation
 * between snapshots; "-" before the first one; the last snapshot's error after the last one) and
 * the ratio to lp at the budget. bn_ext runs for every N in --bn-lights with the scene's spp per
 * pass (bench_scenes, or --bn-spp), then bn_noext at the N whose bn_ext had the lowest ssf error
 * (or --noext-lights). Each bn row also reports one pass's preparation time (pass 0's lights,
 * timed apart by calling the per-pass hook) and its share of the mean pass.
 *
 * Equal virtual-light count: N surface VSLs per pass for N in --counts, --count-passes passes
 * of --count-spp spp for every configuration. bn_*: vsl_lights = N, light_paths = --lp-paths.
 * lp*: light_paths = round(N / v), v = the mean surface VSLs per light path measured by
 * vbl_photon_trace_with_surfaces (photon_trace.h) over 4 passes of 2000 paths; the table reports
 * the actual mean VSL count of the passes rendered (the same passes traced again: the store
 * depends only on scene, seed and pass). lp_clamp is left out by default (--count-configs): in
 * the smoky room the lp light paths also drive the volume classes, and N = 16384 costs minutes.
 *
 * Reference: two independent pt halves, cached in the build directory with bench_curves' file
 * names, layout and key (bench_curves_ref_<scene>_<W>x<H>.raw / .txt), so one cache serves both
 * benchmarks (smoky_room: 600 s, bench_curves' setting; glossy_room: 560 s; x --reference-scale,
 * which is part of the cache key). Its own error rMAE(half A, half B) / 2 is printed as the floor.
 *
 * CSV columns: experiment,scene,config,lights,light_paths,vsl_per_pass,passes,spp,pass,seconds,
 * rmae_beauty,rmae_surface_from_surface,ratio_surface_from_surface,rmae_volume_from_surface,
 * ratio_volume_from_surface,ratio_beauty,prep_seconds. experiment "time" has one row per
 * snapshot, "count" one row per run, "reference_floor" one row per scene (seconds = the
 * reference's). */
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "geometry/surfaces.h"
#include "scene/scene.h"
#include "transport/common/estimator.h"
#include "transport/common/photon_trace.h"
#include "transport/surface/surface_gather.h"
#include "bench_reference.h"
#include "vbl/vbl.h"

/* ---- scenes and configurations ------------------------------------------------------------ */

#define MAX_BN 4 /* blue-noise light counts at equal time */

typedef struct bench_scene {
    const char* name;
    const char* file;         /* relative to the source tree */
    double reference_seconds; /* both halves together */
    int uses_vdb;             /* the scene's medium is the sample cloud (--vdb overrides it) */
    int bn_spp[MAX_BN];       /* equal time: spp per pass of bn_ext at N = bench_args.bn_lights[k] */
} bench_scene;

/* Equal time: every vpl configuration uses light_paths = 100 (the light-path stores of the volume
 * classes and, for lp*, the surface VSLs); bn_* set N = vsl_lights explicitly. spp per pass for
 * N = 4096, 16384, 65536 from 1-pass probes (96x72, 2 threads; the run prints the measured
 * preparation share). Preparing N lights took ~0.7, ~3.3 and ~14-22 s; a camera sample per pixel
 * costs ~0.15-0.4 s in the smoky room (the vpl volume classes) and ~0.01-0.06 s in the glossy
 * room, so the glossy room affords hundreds of spp a pass (prep ~25-35% of a pass) and the smoky
 * room only a few (prep ~40-70%). The gather's cost per camera sample grows with N too (glossy:
 * ~11, 16, 42-57 ms per spp), so 65536 x 1024 spp takes ~65 s a pass in the glossy room (one
 * pass, no value at 30 s; 128 spp fits 30 s). Supplementary runs with --bn-lights 256,1024,4096
 * found smaller N better at this budget (docs/readme/blue_noise_bench.md). */
static const bench_scene bench_scenes[] = {
    {"smoky_room", "samples/smoky_room.json", 600.0, 1, {4, 8, 16, 0}},
    {"glossy_room", "bench/scenes/glossy_room.json", 560.0, 0, {128, 512, 1024, 0}},
};

enum { CFG_PT, CFG_LP, CFG_LP_CLAMP, CFG_BN_EXT, CFG_BN_NOEXT, CFG_KINDS };
static const char* const cfg_names[CFG_KINDS] = {"pt", "lp", "lp_clamp", "bn_ext", "bn_noext"};

static int cfg_is_lp(int c) { return c == CFG_LP || c == CFG_LP_CLAMP; }
static int cfg_is_bn(int c) { return c == CFG_BN_EXT || c == CFG_BN_NOEXT; }

/* One rendered configuration: kind, blue-noise N (0 for pt/lp*) and spp per pass. */
typedef struct run_config {
    int kind, lights, spp;
    char name[32]; /* "lp", "bn_ext_16384", ... */
} run_config;

static run_config make_config(int kind, int lights, int spp)
{
    run_config c = {kind, lights, spp, {0}};
    if (cfg_is_bn(kind)) snprintf(c.name, sizeof c.name, "%s_%d", cfg_names[kind], lights);
    else snprintf(c.name, sizeof c.name, "%s", cfg_names[kind]);
    return c;
}

/* ---- layers and error -------------------------------------------------------------------- */

#define SSF 4 /* surface_from_surface's index in bench_layer_names */

static double sum_ratio(const float* img, const float* ref, int count)
{
    double si = 0.0, sr = 0.0;
    for (int i = 0; i < count; ++i) {
        si += img[i];
        sr += ref[i];
    }
    return sr != 0.0 ? si / sr : NAN;
}

/* The layers the tables report: beauty, surface_from_surface (the placement's layer) and
 * volume_from_surface (blue noise gives it too in media). */
enum { ERR_BEAUTY, ERR_SSF, ERR_VFS, ERR_COUNT };
static const int err_layer[ERR_COUNT] = {0, SSF, 6};

/* rMAE and sum ratio (sum I / sum Iref) per reported layer; NAN where the reference lacks it. */
typedef struct errors {
    double rmae[ERR_COUNT], ratio[ERR_COUNT];
} errors;

static errors film_errors(const vbl_film* film, const bench_reference* r, float* scratch)
{
    errors e;
    const int c = 3 * r->n;
    for (int k = 0; k < ERR_COUNT; ++k) {
        const int l = err_layer[k];
        e.rmae[k] = e.ratio[k] = NAN;
        if (!r->present[l]) continue;
        bench_film_rgb(film, l, r->n, scratch);
        e.rmae[k] = bench_rmae(scratch, r->ref + (size_t)l * c, c);
        e.ratio[k] = sum_ratio(scratch, r->ref + (size_t)l * c, c);
    }
    return e;
}

/* ---- arguments --------------------------------------------------------------------------- */

#define MAX_COUNTS 8

typedef struct bench_args {
    const char* vdb;
    const char* csv;
    int width, height, threads;
    double budget, clamp_fraction, reference_scale;
    int lp_paths;                    /* light_paths of every vpl configuration at equal time */
    int bn_lights[MAX_BN], bn_n;     /* equal time: blue-noise N (vsl_lights) */
    int bn_spp[MAX_BN], bn_spp_n;    /* equal time: spp per pass for each N (none: the scene's) */
    int noext_lights;                /* equal time: bn_noext's N (0: bn_ext's best) */
    char scenes[256], configs[256], count_configs[256];
    int counts[MAX_COUNTS], count_n;
    int count_passes, count_spp;
    int time_on, count_on;
} bench_args;

/* A comma-separated list of positive integers into out[max]; returns the count (0: invalid). */
static int parse_int_list(const char* v, int* out, int max)
{
    int n = 0;
    for (const char* s = v; *s && n < max;) {
        int x = atoi(s);
        if (x < 1) return 0;
        out[n++] = x;
        const char* e = strchr(s, ',');
        if (!e) break;
        s = e + 1;
    }
    return n;
}

static vbl_scene* load_scene(const bench_args* a, const bench_scene* s)
{
    return bench_load_scene("bench_blue_noise", VBL_BENCH_SOURCE_DIR, s->file, s->uses_vdb ? a->vdb : NULL, a->width,
                            a->height);
}

/* ---- reference (bench_reference.h, shared with bench_curves) ----------------------------- */

static void make_reference(const vbl_scene* scene, const bench_args* a, const bench_scene* s, bench_reference* r)
{
    bench_reference_request q = {"bench_blue_noise", VBL_BENCH_CACHE_DIR, s->name, s->file, a->vdb, a->width,
                                 a->height, a->threads, s->reference_seconds * a->reference_scale, 0};
    bench_reference_make(scene, &q, r);
    printf("# reference %s own rMAE (floor): surface_from_surface %.4f, beauty %.4f\n", s->name, r->floor_rmae[SSF],
           r->floor_rmae[0]);
}

/* ---- configurations ---------------------------------------------------------------------- */

/* Options of configuration c: light_paths for the light-path stores (lp*: also the surface
 * VSLs), c.lights = vsl_lights for bn_*, c.spp camera samples per pass. */
static vbl_render_options config_options(const vbl_scene* scene, const bench_args* a, run_config c, int light_paths,
                                         double clamp)
{
    vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
    vbl_scene_render_options(scene, &o);
    o.threads = a->threads;
    /* one seed for every vpl configuration: the same light paths (common random numbers) */
    o.seed = c.kind == CFG_PT ? 1000003u : 1000034u;
    o.method = c.kind == CFG_PT ? VBL_RENDER_PT : VBL_RENDER_VPL;
    o.spp = c.spp;
    o.light_paths = c.kind == CFG_PT ? 0 : light_paths;
    o.vpl.clamp_distance = c.kind == CFG_LP_CLAMP ? clamp : 0.0;
    o.vsl.placement = cfg_is_bn(c.kind) ? VBL_VSL_PLACEMENT_BLUE_NOISE : VBL_VSL_PLACEMENT_LIGHT_PATHS;
    o.vsl.path_extension = c.kind == CFG_BN_NOEXT ? VBL_VSL_PATH_EXTENSION_OFF : VBL_VSL_PATH_EXTENSION_ON;
    o.vsl.lights = cfg_is_bn(c.kind) ? c.lights : 0;
    return o;
}

/* The surfaces' bounding-box diagonal (the clamp distance's scale). */
static double surfaces_diagonal(const vbl_scene* scene)
{
    vbl_vec3 lo, hi;
    if (!scene->surfaces || !vbl_surfaces_bounds(scene->surfaces, &lo, &hi)) return 0.0;
    return vbl_v3_length(vbl_v3_sub(hi, lo));
}

/* Surface VSLs recorded by light_paths paths in each of passes first .. first + passes - 1
 * (the vpl store's photon settings; the store depends only on scene, seed and pass). Returns the
 * mean count per pass. */
static double mean_vsl_count(const vbl_scene* scene, const vbl_render_options* o, int first, int passes)
{
    vbl_render_context ctx;
    memset(&ctx, 0, sizeof ctx);
    ctx.scene = scene;
    ctx.extinction = &scene->extinction;
    ctx.options = *o;
    ctx.options.size = sizeof(vbl_render_options);
    ctx.tracking.estimator = VBL_TRANSMITTANCE_RATIO_TRACKING;
    ctx.threads = o->threads > 0 ? o->threads : omp_get_max_threads();
    vbl_photon_settings ps = {0, 1, 0, VBL_TRANSMITTANCE_CACHED_RATIO, 16}; /* vpl.c's settings */
    double total = 0.0;
    for (int p = first; p < first + passes; ++p) {
        ctx.pass = (uint32_t)p;
        vbl_photon_store store;
        memset(&store, 0, sizeof store);
        if (vbl_photon_trace_with_surfaces(&ctx, &ps, 1, &store)) {
            fprintf(stderr, "bench_blue_noise: %s\n", vbl_last_error_message());
            exit(1);
        }
        total += (double)store.surface_vsl_count;
        vbl_photon_store_free(&store);
    }
    return total / passes;
}

/* Seconds to prepare pass 0's blue-noise lights with options o (the per-pass hook vpl calls:
 * N lights from 10 N candidates, 10 N light paths; surface_gather.h). */
static double bn_prepare_seconds(const vbl_scene* scene, const vbl_render_options* o)
{
    vbl_render_context ctx;
    memset(&ctx, 0, sizeof ctx);
    ctx.scene = scene;
    ctx.extinction = &scene->extinction;
    ctx.options = *o;
    ctx.options.size = sizeof(vbl_render_options);
    ctx.tracking.estimator = VBL_TRANSMITTANCE_RATIO_TRACKING;
    ctx.threads = o->threads > 0 ? o->threads : omp_get_max_threads();
    vbl_surface_gather_settings gs;
    memset(&gs, 0, sizeof gs);
    double t0 = omp_get_wtime();
    if (vbl_surface_gather_blue_noise_begin(&ctx, &gs)) {
        fprintf(stderr, "bench_blue_noise: %s\n", vbl_last_error_message());
        exit(1);
    }
    double seconds = omp_get_wtime() - t0;
    vbl_surface_gather_blue_noise_end(&gs);
    return seconds;
}

/* ---- equal time: one progressive render, snapshots in the pass callback -------------------- */

typedef struct curve_point {
    int pass;
    double seconds;
    errors e;
} curve_point;

typedef struct curve {
    const bench_reference* ref;
    double budget;
    double overhead; /* seconds spent in this callback so far */
    double next_record;
    float* img;
    curve_point* points;
    int count, capacity;
} curve;

static void curve_add(curve* c, int pass, double seconds, const vbl_film* film)
{
    if (c->count == c->capacity) {
        c->capacity = c->capacity ? 2 * c->capacity : 64;
        c->points = realloc(c->points, sizeof *c->points * (size_t)c->capacity);
        if (!c->points) exit(1);
    }
    curve_point* p = &c->points[c->count++];
    p->pass = pass;
    p->seconds = seconds;
    p->e = film_errors(film, c->ref, c->img);
}

static int on_pass(const vbl_render_progress* progress, void* user)
{
    curve* c = user;
    double t0 = omp_get_wtime();
    double seconds = progress->elapsed_seconds - c->overhead;
    /* stop after the pass that reaches the budget, or earlier when one more pass would end past
     * 1.25 x budget (the large-N passes); the error at later fixed times is then the last one */
    int stop = seconds >= c->budget || seconds + progress->pass_seconds > 1.25 * c->budget;
    /* every pass up to 32, then passes ~4% apart, and the last one */
    if (progress->pass <= 32 || progress->pass >= c->next_record || stop) {
        vbl_film* film = NULL;
        if (vbl_render_snapshot(progress, &film)) {
            fprintf(stderr, "bench_blue_noise: %s\n", vbl_last_error_message());
            exit(1);
        }
        curve_add(c, progress->pass, seconds, film);
        vbl_film_release(film);
        c->next_record = progress->pass * 1.04;
    }
    c->overhead += omp_get_wtime() - t0;
    return stop;
}

/* A curve's error (ERR_*) at time t, log-log between the snapshots around it; NAN before the
 * first snapshot, the last snapshot's error after it. */
static double error_at(const curve* c, double t, int k)
{
    for (int i = 0; i < c->count; ++i) {
        const curve_point* b = &c->points[i];
        if (b->seconds < t) continue;
        double eb = b->e.rmae[k];
        if (b->seconds == t) return eb;
        if (i == 0) return NAN;
        const curve_point* p = &c->points[i - 1];
        double ep = p->e.rmae[k];
        double f = (log(t) - log(p->seconds)) / (log(b->seconds) - log(p->seconds));
        return exp(log(ep) + f * (log(eb) - log(ep)));
    }
    return c->count ? c->points[c->count - 1].e.rmae[k] : NAN;
}

static void csv_row(FILE* csv, const char* experiment, const char* scene, const run_config* cfg, int light_paths,
                    double vsl_per_pass, int passes, int pass, double seconds, const errors* e, double prep)
{
    fprintf(csv, "%s,%s,%s,%d,%d,%.1f,%d,%d,%d,%.4f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.4f\n", experiment, scene, cfg->name,
            cfg->lights, light_paths, vsl_per_pass, passes, cfg->spp, pass, seconds, e->rmae[ERR_BEAUTY],
            e->rmae[ERR_SSF], e->ratio[ERR_SSF], e->rmae[ERR_VFS], e->ratio[ERR_VFS], e->ratio[ERR_BEAUTY], prep);
}

typedef struct time_result {
    int ok, passes, light_paths;
    run_config cfg;
    double seconds, vsl_per_pass, prep_seconds; /* prep: one pass's blue-noise preparation */
    double at[ERR_COUNT][4];                    /* rMAE at budget / 8, / 4, / 2, 1 */
    errors end;
} time_result;

static void run_time(const vbl_scene* scene, const bench_args* a, const bench_reference* ref, const bench_scene* bs,
                     run_config cfg, double clamp, FILE* csv, time_result* out)
{
    memset(out, 0, sizeof *out);
    out->cfg = cfg;
    curve c;
    memset(&c, 0, sizeof c);
    c.ref = ref;
    c.budget = a->budget;
    c.img = malloc(sizeof(float) * 3 * (size_t)ref->n);
    if (!c.img) exit(1);
    vbl_render_options o = config_options(scene, a, cfg, a->lp_paths, clamp);
    o.passes = 1 << 30;
    o.callback = on_pass;
    o.callback_user_data = &c;
    vbl_film* film = NULL;
    vbl_result r = vbl_render(scene, &o, &film);
    if (film) vbl_film_release(film);
    if ((r && r != VBL_ERROR_INTERRUPTED) || c.count == 0) {
        printf("# %s %s: skipped (%s)\n", bs->name, cfg.name, r ? vbl_last_error_message() : "no pass");
        free(c.img);
        free(c.points);
        return;
    }
    const curve_point* last = &c.points[c.count - 1];
    out->ok = 1;
    out->passes = last->pass;
    out->seconds = last->seconds;
    out->end = last->e;
    out->light_paths = o.light_paths;
    for (int k = 0; k < ERR_COUNT; ++k)
        for (int j = 0; j < 4; ++j) out->at[k][j] = error_at(&c, a->budget / (double)(8 >> j), k);
    /* lp: the surface VSLs of the first 4 passes; bn: N lights exactly */
    out->vsl_per_pass = cfg_is_lp(cfg.kind) ? mean_vsl_count(scene, &o, 0, 4) : (double)cfg.lights;
    out->prep_seconds = cfg_is_bn(cfg.kind) ? bn_prepare_seconds(scene, &o) : 0.0;
    for (int i = 0; i < c.count; ++i) {
        const curve_point* p = &c.points[i];
        csv_row(csv, "time", bs->name, &cfg, o.light_paths, out->vsl_per_pass, p->pass, p->pass, p->seconds, &p->e,
                out->prep_seconds);
    }
    fflush(csv);
    free(c.img);
    free(c.points);
}

/* ---- equal virtual-light count: fixed passes and spp ------------------------------------- */

typedef struct count_result {
    int ok, light_paths;
    run_config cfg;
    double vsl_per_pass, seconds;
    errors e;
} count_result;

/* N surface VSLs per pass: lp*: light_paths = round(N / v); bn_*: vsl_lights = N with the same
 * light_paths as at equal time (--lp-paths) for the volume classes' stores. */
static void run_count(const vbl_scene* scene, const bench_args* a, const bench_reference* ref, const bench_scene* bs,
                      run_config cfg, int lights, double vsl_per_path, double clamp, FILE* csv, count_result* out)
{
    memset(out, 0, sizeof *out);
    out->cfg = cfg;
    int paths = cfg_is_lp(cfg.kind) ? (int)fmax(1.0, floor(lights / vsl_per_path + 0.5)) : a->lp_paths;
    vbl_render_options o = config_options(scene, a, cfg, paths, clamp);
    o.passes = a->count_passes;
    vbl_film* film = NULL;
    double t0 = omp_get_wtime();
    vbl_result r = vbl_render(scene, &o, &film);
    double seconds = omp_get_wtime() - t0;
    if (r || !film) {
        printf("# %s %s N=%d: skipped (%s)\n", bs->name, cfg.name, lights, vbl_last_error_message());
        if (film) vbl_film_release(film);
        return;
    }
    float* img = malloc(sizeof(float) * 3 * (size_t)ref->n);
    if (!img) exit(1);
    out->ok = 1;
    out->light_paths = paths;
    out->seconds = seconds;
    out->e = film_errors(film, ref, img);
    out->vsl_per_pass = cfg_is_lp(cfg.kind) ? mean_vsl_count(scene, &o, 0, o.passes) : (double)lights;
    vbl_film_release(film);
    free(img);
    run_config row = cfg;
    row.lights = lights; /* the CSV's N column: the count this row belongs to */
    csv_row(csv, "count", bs->name, &row, paths, out->vsl_per_pass, o.passes, o.passes, seconds, &out->e, 0.0);
    fflush(csv);
}

/* ---- tables ------------------------------------------------------------------------------ */

/* "%.4f", or "-" for NAN (a layer the scene lacks). */
static const char* fmt4(char* buf, size_t size, double v)
{
    if (isnan(v)) snprintf(buf, size, "-");
    else snprintf(buf, size, "%.4f", v);
    return buf;
}

static const char* fmt_ratio(char* buf, size_t size, double v, double base)
{
    if (isnan(v) || isnan(base) || !(base > 0.0)) snprintf(buf, size, "-");
    else snprintf(buf, size, "%.2f", v / base);
    return buf;
}

static void print_time_table(const bench_scene* bs, const bench_args* a, const bench_reference* ref,
                             const time_result* tr, int count)
{
    const double t = a->budget;
    char fv[32];
    printf("\n#### %s, equal time (%g s per configuration; light_paths %d for every vpl configuration; reference "
           "floor: ssf %.4f, vfs %s, beauty %.4f)\n\n",
           bs->name, t, a->lp_paths, ref->floor_rmae[SSF], fmt4(fv, sizeof fv, ref->floor_rmae[6]), ref->floor_rmae[0]);
    printf("| config | N | spp | passes | seconds | prep s / pass (share) | ssf @ %g s | @ %g s | @ %g s | @ %g s | "
           "ssf / lp | ssf sum ratio | vfs @ %g s | @ %g s | vfs / lp | vfs sum ratio | beauty @ %g s | @ %g s | "
           "beauty / lp |\n",
           t / 8, t / 4, t / 2, t, t / 4, t, t / 4, t);
    printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    const time_result* lp = NULL;
    for (int i = 0; i < count; ++i)
        if (tr[i].ok && tr[i].cfg.kind == CFG_LP) lp = &tr[i];
    for (int i = 0; i < count; ++i) {
        const time_result* r = &tr[i];
        if (!r->ok) continue;
        char b[13][32], prep[48];
        if (cfg_is_bn(r->cfg.kind))
            snprintf(prep, sizeof prep, "%.2f (%.0f%%)", r->prep_seconds,
                     100.0 * r->prep_seconds * r->passes / r->seconds);
        else snprintf(prep, sizeof prep, "-");
        printf("| %s | %s | %d | %d | %.1f | %s | %s | %s | %s | %s | %s | %.3f | %s | %s | %s | %s | %s | %s | %s |\n",
               r->cfg.name, cfg_is_bn(r->cfg.kind) ? (snprintf(b[11], 32, "%d", r->cfg.lights), b[11]) : "-",
               r->cfg.spp, r->passes, r->seconds, prep, fmt4(b[0], 32, r->at[ERR_SSF][0]),
               fmt4(b[1], 32, r->at[ERR_SSF][1]), fmt4(b[2], 32, r->at[ERR_SSF][2]), fmt4(b[3], 32, r->at[ERR_SSF][3]),
               fmt_ratio(b[4], 32, r->at[ERR_SSF][3], lp ? lp->at[ERR_SSF][3] : NAN), r->end.ratio[ERR_SSF],
               fmt4(b[5], 32, r->at[ERR_VFS][1]), fmt4(b[6], 32, r->at[ERR_VFS][3]),
               fmt_ratio(b[7], 32, r->at[ERR_VFS][3], lp ? lp->at[ERR_VFS][3] : NAN),
               isnan(r->end.ratio[ERR_VFS]) ? "-" : (snprintf(b[10], 32, "%.3f", r->end.ratio[ERR_VFS]), b[10]),
               fmt4(b[8], 32, r->at[ERR_BEAUTY][1]), fmt4(b[9], 32, r->at[ERR_BEAUTY][3]),
               fmt_ratio(b[12], 32, r->at[ERR_BEAUTY][3], lp ? lp->at[ERR_BEAUTY][3] : NAN));
    }
}

static void print_count_table(const bench_scene* bs, const bench_args* a, const bench_reference* ref,
                              const count_result* cr, int per_count, double vsl_per_path)
{
    printf("\n#### %s, equal virtual-light count (%d passes x %d spp; lp*: %.2f surface VSLs per light path; "
           "bn_*: light_paths %d; reference floor: ssf %.4f)\n\n",
           bs->name, a->count_passes, a->count_spp, vsl_per_path, a->lp_paths, ref->floor_rmae[SSF]);
    printf("| N | config | light paths / pass | VSLs / pass | seconds | ssf rMAE | ssf / lp | ssf sum ratio | "
           "vfs rMAE | vfs sum ratio | beauty rMAE | beauty / lp |\n"
           "|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (int k = 0; k < a->count_n; ++k) {
        const count_result* row = cr + (size_t)k * per_count;
        const count_result* lp = row[0].ok && row[0].cfg.kind == CFG_LP ? &row[0] : NULL;
        for (int c = 0; c < per_count; ++c) {
            const count_result* r = &row[c];
            if (!r->ok) continue;
            char b[6][32];
            printf("| %d | %s | %d | %.0f | %.1f | %.4f | %s | %.3f | %s | %s | %.4f | %s |\n", a->counts[k],
                   r->cfg.name, r->light_paths, r->vsl_per_pass, r->seconds, r->e.rmae[ERR_SSF],
                   fmt_ratio(b[0], 32, r->e.rmae[ERR_SSF], lp ? lp->e.rmae[ERR_SSF] : NAN), r->e.ratio[ERR_SSF],
                   fmt4(b[1], 32, r->e.rmae[ERR_VFS]),
                   isnan(r->e.ratio[ERR_VFS]) ? "-" : (snprintf(b[2], 32, "%.3f", r->e.ratio[ERR_VFS]), b[2]),
                   r->e.rmae[ERR_BEAUTY],
                   fmt_ratio(b[3], 32, r->e.rmae[ERR_BEAUTY], lp ? lp->e.rmae[ERR_BEAUTY] : NAN));
        }
    }
}

/* ---- main -------------------------------------------------------------------------------- */

static int parse_args(int argc, char** argv, bench_args* a)
{
    for (int i = 1; i < argc; ++i) {
        if (!strcmp(argv[i], "--no-time")) {
            a->time_on = 0;
            continue;
        }
        if (!strcmp(argv[i], "--no-count")) {
            a->count_on = 0;
            continue;
        }
        const char* v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!v) return 0;
        if (!strcmp(argv[i], "--vdb")) a->vdb = v;
        else if (!strcmp(argv[i], "--csv")) a->csv = v;
        else if (!strcmp(argv[i], "--res")) {
            if (sscanf(v, "%dx%d", &a->width, &a->height) != 2 || a->width < 1 || a->height < 1) return 0;
        } else if (!strcmp(argv[i], "--budget")) a->budget = atof(v);
        else if (!strcmp(argv[i], "--threads")) a->threads = atoi(v);
        else if (!strcmp(argv[i], "--scenes")) snprintf(a->scenes, sizeof a->scenes, "%s", v);
        else if (!strcmp(argv[i], "--configs")) snprintf(a->configs, sizeof a->configs, "%s", v);
        else if (!strcmp(argv[i], "--count-configs")) snprintf(a->count_configs, sizeof a->count_configs, "%s", v);
        else if (!strcmp(argv[i], "--counts")) {
            if (!(a->count_n = parse_int_list(v, a->counts, MAX_COUNTS))) return 0;
        } else if (!strcmp(argv[i], "--count-passes")) a->count_passes = atoi(v);
        else if (!strcmp(argv[i], "--count-spp")) a->count_spp = atoi(v);
        else if (!strcmp(argv[i], "--clamp-fraction")) a->clamp_fraction = atof(v);
        else if (!strcmp(argv[i], "--reference-scale")) a->reference_scale = atof(v);
        else if (!strcmp(argv[i], "--lp-paths")) a->lp_paths = atoi(v);
        else if (!strcmp(argv[i], "--bn-lights")) {
            if (!(a->bn_n = parse_int_list(v, a->bn_lights, MAX_BN))) return 0;
        } else if (!strcmp(argv[i], "--bn-spp")) {
            if (!(a->bn_spp_n = parse_int_list(v, a->bn_spp, MAX_BN))) return 0;
        } else if (!strcmp(argv[i], "--noext-lights")) a->noext_lights = atoi(v);
        else return 0;
        ++i;
    }
    return a->budget > 0.0 && a->threads >= 0 && a->count_passes >= 1 && a->count_spp >= 1 &&
           a->clamp_fraction > 0.0 && a->reference_scale > 0.0 && a->lp_paths >= 1 && a->noext_lights >= 0 &&
           (a->bn_spp_n == 0 || a->bn_spp_n == a->bn_n);
}

static void print_header(const bench_args* a)
{
    double load[3] = {-1, -1, -1};
    FILE* lf = fopen("/proc/loadavg", "r");
    if (lf) {
        if (fscanf(lf, "%lf %lf %lf", &load[0], &load[1], &load[2]) != 3) load[0] = -1;
        fclose(lf);
    }
    printf("# bench_blue_noise: %dx%d, threads %d, budget %g s per configuration, light_paths %d, equal count %d "
           "passes x %d spp, clamp %g x diagonal, VBL_VSL_LIGHTS_DEFAULT %d, load average at start %.2f %.2f %.2f\n",
           a->width, a->height, a->threads, a->budget, a->lp_paths, a->count_passes, a->count_spp, a->clamp_fraction,
           VBL_VSL_LIGHTS_DEFAULT, load[0], load[1], load[2]);
    fflush(stdout);
}

static void print_load(void)
{
    double load = -1;
    FILE* lf = fopen("/proc/loadavg", "r");
    if (lf) {
        if (fscanf(lf, "%lf", &load) != 1) load = -1;
        fclose(lf);
    }
    printf(" (load %.2f)\n", load);
    fflush(stdout);
}

/* Equal time: pt, lp, lp_clamp, bn_ext at each N, then bn_noext at the N whose bn_ext had the
 * lowest surface_from_surface rMAE at the budget (or --noext-lights). Returns the runs made. */
static int run_time_all(const vbl_scene* scene, const bench_args* a, const bench_reference* ref, const bench_scene* bs,
                        double clamp, FILE* csv, time_result* tr)
{
    int n = 0;
    const int fixed[3] = {CFG_PT, CFG_LP, CFG_LP_CLAMP};
    run_config cfgs[3 + MAX_BN];
    for (int k = 0; k < 3; ++k) cfgs[n++] = make_config(fixed[k], 0, fixed[k] == CFG_PT ? 4 : 1);
    for (int k = 0; k < a->bn_n; ++k)
        cfgs[n++] = make_config(CFG_BN_EXT, a->bn_lights[k], a->bn_spp_n ? a->bn_spp[k] : bs->bn_spp[k]);
    int done = 0, best = -1;
    for (int i = 0; i < n; ++i) {
        if (!bench_in_list(a->configs, cfg_names[cfgs[i].kind])) continue;
        time_result* r = &tr[done++];
        run_time(scene, a, ref, bs, cfgs[i], clamp, csv, r);
        printf("# %s time %s: %d passes, %.1f s, ssf %.4f, prep %.2f s", bs->name, cfgs[i].name, r->passes,
               r->seconds, r->end.rmae[ERR_SSF], r->prep_seconds);
        print_load();
        if (r->ok && r->cfg.kind == CFG_BN_EXT && (best < 0 || r->at[ERR_SSF][3] < tr[best].at[ERR_SSF][3]))
            best = done - 1;
    }
    if (!bench_in_list(a->configs, cfg_names[CFG_BN_NOEXT]) || (best < 0 && !a->noext_lights)) return done;
    run_config nx = best >= 0 ? make_config(CFG_BN_NOEXT, tr[best].cfg.lights, tr[best].cfg.spp)
                              : make_config(CFG_BN_NOEXT, a->noext_lights, bs->bn_spp[0]);
    for (int k = 0; a->noext_lights && k < a->bn_n; ++k)
        if (a->bn_lights[k] == a->noext_lights)
            nx = make_config(CFG_BN_NOEXT, a->noext_lights, a->bn_spp_n ? a->bn_spp[k] : bs->bn_spp[k]);
    time_result* r = &tr[done++];
    run_time(scene, a, ref, bs, nx, clamp, csv, r);
    printf("# %s time %s: %d passes, %.1f s, ssf %.4f, prep %.2f s", bs->name, nx.name, r->passes, r->seconds,
           r->end.rmae[ERR_SSF], r->prep_seconds);
    print_load();
    return done;
}

/* Equal count: for each N, lp, lp_clamp, bn_ext and bn_noext (the order of the table). */
static void run_count_all(const vbl_scene* scene, const bench_args* a, const bench_reference* ref, const bench_scene* bs,
                          double clamp, double vsl_per_path, FILE* csv, count_result* cr)
{
    const int kinds[4] = {CFG_LP, CFG_LP_CLAMP, CFG_BN_EXT, CFG_BN_NOEXT};
    for (int k = 0; k < a->count_n; ++k)
        for (int c = 0; c < 4; ++c) {
            if (!bench_in_list(a->count_configs, cfg_names[kinds[c]])) continue;
            count_result* r = &cr[k * 4 + c];
            run_config cfg = make_config(kinds[c], cfg_is_bn(kinds[c]) ? a->counts[k] : 0, a->count_spp);
            run_count(scene, a, ref, bs, cfg, a->counts[k], vsl_per_path, clamp, csv, r);
            printf("# %s count N=%d %s: %.1f s, ssf %.4f", bs->name, a->counts[k], cfg.name, r->seconds,
                   r->e.rmae[ERR_SSF]);
            print_load();
        }
}

static void bench_scene_run(const bench_args* a, const bench_scene* bs, FILE* csv)
{
    vbl_scene* scene = load_scene(a, bs);
    bench_reference ref;
    memset(&ref, 0, sizeof ref);
    make_reference(scene, a, bs, &ref);
    errors floor_e;
    for (int k = 0; k < ERR_COUNT; ++k) {
        floor_e.rmae[k] = ref.floor_rmae[err_layer[k]];
        floor_e.ratio[k] = NAN;
    }
    run_config pt = make_config(CFG_PT, 0, 4);
    csv_row(csv, "reference_floor", bs->name, &pt, 0, 0.0, 0, 0, ref.seconds, &floor_e, 0.0);
    const double clamp = a->clamp_fraction * surfaces_diagonal(scene);
    /* surface VSLs per light path (vpl's photon settings, 4 passes of 2000 paths) */
    vbl_render_options probe = config_options(scene, a, make_config(CFG_LP, 0, 1), 2000, 0.0);
    const double vsl_per_path = mean_vsl_count(scene, &probe, 0, 4) / 2000.0;
    printf("# %s: clamp distance %.3f (%g x surfaces diagonal %.3f); %.3f surface VSLs per light path\n", bs->name,
           clamp, a->clamp_fraction, surfaces_diagonal(scene), vsl_per_path);
    fflush(stdout);
    time_result tr[4 + MAX_BN];
    memset(tr, 0, sizeof tr);
    int time_runs = a->time_on ? run_time_all(scene, a, &ref, bs, clamp, csv, tr) : 0;
    count_result cr[MAX_COUNTS * 4];
    memset(cr, 0, sizeof cr);
    if (a->count_on) run_count_all(scene, a, &ref, bs, clamp, vsl_per_path, csv, cr);
    if (a->time_on) print_time_table(bs, a, &ref, tr, time_runs);
    if (a->count_on) print_count_table(bs, a, &ref, cr, 4, vsl_per_path);
    printf("\n");
    fflush(stdout);
    free(ref.halves);
    free(ref.ref);
    vbl_scene_release(scene);
}

int main(int argc, char** argv)
{
    bench_args a;
    memset(&a, 0, sizeof a);
    a.vdb = VBL_BENCH_DEFAULT_VDB;
    a.csv = VBL_BENCH_CACHE_DIR "/blue_noise.csv";
    a.width = 96;
    a.height = 72;
    a.threads = 2;
    a.budget = 30.0;
    a.clamp_fraction = 0.05;
    a.reference_scale = 1.0;
    a.lp_paths = 100;
    a.count_passes = 1;
    a.count_spp = 1;
    a.time_on = a.count_on = 1;
    a.count_n = parse_int_list("1024,4096,16384", a.counts, MAX_COUNTS);
    a.bn_n = parse_int_list("4096,16384,65536", a.bn_lights, MAX_BN);
    snprintf(a.scenes, sizeof a.scenes, "smoky_room,glossy_room");
    snprintf(a.configs, sizeof a.configs, "pt,lp,lp_clamp,bn_ext,bn_noext");
    snprintf(a.count_configs, sizeof a.count_configs, "lp,bn_ext,bn_noext");
    if (!parse_args(argc, argv, &a)) {
        fprintf(stderr, "usage: bench_blue_noise [--budget S] [--res WxH] [--threads N] "
                        "[--scenes smoky_room,glossy_room] [--counts 1024,4096,16384] [--count-passes P] "
                        "[--count-spp S] [--clamp-fraction F] [--reference-scale F] [--lp-paths L] "
                        "[--bn-lights 4096,16384,65536] [--bn-spp S1,S2,S3] [--noext-lights N] "
                        "[--configs pt,lp,lp_clamp,bn_ext,bn_noext] [--count-configs lp,bn_ext,bn_noext] [--no-time] "
                        "[--no-count] [--vdb FILE] "
                        "[--csv FILE]\n");
        return 2;
    }
    if (a.threads > 0) omp_set_num_threads(a.threads); /* the preparation timing outside vbl_render */
    FILE* csv = fopen(a.csv, "w");
    if (!csv) {
        fprintf(stderr, "bench_blue_noise: cannot write %s\n", a.csv);
        return 1;
    }
    fprintf(csv, "experiment,scene,config,lights,light_paths,vsl_per_pass,passes,spp,pass,seconds,rmae_beauty,"
                 "rmae_surface_from_surface,ratio_surface_from_surface,rmae_volume_from_surface,"
                 "ratio_volume_from_surface,ratio_beauty,prep_seconds\n");
    print_header(&a);
    for (size_t s = 0; s < sizeof bench_scenes / sizeof bench_scenes[0]; ++s)
        if (bench_in_list(a.scenes, bench_scenes[s].name)) bench_scene_run(&a, &bench_scenes[s], csv);
    fclose(csv);
    return 0;
}
