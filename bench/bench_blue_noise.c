/* Issue-8 benchmark: light-path surface VSLs against blue-noise VSLs
 * (../shared/papers/virtual-blue-noise-lighting.txt), with and without the adaptive camera path
 * extension (eqs 6-9), at equal time and at equal virtual-light count, on the smoky room (media +
 * surfaces) and a surfaces-only glossy room (bench/scenes/glossy_room.json).
 *
 *   build/bench/bench_blue_noise [--budget 30] [--res 96x72] [--threads 2] [--scenes smoky_room,glossy_room]
 *       [--counts 64,256,1024] [--count-passes 4] [--count-spp 1] [--clamp-fraction 0.05]
 *       [--lp-paths 100] [--bn-lights N] [--bn-spp S] [--configs pt,lp,lp_clamp,bn_ext,bn_noext]
 *       [--reference-scale 1] [--no-time] [--no-count] [--vdb build/samples/cloud.vdb]
 *       [--csv build/bench/blue_noise.csv]
 *
 * Configurations (every virtual-light one is method vpl: it has the cheapest volume classes, and
 * the placement only changes surface_from_surface):
 *   lp        light-path VSLs (vsl_placement light_paths, the default): the surface vertices of
 *             the pass's light paths, gathered as point lights (every VSL, every camera sample);
 *   lp_clamp  the same with vpl_clamp_distance = --clamp-fraction x the surfaces' bounding-box
 *             diagonal (1/w^2 -> 1/max(w^2, c^2): the usual firefly fix, biased);
 *   bn_ext    blue-noise VSLs (vsl_placement blue_noise): N = light_paths lights per pass from
 *             10 N camera candidates by sample elimination, 10 N light paths split among them,
 *             light + BSDF sample with MIS, and the path extension (eq 6, vsl_path_extension on);
 *   bn_noext  the same with vsl_path_extension off (virtual lights only, w_v = 1);
 *   pt        path tracing, 4 spp per pass (equal time only): the baseline.
 *
 * Error: rMAE = sum |I - Iref| / sum |Iref| over all pixels and R, G, B of one layer (the
 * definition of bench_curves), for surface_from_surface (the layer the placement changes) and
 * beauty; "ratio" = sum I / sum Iref of surface_from_surface (a layer's bias shows there).
 *
 * Equal time: one progressive vbl_render per configuration; its pass callback takes
 * vbl_render_snapshot, computes the errors and records them with the render's elapsed time minus
 * the time spent in the callback; it stops after the pass that passes --budget seconds. The table
 * gives the error at budget/8, /4, /2 and 1 (log-log interpolation between snapshots) and the
 * ratio to lp at the end.
 *
 * Equal virtual-light count: N lights per pass for N in --counts, --count-passes passes of
 * --count-spp spp for every configuration. bn_*: light_paths = N (exactly N lights). lp*:
 * light_paths = round(N / v), v = the mean surface VSLs per light path measured by
 * vbl_photon_trace_with_surfaces (photon_trace.h) over 4 passes of 2000 paths; the table reports
 * the actual mean VSL count of the passes rendered (the same passes traced again: the store
 * depends only on scene, seed and pass).
 *
 * Reference: two independent pt halves, cached in the build directory with bench_curves' file
 * names, layout and key (bench_curves_ref_<scene>_<W>x<H>.raw / .txt), so one cache serves both
 * benchmarks (smoky_room: 600 s, bench_curves' setting; glossy_room: 560 s; x --reference-scale,
 * which is part of the cache key). Its own error
 * rMAE(half A, half B) / 2 is printed as the floor.
 *
 * CSV columns: experiment,scene,config,lights,light_paths,vsl_per_pass,passes,spp,pass,seconds,
 * rmae_beauty,rmae_surface_from_surface,ratio_surface_from_surface. experiment "time" has one row
 * per snapshot, "count" one row per run, "reference_floor" one row per scene (seconds = the
 * reference's). */
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "geometry/surfaces.h"
#include "scene/scene.h"
#include "transport/estimator.h"
#include "transport/photon_trace.h"
#include "vbl/vbl.h"

