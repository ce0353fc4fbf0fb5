/* Issue-3 benchmark: pt, vpl and vrl at equal wall-clock time on the sample cloud, against a long
 * pt reference.
 *
 *   build/bench/bench_methods [--scene samples/cloud.json] [--vdb build/samples/cloud.vdb]
 *       [--res 96x72] [--reference-seconds 240] [--budgets 2,5,10,20] [--threads 0]
 *       [--vrl-light-paths 30,100,300] [--vpl-light-paths 300,1000,3000] [--pt-spp 4]
 *
 * Error metric (per layer): rMAE = mean over pixels of |I - Iref| / (Iref + 0.01 mean(Iref)),
 * with I the mean of R, G, B of the pixel; reported for beauty and volume_from_volume.
 *
 * Each configuration renders progressive passes one vbl_render call at a time (passes = 1, seed
 * = base + pass: exactly the driver's independent passes) and keeps the running mean, so one run
 * up to the largest budget gives the error at every budget (the passes finished within it, as
 * options.time_limit would stop) and the time at which rMAE first drops to 0.1. Times are wall
 * clock and include the per-pass photon tracing.
 *
 * The reference is two independent pt halves of reference-seconds / 2 each, cached in the build
 * directory (bench/bench_methods_ref_<W>x<H>.raw, float RGB beauty then volume_from_volume, with
 * its settings in the .txt beside it); the cache is reused when scene, VDB, resolution and
 * seconds match. Its own error is estimated as rMAE(half A, half B) / 2 and printed. */
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene/scene.h"
#include "transport/common/photon_trace.h"
#include "vbl/vbl.h"

#ifndef VBL_BENCH_DEFAULT_VDB
#define VBL_BENCH_DEFAULT_VDB "build/samples/cloud.vdb"
#endif
#ifndef VBL_BENCH_DEFAULT_SCENE
#define VBL_BENCH_DEFAULT_SCENE "samples/cloud.json"
#endif
#ifndef VBL_BENCH_CACHE_DIR
#define VBL_BENCH_CACHE_DIR "."
#endif

#define MAX_LIST 8
#define LAYERS 2
static const char* const layer_names[LAYERS] = {"", "volume_from_volume"};
static const char* const layer_labels[LAYERS] = {"beauty", "volume_from_volume"};

typedef struct bench_args {
    const char* scene;
    const char* vdb;
    int width, height;
    double reference_seconds;
    double budgets[MAX_LIST];
    int budget_count;
    int vrl_paths[MAX_LIST], vrl_path_count;
    int vpl_paths[MAX_LIST], vpl_path_count;
    int pt_spp;
    int threads;
} bench_args;

static int parse_list_d(const char* s, double* out)
{
    int n = 0;
    while (s && *s && n < MAX_LIST) {
        char* end;
        out[n++] = strtod(s, &end);
        if (end == s) return 0;
        s = *end == ',' ? end + 1 : end;
    }
    return n;
}

static int parse_list_i(const char* s, int* out)
{
    double d[MAX_LIST];
    int n = parse_list_d(s, d);
    for (int i = 0; i < n; ++i) out[i] = (int)d[i];
    return n;
}

static vbl_scene* load_scene(const bench_args* a)
{
    const char* overrides[1] = {a->vdb};
    vbl_scene_load_options lo = VBL_SCENE_LOAD_OPTIONS_DEFAULT;
    lo.vdb_overrides = overrides;
    lo.vdb_override_count = 1;
    vbl_scene* scene = NULL;
    if (vbl_scene_load_ex(a->scene, &lo, &scene)) {
        fprintf(stderr, "bench_methods: %s\n", vbl_last_error_message());
        exit(1);
    }
    /* same vertical field of view, the requested pixel count (the scene is ours until shared) */
    scene->camera.width = a->width;
    scene->camera.height = a->height;
    return scene;
}

/* Per-pixel mean of R, G, B of the two layers (0 where the film lacks the layer). */
static void film_layers(const vbl_film* film, int n, float* out /* LAYERS * n */)
{
    for (int l = 0; l < LAYERS; ++l) {
        int ch = 0;
        const float* p = vbl_film_layer(film, layer_names[l], &ch);
        for (int i = 0; i < n; ++i) out[l * n + i] = p ? (p[ch * i] + p[ch * i + 1] + p[ch * i + 2]) / 3.0f : 0.0f;
    }
}

static double rmae(const double* img, const float* ref, int n)
{
    double mean = 0.0;
    for (int i = 0; i < n; ++i) mean += ref[i];
    mean /= n;
    if (!(mean > 0.0)) return NAN;
    double e = 0.0;
    for (int i = 0; i < n; ++i) e += fabs(img[i] - ref[i]) / (ref[i] + 0.01 * mean);
    return e / n;
}

typedef struct run_config {
    char label[64];
    vbl_render_method method;
    int spp, light_paths;
} run_config;

/* Progressive run up to max_seconds; err[b][l] = rMAE at budgets[b]; t01[l] = first time rMAE <= 0.1. */
typedef struct run_result {
    double err[MAX_LIST][LAYERS];
    int passes_at[MAX_LIST];
    double t01[LAYERS];
    double seconds_per_pass;
} run_result;

static void run(const vbl_scene* scene, const bench_args* a, const run_config* c, const float* ref, run_result* res)
{
    const int n = a->width * a->height;
    double* sum = calloc((size_t)LAYERS * n, sizeof *sum);
    double* mean = calloc((size_t)LAYERS * n, sizeof *mean);
    float* pass = calloc((size_t)LAYERS * n, sizeof *pass);
    if (!sum || !mean || !pass) exit(1);
    for (int b = 0; b < a->budget_count; ++b)
        for (int l = 0; l < LAYERS; ++l) res->err[b][l] = NAN;
    res->t01[0] = res->t01[1] = NAN;
    const double max_budget = a->budgets[a->budget_count - 1];
    vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
    vbl_scene_render_options(scene, &o);
    o.method = c->method;
    o.spp = c->spp;
    o.light_paths = c->light_paths;
    o.passes = 1;
    o.threads = a->threads;
    double start = omp_get_wtime(), elapsed = 0.0;
    int b = 0;
    double prev_err[LAYERS] = {NAN, NAN};
    for (int p = 0; b < a->budget_count; ++p) {
        o.seed = 1000003u + (uint64_t)p;
        vbl_film* film = NULL;
        if (vbl_render(scene, &o, &film)) {
            fprintf(stderr, "bench_methods: %s\n", vbl_last_error_message());
            exit(1);
        }
        double now = omp_get_wtime() - start;
        /* budgets that ended before this pass finished see the passes before it (time_limit
         * semantics would include this pass when it started before the budget; we are stricter) */
        while (b < a->budget_count && now > a->budgets[b]) {
            for (int l = 0; l < LAYERS; ++l) res->err[b][l] = p > 0 ? prev_err[l] : NAN;
            res->passes_at[b] = p;
            ++b;
        }
        film_layers(film, n, pass);
        vbl_film_release(film);
        for (int i = 0; i < LAYERS * n; ++i) {
            sum[i] += pass[i];
            mean[i] = sum[i] / (p + 1);
        }
        for (int l = 0; l < LAYERS; ++l) {
            prev_err[l] = rmae(mean + l * n, ref + l * n, n);
            if (isnan(res->t01[l]) && prev_err[l] <= 0.1) res->t01[l] = now;
        }
        elapsed = now;
        res->seconds_per_pass = elapsed / (p + 1);
        if (now > max_budget) break;
    }
    free(sum);
    free(mean);
    free(pass);
}

static int load_reference(const char* raw, const char* txt, const char* want, float* ref, int n)
{
    FILE* f = fopen(txt, "r");
    if (!f) return 0;
    char have[2048] = {0};
    size_t got = fread(have, 1, sizeof have - 1, f);
    fclose(f);
    have[got] = '\0';
    /* the settings line is the first line */
    char* nl = strchr(have, '\n');
    if (nl) *nl = '\0';
    if (strcmp(have, want)) return 0;
    f = fopen(raw, "rb");
    if (!f) return 0;
    size_t count = fread(ref, sizeof(float), (size_t)(2 * LAYERS) * n, f);
    fclose(f);
    return count == (size_t)(2 * LAYERS) * n;
}

static void render_reference(const vbl_scene* scene, const bench_args* a, float* halves /* 2 * LAYERS * n */)
{
    const int n = a->width * a->height;
    for (int h = 0; h < 2; ++h) {
        vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
        vbl_scene_render_options(scene, &o);
        o.method = VBL_RENDER_PT;
        o.spp = 4;
        o.passes = 1 << 30;
        o.time_limit = 0.5 * a->reference_seconds;
        o.seed = 77u + 1000u * (uint64_t)h;
        o.threads = a->threads;
        vbl_film* film = NULL;
        if (vbl_render(scene, &o, &film)) {
            fprintf(stderr, "bench_methods: %s\n", vbl_last_error_message());
            exit(1);
        }
        vbl_film_stats st;
        memset(&st, 0, sizeof st);
        st.size = sizeof st;
        vbl_film_get_stats(film, &st);
        printf("# reference half %d: pt %d passes x %d spp in %.1f s\n", h, st.passes, st.spp, st.render_seconds);
        film_layers(film, n, halves + (size_t)h * LAYERS * n);
        vbl_film_release(film);
    }
}