#ifndef VBL_BENCH_DEFAULT_VDB
#define VBL_BENCH_DEFAULT_VDB "build/samples/cloud.vdb"
#endif
#ifndef VBL_BENCH_SOURCE_DIR
#define VBL_BENCH_SOURCE_DIR "."
#endif
#ifndef VBL_BENCH_CACHE_DIR
#define VBL_BENCH_CACHE_DIR "."
#endif

/* ---- scenes and configurations ------------------------------------------------------------ */

typedef struct bench_scene {
    const char* name;
    const char* file;         /* relative to the source tree */
    double reference_seconds; /* both halves together */
    int uses_vdb;             /* the scene's medium is the sample cloud (--vdb overrides it) */
    int bn_lights, bn_spp;    /* bn_* at equal time: N and spp per pass (see below) */
} bench_scene;

/* Equal time: lp* use 100 light paths a pass (bench_curves' smoky-room count) at 1 spp. bn_* take
 * the best of N in {100, 256, 1024} x spp in {1, 4} in 8 s probes (96x72, 2 threads):
 *   glossy_room: N = 256, 4 spp (ssf rMAE 0.15 / 0.14 ext / no ext; 100 x 1: 0.21 / 0.17,
 *                1024 x 4: 0.20 / 0.17);
 *   smoky_room:  N = 100, 1 spp. light_paths is both N and the vpl light paths whose VPLs and
 *                surface VSLs every camera sample gathers for the volume classes, so a larger N
 *                costs volume work too: 256 x 1 took 4 s a pass, 256 x 4 15 s, 1024 x 4 50 s
 *                (100 x 1: 1.6 s); 100 keeps the volume work equal to lp's. */
static const bench_scene bench_scenes[] = {
    {"smoky_room", "samples/smoky_room.json", 600.0, 1, 100, 1},
    {"glossy_room", "bench/scenes/glossy_room.json", 560.0, 0, 256, 4},
};

enum { CFG_PT, CFG_LP, CFG_LP_CLAMP, CFG_BN_EXT, CFG_BN_NOEXT, CFG_COUNT };
static const char* const cfg_names[CFG_COUNT] = {"pt", "lp", "lp_clamp", "bn_ext", "bn_noext"};

static int cfg_is_lp(int c) { return c == CFG_LP || c == CFG_LP_CLAMP; }
static int cfg_is_bn(int c) { return c == CFG_BN_EXT || c == CFG_BN_NOEXT; }

/* ---- layers and error -------------------------------------------------------------------- */

#define MAX_LAYERS 9 /* bench_curves' reference layout: beauty, 7 classes, medium */
#define SSF 4        /* surface_from_surface */
static const char* const all_layers[MAX_LAYERS] = {"",
                                                   "emission",
                                                   "surface_direct",
                                                   "volume_direct",
                                                   "surface_from_surface",
                                                   "surface_from_volume",
                                                   "volume_from_surface",
                                                   "volume_from_volume",
                                                   "medium"};

typedef struct reference {
    int n;                   /* pixels */
    int present[MAX_LAYERS]; /* layer in the reference film */
    float* halves;           /* [2][MAX_LAYERS][n * 3] */
    float* ref;              /* [MAX_LAYERS][n * 3]: mean of the halves */
    double floor_rmae[MAX_LAYERS];
    double seconds;
} reference;

/* RGB of a layer into out[n * 3] (medium = beauty - emission); 0 when the film lacks it. */
static int film_rgb(const vbl_film* film, int l, int n, float* out)
{
    int ch = 0, che = 0;
    const float* p = vbl_film_layer(film, l == 8 ? "" : all_layers[l], &ch);
    const float* e = l == 8 ? vbl_film_layer(film, "emission", &che) : NULL;
    if (!p || ch < 3) {
        memset(out, 0, sizeof(float) * 3 * (size_t)n);
        return 0;
    }
    for (int i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k)
            out[3 * i + k] = p[(size_t)ch * i + k] - (e && che >= 3 ? e[(size_t)che * i + k] : 0.0f);
    return 1;
}