/* Virtual lights per light path on this scene (1000 paths, the photon tracer the estimators use):
 * the per-camera-sample cost of vpl / vrl is proportional to these counts. */
static void print_photon_stats(const vbl_scene* scene, int threads)
{
    vbl_render_context ctx;
    memset(&ctx, 0, sizeof ctx);
    vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
    vbl_scene_render_options(scene, &o);
    o.light_paths = 1000;
    ctx.scene = scene;
    ctx.extinction = &scene->extinction;
    ctx.options = o;
    ctx.tracking.estimator = VBL_TRANSMITTANCE_RATIO_TRACKING;
    ctx.threads = threads > 0 ? threads : omp_get_max_threads();
    vbl_photon_settings ps = {1, 1, 0, VBL_TRANSMITTANCE_CACHED_RATIO, 16};
    vbl_photon_store st;
    if (vbl_photon_trace(&ctx, &ps, &st)) return;
    double len = 0.0;
    for (size_t i = 0; i < st.vrl_count; ++i) len += st.vrls[i].length;
    printf("# photon tracing: %.2f VRLs and %.2f VPLs per light path, mean short-VRL length %.4f\n",
           st.vrl_count / 1000.0, st.vpl_count / 1000.0, st.vrl_count ? len / st.vrl_count : 0.0);
    vbl_photon_store_free(&st);
}