static double rmae(const float* img, const float* ref, int count)
{
    double num = 0.0, den = 0.0;
    for (int i = 0; i < count; ++i) {
        num += fabs((double)img[i] - ref[i]);
        den += fabs((double)ref[i]);
    }
    return den > 0.0 ? num / den : NAN;
}

static double sum_ratio(const float* img, const float* ref, int count)
{
    double si = 0.0, sr = 0.0;
    for (int i = 0; i < count; ++i) {
        si += img[i];
        sr += ref[i];
    }
    return sr != 0.0 ? si / sr : NAN;
}

/* rMAE of beauty and surface_from_surface, and the surface_from_surface sum ratio. */
typedef struct errors {
    double beauty, ssf, ssf_ratio;
} errors;

static errors film_errors(const vbl_film* film, const reference* r, float* scratch)
{
    errors e = {NAN, NAN, NAN};
    const int c = 3 * r->n;
    film_rgb(film, 0, r->n, scratch);
    e.beauty = rmae(scratch, r->ref, c);
    if (r->present[SSF]) {
        film_rgb(film, SSF, r->n, scratch);
        e.ssf = rmae(scratch, r->ref + (size_t)SSF * c, c);
        e.ssf_ratio = sum_ratio(scratch, r->ref + (size_t)SSF * c, c);
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
    int lp_paths, bn_lights, bn_spp; /* equal time: lp* light paths, bn* N and spp (0: the scene's) */
    char scenes[256], configs[256];
    int counts[MAX_COUNTS], count_n;
    int count_passes, count_spp;
    int time_on, count_on;
} bench_args;

static int in_list(const char* list, const char* name)
{
    size_t len = strlen(name);
    for (const char* s = list; *s;) {
        const char* e = strchr(s, ',');
        size_t l = e ? (size_t)(e - s) : strlen(s);
        if (l == len && !strncmp(s, name, len)) return 1;
        if (!e) break;
        s = e + 1;
    }
    return 0;
}

static int parse_counts(const char* v, bench_args* a)
{
    a->count_n = 0;
    for (const char* s = v; *s && a->count_n < MAX_COUNTS;) {
        int n = atoi(s);
        if (n < 1) return 0;
        a->counts[a->count_n++] = n;
        const char* e = strchr(s, ',');
        if (!e) break;
        s = e + 1;
    }
    return a->count_n > 0;
}

static vbl_scene* load_scene(const bench_args* a, const bench_scene* s)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", VBL_BENCH_SOURCE_DIR, s->file);
    const char* overrides[1] = {a->vdb};
    vbl_scene_load_options lo = VBL_SCENE_LOAD_OPTIONS_DEFAULT;
    lo.vdb_overrides = overrides;
    lo.vdb_override_count = s->uses_vdb ? 1 : 0;
    vbl_scene* scene = NULL;
    if (vbl_scene_load_ex(path, &lo, &scene)) {
        fprintf(stderr, "bench_blue_noise: %s\n", vbl_last_error_message());
        exit(1);
    }
    /* same field of view at the bench resolution (the scene is not shared yet) */
    scene->camera.width = a->width;
    scene->camera.height = a->height;
    return scene;
}

/* ---- reference (bench_curves' cache format) ---------------------------------------------- */

static int load_reference(const char* raw, const char* txt, const char* want, reference* r)
{
    FILE* f = fopen(txt, "r");
    if (!f) return 0;
    char have[2048] = {0};
    size_t got = fread(have, 1, sizeof have - 1, f);
    fclose(f);
    have[got] = '\0';
    char* nl = strchr(have, '\n');
    if (!nl) return 0;
    *nl = '\0';
    if (strcmp(have, want)) return 0;
    for (int l = 0; l < MAX_LAYERS; ++l) {
        if (nl[1 + l] != '0' && nl[1 + l] != '1') return 0;
        r->present[l] = nl[1 + l] == '1';
    }
    f = fopen(raw, "rb");
    if (!f) return 0;
    size_t want_count = (size_t)2 * MAX_LAYERS * 3 * r->n;
    size_t count = fread(r->halves, sizeof(float), want_count, f);
    fclose(f);
    return count == want_count;
}

static void render_reference(const vbl_scene* scene, const bench_args* a, reference* r)
{
    for (int h = 0; h < 2; ++h) {
        vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
        vbl_scene_render_options(scene, &o);
        o.method = VBL_RENDER_PT;
        o.spp = 4;
        o.passes = 1 << 30;
        o.time_limit = 0.5 * r->seconds;
        o.seed = 4242u + 7919u * (uint64_t)h; /* bench_curves' seeds */
        o.threads = a->threads;
        vbl_film* film = NULL;
        if (vbl_render(scene, &o, &film)) {
            fprintf(stderr, "bench_blue_noise: %s\n", vbl_last_error_message());
            exit(1);
        }
        vbl_film_stats st;
        memset(&st, 0, sizeof st);
        st.size = sizeof st;
        vbl_film_get_stats(film, &st);
        printf("# reference half %d: pt %d passes x %d spp in %.1f s\n", h, st.passes, st.spp, st.render_seconds);
        for (int l = 0; l < MAX_LAYERS; ++l)
            r->present[l] = film_rgb(film, l, r->n, r->halves + ((size_t)h * MAX_LAYERS + l) * 3 * r->n);
        vbl_film_release(film);
    }
}

static void save_reference(const char* raw, const char* txt, const char* want, const reference* r)
{
    size_t count = (size_t)2 * MAX_LAYERS * 3 * r->n;
    char tmp[1100];
    snprintf(tmp, sizeof tmp, "%s.tmp", raw);
    FILE* f = fopen(tmp, "wb");
    if (!f || fwrite(r->halves, sizeof(float), count, f) != count || fclose(f)) {
        fprintf(stderr, "bench_blue_noise: cannot write %s (reference not cached)\n", tmp);
        return;
    }
    rename(tmp, raw);
    f = fopen(txt, "w");
    if (!f) return;
    fprintf(f, "%s\n", want);
    for (int l = 0; l < MAX_LAYERS; ++l) fputc(r->present[l] ? '1' : '0', f);
    fputc('\n', f);
    fclose(f);
}

/* The reference's own rMAE per layer: E|A - B| = 2 E|mean - truth| for independent halves. */
static void reference_floor(reference* r)
{
    size_t per = (size_t)MAX_LAYERS * 3 * r->n;
    for (int l = 0; l < MAX_LAYERS; ++l) {
        r->floor_rmae[l] = NAN;
        if (!r->present[l]) continue;
        const float* a0 = r->halves + (size_t)l * 3 * r->n;
        const float* b0 = r->halves + per + (size_t)l * 3 * r->n;
        double num = 0.0, den = 0.0;
        for (int i = 0; i < 3 * r->n; ++i) {
            num += fabs((double)a0[i] - b0[i]);
            den += fabs(0.5 * ((double)a0[i] + b0[i]));
        }
        r->floor_rmae[l] = den > 0.0 ? 0.5 * num / den : NAN;
    }
}

static void make_reference(const vbl_scene* scene, const bench_args* a, const bench_scene* s, reference* r)
{
    r->n = a->width * a->height;
    r->seconds = s->reference_seconds * a->reference_scale;
    size_t per = (size_t)MAX_LAYERS * 3 * r->n;
    r->halves = calloc(2 * per, sizeof(float));
    r->ref = calloc(per, sizeof(float));
    if (!r->halves || !r->ref) exit(1);
    char raw[1024], txt[1024], want[2048];
    snprintf(raw, sizeof raw, "%s/bench_curves_ref_%s_%dx%d.raw", VBL_BENCH_CACHE_DIR, s->name, a->width, a->height);
    snprintf(txt, sizeof txt, "%s/bench_curves_ref_%s_%dx%d.txt", VBL_BENCH_CACHE_DIR, s->name, a->width, a->height);
    snprintf(want, sizeof want, "scene=%s vdb=%s res=%dx%d method=pt spp=4 seconds=%g halves=2 layers=%d rgb", s->file,
             a->vdb, a->width, a->height, r->seconds, MAX_LAYERS);
    if (load_reference(raw, txt, want, r)) {
        printf("# reference %s: cached %s (pt, %g s in two halves)\n", s->name, raw, r->seconds);
    } else {
        render_reference(scene, a, r);
        save_reference(raw, txt, want, r);
    }
    for (size_t i = 0; i < per; ++i) r->ref[i] = 0.5f * (r->halves[i] + r->halves[per + i]);
    reference_floor(r);
    printf("# reference %s own rMAE (floor): surface_from_surface %.4f, beauty %.4f\n", s->name, r->floor_rmae[SSF],
           r->floor_rmae[0]);
}