int main(int argc, char** argv)
{
    bench_args a;
    memset(&a, 0, sizeof a);
    a.scene = VBL_BENCH_DEFAULT_SCENE;
    a.vdb = VBL_BENCH_DEFAULT_VDB;
    a.width = 96;
    a.height = 72;
    a.reference_seconds = 240.0;
    a.budget_count = parse_list_d("2,5,10,20", a.budgets);
    a.vrl_path_count = parse_list_i("30,100,300", a.vrl_paths);
    a.vpl_path_count = parse_list_i("300,1000,3000", a.vpl_paths);
    a.pt_spp = 4;
    for (int i = 1; i < argc; ++i) {
        const char* v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!v) goto usage;
        if (!strcmp(argv[i], "--scene")) a.scene = v;
        else if (!strcmp(argv[i], "--vdb")) a.vdb = v;
        else if (!strcmp(argv[i], "--res")) {
            if (sscanf(v, "%dx%d", &a.width, &a.height) != 2 || a.width < 1 || a.height < 1) goto usage;
        } else if (!strcmp(argv[i], "--reference-seconds")) a.reference_seconds = atof(v);
        else if (!strcmp(argv[i], "--budgets")) a.budget_count = parse_list_d(v, a.budgets);
        else if (!strcmp(argv[i], "--vrl-light-paths")) a.vrl_path_count = parse_list_i(v, a.vrl_paths);
        else if (!strcmp(argv[i], "--vpl-light-paths")) a.vpl_path_count = parse_list_i(v, a.vpl_paths);
        else if (!strcmp(argv[i], "--pt-spp")) a.pt_spp = atoi(v);
        else if (!strcmp(argv[i], "--threads")) a.threads = atoi(v);
        else goto usage;
        ++i;
    }
    if (a.budget_count < 1 || !(a.reference_seconds > 0.0) || a.pt_spp < 1) goto usage;

    vbl_scene* scene = load_scene(&a);
    print_photon_stats(scene, a.threads);
    const int n = a.width * a.height;
    float* halves = calloc((size_t)2 * LAYERS * n, sizeof *halves);
    float* ref = calloc((size_t)LAYERS * n, sizeof *ref);
    if (!halves || !ref) return 1;
    char raw[1024], txt[1024], want[2048];
    snprintf(raw, sizeof raw, "%s/bench_methods_ref_%dx%d.raw", VBL_BENCH_CACHE_DIR, a.width, a.height);
    snprintf(txt, sizeof txt, "%s/bench_methods_ref_%dx%d.txt", VBL_BENCH_CACHE_DIR, a.width, a.height);
    snprintf(want, sizeof want, "scene=%s vdb=%s res=%dx%d method=pt spp=4 seconds=%g halves=2 layers=beauty,volume_from_volume",
             a.scene, a.vdb, a.width, a.height, a.reference_seconds);
    if (load_reference(raw, txt, want, halves, n)) {
        printf("# reference: cached %s\n", raw);
    } else {
        render_reference(scene, &a, halves);
        char tmp[1100];
        snprintf(tmp, sizeof tmp, "%s.tmp", raw);
        FILE* f = fopen(tmp, "wb");
        if (f && fwrite(halves, sizeof(float), (size_t)2 * LAYERS * n, f) == (size_t)2 * LAYERS * n && !fclose(f)) {
            rename(tmp, raw);
            f = fopen(txt, "w");
            if (f) {
                fprintf(f, "%s\n", want);
                fclose(f);
            }
        } else {
            if (f) fclose(f);
            fprintf(stderr, "bench_methods: cannot write %s (reference not cached)\n", tmp);
        }
    }
    for (int i = 0; i < LAYERS * n; ++i) ref[i] = 0.5f * (halves[i] + halves[LAYERS * n + i]);
    for (int l = 0; l < LAYERS; ++l) {
        double* a_img = malloc(sizeof(double) * n);
        for (int i = 0; i < n; ++i) a_img[i] = halves[l * n + i];
        printf("# reference %-18s own rMAE ~ %.4f (rMAE(half A, half B) / 2)\n", layer_labels[l],
               0.5 * rmae(a_img, halves + LAYERS * n + l * n, n));
        free(a_img);
    }

    run_config configs[1 + 2 * MAX_LIST];
    int cc = 0;
    configs[cc] = (run_config){"", VBL_RENDER_PT, a.pt_spp, 0};
    snprintf(configs[cc].label, sizeof configs[cc].label, "pt spp=%d", a.pt_spp);
    ++cc;
    for (int i = 0; i < a.vpl_path_count; ++i, ++cc) {
        configs[cc] = (run_config){"", VBL_RENDER_VPL, 1, a.vpl_paths[i]};
        snprintf(configs[cc].label, sizeof configs[cc].label, "vpl lp=%d", a.vpl_paths[i]);
    }
    for (int i = 0; i < a.vrl_path_count; ++i, ++cc) {
        configs[cc] = (run_config){"", VBL_RENDER_VRL, 1, a.vrl_paths[i]};
        snprintf(configs[cc].label, sizeof configs[cc].label, "vrl lp=%d", a.vrl_paths[i]);
    }

    double load[3] = {0};
    FILE* lf = fopen("/proc/loadavg", "r");
    if (lf) {
        if (fscanf(lf, "%lf %lf %lf", &load[0], &load[1], &load[2]) != 3) load[0] = -1;
        fclose(lf);
    }
    printf("# %dx%d, threads %d, load average at start %.2f %.2f %.2f\n", a.width, a.height,
           a.threads > 0 ? a.threads : omp_get_max_threads(), load[0], load[1], load[2]);
    printf("| layer | config | s/pass |");
    for (int b = 0; b < a.budget_count; ++b) printf(" %g s |", a.budgets[b]);
    printf(" t(rMAE<=0.1) |\n|---|---|---|");
    for (int b = 0; b < a.budget_count; ++b) printf("---|");
    printf("---|\n");
    fflush(stdout);
    run_result results[1 + 2 * MAX_LIST];
    for (int c = 0; c < cc; ++c) {
        run(scene, &a, &configs[c], ref, &results[c]);
        for (int l = 0; l < LAYERS; ++l) {
            printf("| %s | %s | %.3f |", layer_labels[l], configs[c].label, results[c].seconds_per_pass);
            for (int b = 0; b < a.budget_count; ++b) {
                if (isnan(results[c].err[b][l])) printf(" - |");
                else printf(" %.4f |", results[c].err[b][l]);
            }
            if (isnan(results[c].t01[l])) printf(" not reached |\n");
            else printf(" %.2f s |\n", results[c].t01[l]);
        }
        fflush(stdout);
    }
    vbl_scene_release(scene);
    free(halves);
    free(ref);
    return 0;
usage:
    fprintf(stderr, "usage: bench_methods [--scene FILE] [--vdb FILE] [--res WxH] [--reference-seconds S] "
                    "[--budgets a,b,..] [--vrl-light-paths a,b,..] [--vpl-light-paths a,b,..] [--pt-spp N] "
                    "[--threads N]\n");
    return 2;
}