/* ---- configurations ---------------------------------------------------------------------- */

/* Options of configuration c with `light_paths` (lp: paths; bn: lights N). */
static vbl_render_options config_options(const vbl_scene* scene, const bench_args* a, int c, int light_paths,
                                         double clamp)
{
    vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
    vbl_scene_render_options(scene, &o);
    o.threads = a->threads;
    /* one seed for every vpl configuration: the same light paths (common random numbers) */
    o.seed = c == CFG_PT ? 1000003u : 1000034u;
    o.method = c == CFG_PT ? VBL_RENDER_PT : VBL_RENDER_VPL;
    o.spp = c == CFG_PT ? 4 : 1;
    o.light_paths = c == CFG_PT ? 0 : light_paths;
    o.vpl_clamp_distance = c == CFG_LP_CLAMP ? clamp : 0.0;
    o.vsl_placement = cfg_is_bn(c) ? VBL_VSL_PLACEMENT_BLUE_NOISE : VBL_VSL_PLACEMENT_LIGHT_PATHS;
    o.vsl_path_extension = c == CFG_BN_NOEXT ? VBL_VSL_PATH_EXTENSION_OFF : VBL_VSL_PATH_EXTENSION_ON;
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

/* ---- equal time: one progressive render, snapshots in the pass callback -------------------- */

typedef struct curve_point {
    int pass;
    double seconds;
    errors e;
} curve_point;

typedef struct curve {
    const reference* ref;
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
    int stop = seconds >= c->budget;
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

/* A curve's error at time t, log-log between the snapshots around it; NAN before the first
 * snapshot, the last snapshot's error after it. */
static double error_at(const curve* c, double t, int ssf)
{
    for (int i = 0; i < c->count; ++i) {
        const curve_point* b = &c->points[i];
        if (b->seconds < t) continue;
        double eb = ssf ? b->e.ssf : b->e.beauty;
        if (b->seconds == t) return eb;
        if (i == 0) return NAN;
        const curve_point* p = &c->points[i - 1];
        double ep = ssf ? p->e.ssf : p->e.beauty;
        double f = (log(t) - log(p->seconds)) / (log(b->seconds) - log(p->seconds));
        return exp(log(ep) + f * (log(eb) - log(ep)));
    }
    if (c->count == 0) return NAN;
    return ssf ? c->points[c->count - 1].e.ssf : c->points[c->count - 1].e.beauty;
}

typedef struct time_result {
    int ok, passes, light_paths, spp;
    double seconds, vsl_per_pass;
    double ssf_at[4], beauty_at[4]; /* at budget / 8, / 4, / 2, 1 */
    errors end;
} time_result;

static void run_time(const vbl_scene* scene, const bench_args* a, const reference* ref, const bench_scene* bs, int cfg,
                     double clamp, FILE* csv, time_result* out)
{
    memset(out, 0, sizeof *out);
    curve c;
    memset(&c, 0, sizeof c);
    c.ref = ref;
    c.budget = a->budget;
    c.img = malloc(sizeof(float) * 3 * (size_t)ref->n);
    if (!c.img) exit(1);
    int lights = cfg_is_bn(cfg) ? (a->bn_lights > 0 ? a->bn_lights : bs->bn_lights) : a->lp_paths;
    vbl_render_options o = config_options(scene, a, cfg, lights, clamp);
    if (cfg_is_bn(cfg)) o.spp = a->bn_spp > 0 ? a->bn_spp : bs->bn_spp;
    o.passes = 1 << 30;
    o.callback = on_pass;
    o.callback_user_data = &c;
    vbl_film* film = NULL;
    vbl_result r = vbl_render(scene, &o, &film);
    if (film) vbl_film_release(film);
    if ((r && r != VBL_ERROR_INTERRUPTED) || c.count == 0) {
        printf("# %s %s: skipped (%s)\n", bs->name, cfg_names[cfg], r ? vbl_last_error_message() : "no pass");
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
    out->spp = o.spp;
    for (int k = 0; k < 4; ++k) {
        double t = a->budget / (double)(8 >> k);
        out->ssf_at[k] = error_at(&c, t, 1);
        out->beauty_at[k] = error_at(&c, t, 0);
    }
    /* lp: the surface VSLs of the first 4 passes; bn: N lights exactly */
    out->vsl_per_pass = cfg_is_lp(cfg) ? mean_vsl_count(scene, &o, 0, 4) : (cfg_is_bn(cfg) ? (double)lights : 0.0);
    for (int i = 0; i < c.count; ++i) {
        const curve_point* p = &c.points[i];
        fprintf(csv, "time,%s,%s,%d,%d,%.1f,%d,%d,%d,%.4f,%.6f,%.6f,%.6f\n", bs->name, cfg_names[cfg],
                cfg_is_bn(cfg) ? lights : 0, o.light_paths, out->vsl_per_pass, p->pass, o.spp, p->pass, p->seconds,
                p->e.beauty, p->e.ssf, p->e.ssf_ratio);
    }
    fflush(csv);
    free(c.img);
    free(c.points);
}

/* ---- equal virtual-light count: fixed passes and spp ------------------------------------- */

typedef struct count_result {
    int ok, lights, light_paths;
    double vsl_per_pass, seconds;
    errors e;
} count_result;

static void run_count(const vbl_scene* scene, const bench_args* a, const reference* ref, const bench_scene* bs,
                      int cfg, int lights, double vsl_per_path, double clamp, FILE* csv, count_result* out)
{
    memset(out, 0, sizeof *out);
    int paths = lights;
    if (cfg_is_lp(cfg)) paths = (int)fmax(1.0, floor(lights / vsl_per_path + 0.5));
    vbl_render_options o = config_options(scene, a, cfg, paths, clamp);
    o.passes = a->count_passes;
    o.spp = a->count_spp;
    vbl_film* film = NULL;
    double t0 = omp_get_wtime();
    vbl_result r = vbl_render(scene, &o, &film);
    double seconds = omp_get_wtime() - t0;
    if (r || !film) {
        printf("# %s %s N=%d: skipped (%s)\n", bs->name, cfg_names[cfg], lights, vbl_last_error_message());
        if (film) vbl_film_release(film);
        return;
    }
    float* img = malloc(sizeof(float) * 3 * (size_t)ref->n);
    if (!img) exit(1);
    out->ok = 1;
    out->lights = lights;
    out->light_paths = paths;
    out->seconds = seconds;
    out->e = film_errors(film, ref, img);
    out->vsl_per_pass = cfg_is_lp(cfg) ? mean_vsl_count(scene, &o, 0, o.passes) : (double)lights;
    vbl_film_release(film);
    free(img);
    fprintf(csv, "count,%s,%s,%d,%d,%.1f,%d,%d,%d,%.4f,%.6f,%.6f,%.6f\n", bs->name, cfg_names[cfg], lights, paths,
            out->vsl_per_pass, o.passes, o.spp, o.passes, seconds, out->e.beauty, out->e.ssf, out->e.ssf_ratio);
    fflush(csv);
}

/* ---- tables ------------------------------------------------------------------------------ */

static void print_time_table(const bench_scene* bs, const bench_args* a, const reference* ref,
                             const time_result* tr)
{
    printf("\n#### %s, equal time (%g s per configuration; reference floor: surface_from_surface %.4f, "
           "beauty %.4f)\n\n",
           bs->name, a->budget, ref->floor_rmae[SSF], ref->floor_rmae[0]);
    printf("| config | light paths | VSLs / pass | spp | passes | seconds | ssf rMAE @ %g s | @ %g s | @ %g s | "
           "@ %g s | ssf / lp | ssf sum ratio | beauty rMAE @ %g s | beauty / lp |\n",
           a->budget / 8, a->budget / 4, a->budget / 2, a->budget, a->budget);
    printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    const time_result* lp = &tr[CFG_LP];
    for (int c = 0; c < CFG_COUNT; ++c) {
        const time_result* r = &tr[c];
        if (!r->ok) continue;
        printf("| %s | %d | %.0f | %d | %d | %.1f | %.4f | %.4f | %.4f | %.4f | %.2f | %.3f | %.4f | %.2f |\n",
               cfg_names[c], r->light_paths, r->vsl_per_pass, r->spp, r->passes, r->seconds, r->ssf_at[0], r->ssf_at[1],
               r->ssf_at[2], r->ssf_at[3], lp->ok ? r->ssf_at[3] / lp->ssf_at[3] : NAN, r->end.ssf_ratio,
               r->beauty_at[3], lp->ok ? r->beauty_at[3] / lp->beauty_at[3] : NAN);
    }
}

static void print_count_table(const bench_scene* bs, const bench_args* a, const reference* ref,
                              const count_result* cr, double vsl_per_path)
{
    printf("\n#### %s, equal virtual-light count (%d passes x %d spp; light-path VSLs: %.2f surface VSLs per "
           "light path; reference floor: surface_from_surface %.4f)\n\n",
           bs->name, a->count_passes, a->count_spp, vsl_per_path, ref->floor_rmae[SSF]);
    printf("| N | config | light paths / pass | VSLs / pass | seconds | ssf rMAE | ssf / lp | ssf sum ratio | "
           "beauty rMAE |\n|---|---|---|---|---|---|---|---|---|\n");
    for (int k = 0; k < a->count_n; ++k) {
        const count_result* row = cr + (size_t)k * CFG_COUNT;
        for (int c = CFG_LP; c < CFG_COUNT; ++c) {
            const count_result* r = &row[c];
            if (!r->ok) continue;
            printf("| %d | %s | %d | %.0f | %.1f | %.4f | %.2f | %.3f | %.4f |\n", r->lights, cfg_names[c],
                   r->light_paths, r->vsl_per_pass, r->seconds, r->e.ssf,
                   row[CFG_LP].ok ? r->e.ssf / row[CFG_LP].e.ssf : NAN, r->e.ssf_ratio, r->e.beauty);
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
        else if (!strcmp(argv[i], "--counts")) {
            if (!parse_counts(v, a)) return 0;
        } else if (!strcmp(argv[i], "--count-passes")) a->count_passes = atoi(v);
        else if (!strcmp(argv[i], "--count-spp")) a->count_spp = atoi(v);
        else if (!strcmp(argv[i], "--clamp-fraction")) a->clamp_fraction = atof(v);
        else if (!strcmp(argv[i], "--reference-scale")) a->reference_scale = atof(v);
        else if (!strcmp(argv[i], "--lp-paths")) a->lp_paths = atoi(v);
        else if (!strcmp(argv[i], "--bn-lights")) a->bn_lights = atoi(v);
        else if (!strcmp(argv[i], "--bn-spp")) a->bn_spp = atoi(v);
        else return 0;
        ++i;
    }
    return a->budget > 0.0 && a->threads >= 0 && a->count_passes >= 1 && a->count_spp >= 1 &&
           a->clamp_fraction > 0.0 && a->reference_scale > 0.0 && a->lp_paths >= 1 && a->bn_lights >= 0 &&
           a->bn_spp >= 0;
}

static void print_header(const bench_args* a)
{
    double load[3] = {-1, -1, -1};
    FILE* lf = fopen("/proc/loadavg", "r");
    if (lf) {
        if (fscanf(lf, "%lf %lf %lf", &load[0], &load[1], &load[2]) != 3) load[0] = -1;
        fclose(lf);
    }
    printf("# bench_blue_noise: %dx%d, threads %d, budget %g s per configuration, equal count %d passes x %d spp, "
           "clamp %g x diagonal, load average at start %.2f %.2f %.2f\n",
           a->width, a->height, a->threads, a->budget, a->count_passes, a->count_spp, a->clamp_fraction, load[0],
           load[1], load[2]);
    fflush(stdout);
}

static void bench_scene_run(const bench_args* a, const bench_scene* bs, FILE* csv)
{
    vbl_scene* scene = load_scene(a, bs);
    reference ref;
    memset(&ref, 0, sizeof ref);
    make_reference(scene, a, bs, &ref);
    fprintf(csv, "reference_floor,%s,pt,0,0,0,0,4,0,%.1f,%.6f,%.6f,\n", bs->name, ref.seconds, ref.floor_rmae[0],
            ref.floor_rmae[SSF]);
    const double clamp = a->clamp_fraction * surfaces_diagonal(scene);
    /* surface VSLs per light path (vpl's photon settings, 4 passes of 2000 paths) */
    vbl_render_options probe = config_options(scene, a, CFG_LP, 2000, 0.0);
    const double vsl_per_path = mean_vsl_count(scene, &probe, 0, 4) / 2000.0;
    printf("# %s: clamp distance %.3f (%g x surfaces diagonal %.3f); %.3f surface VSLs per light path\n", bs->name,
           clamp, a->clamp_fraction, surfaces_diagonal(scene), vsl_per_path);
    fflush(stdout);
    time_result tr[CFG_COUNT];
    memset(tr, 0, sizeof tr);
    for (int c = 0; a->time_on && c < CFG_COUNT; ++c) {
        if (!in_list(a->configs, cfg_names[c])) continue;
        run_time(scene, a, &ref, bs, c, clamp, csv, &tr[c]);
        printf("# %s time %s: %d passes, %.1f s, ssf %.4f\n", bs->name, cfg_names[c], tr[c].passes, tr[c].seconds,
               tr[c].end.ssf);
        fflush(stdout);
    }
    count_result cr[MAX_COUNTS * CFG_COUNT];
    memset(cr, 0, sizeof cr);
    for (int k = 0; a->count_on && k < a->count_n; ++k)
        for (int c = CFG_LP; c < CFG_COUNT; ++c) {
            if (!in_list(a->configs, cfg_names[c])) continue;
            count_result* r = &cr[k * CFG_COUNT + c];
            run_count(scene, a, &ref, bs, c, a->counts[k], vsl_per_path, clamp, csv, r);
            printf("# %s count N=%d %s: %.1f s, ssf %.4f\n", bs->name, a->counts[k], cfg_names[c], r->seconds,
                   r->e.ssf);
            fflush(stdout);
        }
    if (a->time_on) print_time_table(bs, a, &ref, tr);
    if (a->count_on) print_count_table(bs, a, &ref, cr, vsl_per_path);
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
    a.bn_lights = 0;
    a.bn_spp = 0;
    a.count_passes = 4;
    a.count_spp = 1;
    a.time_on = a.count_on = 1;
    parse_counts("64,256,1024", &a);
    snprintf(a.scenes, sizeof a.scenes, "smoky_room,glossy_room");
    snprintf(a.configs, sizeof a.configs, "pt,lp,lp_clamp,bn_ext,bn_noext");
    if (!parse_args(argc, argv, &a)) {
        fprintf(stderr, "usage: bench_blue_noise [--budget S] [--res WxH] [--threads N] "
                        "[--scenes smoky_room,glossy_room] [--counts 64,256,1024] [--count-passes P] "
                        "[--count-spp S] [--clamp-fraction F] [--reference-scale F] [--lp-paths L] "
                        "[--bn-lights N] [--bn-spp S] [--configs pt,lp,lp_clamp,bn_ext,bn_noext] [--no-time] "
                        "[--no-count] [--vdb FILE] [--csv FILE]\n");
        return 2;
    }
    FILE* csv = fopen(a.csv, "w");
    if (!csv) {
        fprintf(stderr, "bench_blue_noise: cannot write %s\n", a.csv);
        return 1;
    }
    fprintf(csv, "experiment,scene,config,lights,light_paths,vsl_per_pass,passes,spp,pass,seconds,rmae_beauty,"
                 "rmae_surface_from_surface,ratio_surface_from_surface\n");
    print_header(&a);
    for (size_t s = 0; s < sizeof bench_scenes / sizeof bench_scenes[0]; ++s)
        if (in_list(a.scenes, bench_scenes[s].name)) bench_scene_run(&a, &bench_scenes[s], csv);
    fclose(csv);
    return 0;
}
