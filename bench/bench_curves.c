/* Issue-4/6 benchmark: error-vs-time curves of every method and every quality preset against a
 * long pt reference, on the sample cloud, on a dense anisotropic cloud and on the smoky room
 * (the cloud as smoke among surfaces: per-layer curves of the surface layers too).
 *
 *   build/bench/bench_curves [--budget 30] [--reference-seconds 240] [--res 96x72] [--threads 2]
 *       [--scenes cloud,dense,smoky_room] [--methods pt,vpl,vrl,vbl,beams,vrl-sel,vbl-sel] [--no-presets] [--presets-only]
 *       [--vbl-radius0 R] [--vbl-alpha A] (vbl's method run; 0: defaults)
 *       [--vdb build/samples/cloud.vdb] [--csv build/bench/curves.csv]
 *
 * Error: rMAE = sum |I - Iref| / sum |Iref| over all pixels and R, G, B of one layer: beauty, each
 * transport layer the scene produces, and "medium" = beauty - emission (the light the medium
 * scatters; the headline number, because the directly seen environment is exact in every method
 * and would dilute the beauty's error).
 *
 * Every configuration is ONE progressive vbl_render call; its pass callback takes
 * vbl_render_snapshot of the film so far, computes the rMAE of every layer and records it with
 * the render's elapsed time minus the time spent in earlier callbacks (the bench's own cost).
 * Methods stop at --budget seconds; presets run their own pass count (capped at 4x the budget).
 * Time to reach rMAE 0.1 / 0.05 is interpolated log-log between the last point above and the
 * first point at or below the threshold.
 *
 * The reference is two independent pt halves of reference-seconds / 2 each, cached in the build
 * directory (bench/bench_curves_ref_<scene>_<W>x<H>.raw with its settings in the .txt beside it),
 * reused when scene, VDB, resolution, seconds and layers match. Its own error (the rMAE floor of
 * every curve) is estimated as rMAE(half A, half B) / 2, printed and written to the CSV as a row
 * with method "reference_floor", pass 0 and the reference's seconds.
 *
 * CSV columns: method,scene,pass,seconds,rmae_beauty,rmae_emission,...,rmae_volume_from_volume,
 * rmae_medium (empty where the scene has no such layer). */
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_reference.h"
#include "scene/scene.h"
#include "vbl/vbl.h"

#define VBL_BENCH_SEL_LIGHT_PATHS 1000
#define VBL_BENCH_SEL_K 4

/* ---- what is compared: one line per scene / method --------------------------------------- */

#define BENCH_METHOD_COUNT 7 /* bench_methods[] below: pt, vpl, vrl, vbl, beams, vrl-sel, vbl-sel */

typedef struct bench_scene {
    const char* name;
    const char* file;        /* relative to the source tree */
    double reference_factor; /* x --reference-seconds (pt converges slower on the dense cloud) */
    /* per method of bench_methods[]: light paths per pass for this scene; 0: the method's
     * default, -1: the method is skipped for this scene (the reason is next to the table) */
    int light_paths[BENCH_METHOD_COUNT];
} bench_scene;

static const bench_scene bench_scenes[] = {
    {"cloud", "samples/cloud.json", 1.0, {0}},            /* density 12, albedo 0.95, g = 0.5 */
    {"dense", "bench/scenes/cloud_dense.json", 2.5, {0}}, /* density 48, albedo 0.95, g = 0.8 */
    /* the sample cloud as smoke in a room with a glossy Phong floor, a GGX box and a spot light
     * (issue 6). Surfaces add surface_direct, surface_from_surface, surface_from_volume and
     * volume_from_surface. beams is skipped: photon beams gather only volume layers (no surface
     * estimator), so its beauty would lack every surface layer and its curve would measure the
     * missing light, not convergence. vrl / vbl passes are expensive here (surface gathers):
     * at 96x72 one pass costs ~1.4 s (vpl, 100 light paths), ~3 s (vrl, 30), ~2 s (vbl, 10),
     * about linear in the light paths (4x the paths: 4-6x the time, no better error at equal
     * time), so the cloud's counts stand: 40-80 passes in a 120 s budget. The pt reference needs
     * 2.5x (surface_from_volume is pt's noisiest layer here). */
    {"smoky_room", "samples/smoky_room.json", 2.5, {0, 100, 30, 10, -1}},
};

/* Methods by name (skipped when this build does not know or implement them): pass settings
 * chosen from bench_methods (equal-time light-path counts) and the presets. */
typedef struct bench_method {
    const char* label;
    const char* method;
    int spp, light_paths;
    int select; /* vrl_select: VRLs per camera sample from the light tree; 0: every VRL */
} bench_method;

static const bench_method bench_methods[BENCH_METHOD_COUNT] = {
    {"pt", "pt", 4, 0, 0},
    {"vpl", "vpl", 1, 100, 0},
    {"vrl", "vrl", 1, 30, 0},
    {"vbl", "vbl", 1, 10, 0},
    {"beams", "beams", 1, 100, 0},
    /* per-camera-ray selection from the light tree (issue 13): K VRLs per camera sample, so a
     * pass affords many more light paths */
    {"vrl-sel", "vrl", 1, VBL_BENCH_SEL_LIGHT_PATHS, VBL_BENCH_SEL_K},
    {"vbl-sel", "vbl", 1, VBL_BENCH_SEL_LIGHT_PATHS, VBL_BENCH_SEL_K},
};

static const char* const bench_presets[] = {"preview", "production", "final"};

/* ---- layers ------------------------------------------------------------------------------ */

#define VFV 7 /* volume_from_volume's index in bench_layer_names */

/* ---- arguments --------------------------------------------------------------------------- */

typedef struct bench_args {
    const char* vdb;
    const char* csv;
    int width, height, threads;
    double budget, reference_seconds;
    char scenes[256], methods[256];
    int presets, methods_on;
    double vbl_radius0, vbl_alpha; /* for the method runs; 0: the library's defaults */
} bench_args;

static vbl_scene* load_scene(const bench_args* a, const bench_scene* s)
{
    return bench_load_scene("bench_curves", VBL_BENCH_SOURCE_DIR, s->file, a->vdb, a->width, a->height);
}

/* ---- reference --------------------------------------------------------------------------- */

static void make_reference(const vbl_scene* scene, const bench_args* a, const bench_scene* s, bench_reference* r)
{
    bench_reference_request q = {"bench_curves", VBL_BENCH_CACHE_DIR, s->name, s->file, a->vdb, a->width, a->height,
                                 a->threads, a->reference_seconds * s->reference_factor, 0};
    bench_reference_make(scene, &q, r);
    for (int l = 0; l < BENCH_LAYERS; ++l)
        if (r->present[l])
            printf("# reference %s %-20s own rMAE (floor) ~ %.4f\n", s->name, bench_layer_label(l), r->floor_rmae[l]);
    int vd = 3, vfv = VFV;
    if (r->present[vd] && r->present[vfv]) {
        double svd = 0.0, svfv = 0.0;
        for (int i = 0; i < 3 * r->n; ++i) {
            svd += r->ref[(size_t)vd * 3 * r->n + i];
            svfv += r->ref[(size_t)vfv * 3 * r->n + i];
        }
        printf("# reference %s: volume_from_volume / volume_direct (sums over the image) = %.3f\n", s->name,
               svd > 0.0 ? svfv / svd : NAN);
    }
}

/* ---- one progressive render -------------------------------------------------------------- */

typedef struct curve_point {
    int pass;
    double seconds;
    double err[BENCH_LAYERS];
    double ratio[BENCH_LAYERS]; /* sum I / sum Iref: a layer's bias shows here */
} curve_point;

typedef struct curve {
    const bench_reference* ref;
    double budget;     /* stop after the pass that passes it; <= 0: run all passes */
    double max_seconds;
    double overhead;   /* seconds spent in this callback so far */
    double next_record;
    float* img;
    curve_point* points;
    int count, capacity;
    int stopped;
} curve;

static int on_pass(const vbl_render_progress* progress, void* user)
{
    curve* c = user;
    double t0 = omp_get_wtime();
    double seconds = progress->elapsed_seconds - c->overhead;
    int last = progress->pass >= progress->passes;
    int stop = (c->budget > 0.0 && seconds >= c->budget) || seconds >= c->max_seconds;
    /* record every pass up to 16, then passes ~6% apart, and always the last one */
    if (progress->pass <= 16 || progress->pass >= c->next_record || last || stop) {
        vbl_film* film = NULL;
        if (vbl_render_snapshot(progress, &film)) {
            fprintf(stderr, "bench_curves: %s\n", vbl_last_error_message());
            exit(1);
        }
        if (c->count == c->capacity) {
            c->capacity = c->capacity ? 2 * c->capacity : 64;
            c->points = realloc(c->points, sizeof *c->points * (size_t)c->capacity);
            if (!c->points) exit(1);
        }
        curve_point* p = &c->points[c->count++];
        p->pass = progress->pass;
        p->seconds = seconds;
        for (int l = 0; l < BENCH_LAYERS; ++l) {
            p->err[l] = p->ratio[l] = NAN;
            if (!c->ref->present[l]) continue;
            bench_film_rgb(film, l, c->ref->n, c->img);
            const float* rl = c->ref->ref + (size_t)l * 3 * c->ref->n;
            p->err[l] = bench_rmae(c->img, rl, 3 * c->ref->n);
            double si = 0.0, sr = 0.0;
            for (int i = 0; i < 3 * c->ref->n; ++i) {
                si += c->img[i];
                sr += rl[i];
            }
            p->ratio[l] = sr != 0.0 ? si / sr : NAN;
        }
        vbl_film_release(film);
        c->next_record = progress->pass * 1.06;
    }
    c->overhead += omp_get_wtime() - t0;
    if (stop && !last) c->stopped = 1;
    return stop;
}

/* First time the layer's rMAE reaches `threshold`, interpolated log-log; NAN if never. */
static double time_to(const curve* c, int l, double threshold)
{
    for (int i = 0; i < c->count; ++i) {
        double e = c->points[i].err[l];
        if (!(e <= threshold)) continue;
        if (i == 0) return c->points[0].seconds;
        double e0 = c->points[i - 1].err[l], t0 = c->points[i - 1].seconds, t1 = c->points[i].seconds;
        if (!(e0 > threshold) || !(t0 > 0.0) || e <= 0.0) return t1;
        double f = (log(threshold) - log(e0)) / (log(e) - log(e0));
        return exp(log(t0) + f * (log(t1) - log(t0)));
    }
    return NAN;
}

typedef struct run_summary {
    char label[64];
    char settings[160];
    int ok;
    int passes;
    double seconds;
    double err_end[BENCH_LAYERS], ratio_end[BENCH_LAYERS];
    double t10[BENCH_LAYERS], t05[BENCH_LAYERS];
} run_summary;

static void run_one(const vbl_scene* scene, const bench_args* a, const bench_reference* ref, const char* scene_name,
                    const vbl_render_options* base, double budget, const char* label, FILE* csv, run_summary* out)
{
    memset(out, 0, sizeof *out);
    snprintf(out->label, sizeof out->label, "%s", label);
    curve c;
    memset(&c, 0, sizeof c);
    c.ref = ref;
    c.budget = budget;
    c.max_seconds = budget > 0.0 ? 1e30 : 4.0 * a->budget;
    c.img = malloc(sizeof(float) * 3 * (size_t)ref->n);
    if (!c.img) exit(1);
    vbl_render_options o = *base;
    o.threads = a->threads;
    o.callback = on_pass;
    o.callback_user_data = &c;
    if (budget > 0.0)
        snprintf(out->settings, sizeof out->settings, "%s spp=%d lp=%d", vbl_render_method_name(o.method), o.spp,
                 o.light_paths);
    else
        snprintf(out->settings, sizeof out->settings, "%s %d passes x spp=%d lp=%d alpha=%g",
                 vbl_render_method_name(o.method), o.passes, o.spp, o.light_paths, o.beam_lights.alpha);
    vbl_film* film = NULL;
    vbl_result r = vbl_render(scene, &o, &film);
    if (film) vbl_film_release(film);
    if (r && r != VBL_ERROR_INTERRUPTED) {
        printf("# %s %s: skipped (%s)\n", scene_name, label, vbl_last_error_message());
        free(c.img);
        free(c.points);
        return;
    }
    out->ok = c.count > 0;
    if (!out->ok) {
        free(c.img);
        return;
    }
    const curve_point* last = &c.points[c.count - 1];
    out->passes = last->pass;
    out->seconds = last->seconds;
    for (int l = 0; l < BENCH_LAYERS; ++l) {
        out->err_end[l] = last->err[l];
        out->ratio_end[l] = last->ratio[l];
        out->t10[l] = time_to(&c, l, 0.1);
        out->t05[l] = time_to(&c, l, 0.05);
    }
    if (c.stopped && budget <= 0.0)
        printf("# %s %s: stopped at the cap of %.0f s after %d of %d passes\n", scene_name, label, c.max_seconds,
               last->pass, o.passes);
    for (int i = 0; csv && i < c.count; ++i) {
        const curve_point* p = &c.points[i];
        fprintf(csv, "%s,%s,%d,%.4f", label, scene_name, p->pass, p->seconds);
        for (int l = 0; l < BENCH_LAYERS; ++l) {
            if (isnan(p->err[l])) fprintf(csv, ",");
            else fprintf(csv, ",%.6f", p->err[l]);
        }
        fputc('\n', csv);
    }
    if (csv) fflush(csv);
    free(c.img);
    free(c.points);
}

static void print_time(double t)
{
    if (isnan(t)) printf(" not reached |");
    else printf(" %.2f s |", t);
}

int main(int argc, char** argv)
{
    bench_args a;
    memset(&a, 0, sizeof a);
    a.vdb = VBL_BENCH_DEFAULT_VDB;
    a.csv = VBL_BENCH_CACHE_DIR "/curves.csv";
    a.width = 96;
    a.height = 72;
    a.threads = 2;
    a.budget = 30.0;
    a.reference_seconds = 240.0;
    a.presets = 1;
    a.methods_on = 1;
    snprintf(a.scenes, sizeof a.scenes, "cloud,dense,smoky_room");
    snprintf(a.methods, sizeof a.methods, "pt,vpl,vrl,vbl,beams");
    for (int i = 1; i < argc; ++i) {
        if (!strcmp(argv[i], "--no-presets")) {
            a.presets = 0;
            continue;
        }
        if (!strcmp(argv[i], "--presets-only")) {
            a.methods_on = 0;
            continue;
        }
        const char* v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!v) goto usage;
        if (!strcmp(argv[i], "--vdb")) a.vdb = v;
        else if (!strcmp(argv[i], "--csv")) a.csv = v;
        else if (!strcmp(argv[i], "--res")) {
            if (sscanf(v, "%dx%d", &a.width, &a.height) != 2 || a.width < 1 || a.height < 1) goto usage;
        } else if (!strcmp(argv[i], "--budget")) a.budget = atof(v);
        else if (!strcmp(argv[i], "--reference-seconds")) a.reference_seconds = atof(v);
        else if (!strcmp(argv[i], "--threads")) a.threads = atoi(v);
        else if (!strcmp(argv[i], "--scenes")) snprintf(a.scenes, sizeof a.scenes, "%s", v);
        else if (!strcmp(argv[i], "--methods")) snprintf(a.methods, sizeof a.methods, "%s", v);
        else if (!strcmp(argv[i], "--vbl-radius0")) a.vbl_radius0 = atof(v);
        else if (!strcmp(argv[i], "--vbl-alpha")) a.vbl_alpha = atof(v);
        else goto usage;
        ++i;
    }
    if (!(a.budget > 0.0) || !(a.reference_seconds > 0.0) || a.threads < 0 || a.vbl_radius0 < 0.0 ||
        a.vbl_alpha < 0.0 || a.vbl_alpha >= 1.0)
        goto usage;

    FILE* csv = fopen(a.csv, "w");
    if (!csv) {
        fprintf(stderr, "bench_curves: cannot write %s\n", a.csv);
        return 1;
    }
    fprintf(csv, "method,scene,pass,seconds");
    for (int l = 0; l < BENCH_LAYERS; ++l) fprintf(csv, ",rmae_%s", bench_layer_label(l));
    fputc('\n', csv);

    double load[3] = {0};
    FILE* lf = fopen("/proc/loadavg", "r");
    if (lf) {
        if (fscanf(lf, "%lf %lf %lf", &load[0], &load[1], &load[2]) != 3) load[0] = -1;
        fclose(lf);
    }
    printf("# bench_curves: %dx%d, threads %d, budget %g s per method, reference %g s, load average at start "
           "%.2f %.2f %.2f\n",
           a.width, a.height, a.threads, a.budget, a.reference_seconds, load[0], load[1], load[2]);
    fflush(stdout);

    enum { MAX_RUNS = 16 };
    for (size_t s = 0; s < sizeof bench_scenes / sizeof bench_scenes[0]; ++s) {
        const bench_scene* bs = &bench_scenes[s];
        if (!bench_in_list(a.scenes, bs->name)) continue;
        vbl_scene* scene = load_scene(&a, bs);
        bench_reference ref;
        memset(&ref, 0, sizeof ref);
        make_reference(scene, &a, bs, &ref);
        fflush(stdout);
        /* the reference's own error: one row per scene, method "reference_floor", pass 0 */
        fprintf(csv, "reference_floor,%s,0,%.1f", bs->name, a.reference_seconds * bs->reference_factor);
        for (int l = 0; l < BENCH_LAYERS; ++l) {
            if (isnan(ref.floor_rmae[l])) fprintf(csv, ",");
            else fprintf(csv, ",%.6f", ref.floor_rmae[l]);
        }
        fputc('\n', csv);
        run_summary runs[MAX_RUNS];
        int rc = 0;
        for (size_t m = 0; a.methods_on && m < sizeof bench_methods / sizeof bench_methods[0]; ++m) {
            const bench_method* bm = &bench_methods[m];
            vbl_render_method method;
            if (!bench_in_list(a.methods, bm->label)) continue;
            if (vbl_render_method_parse(bm->method, &method)) {
                printf("# method %s: not in this build, skipped\n", bm->method);
                continue;
            }
            vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
            vbl_scene_render_options(scene, &o);
            o.method = method;
            o.spp = bm->spp;
            o.light_paths = bm->light_paths;
            o.vrl.select = bm->select;
            if (bs->light_paths[m] < 0) {
                printf("# %s %s: skipped for this scene (see bench_scenes[])\n", bs->name, bm->label);
                continue;
            }
            if (bs->light_paths[m] > 0) o.light_paths = bs->light_paths[m];
            o.passes = 1 << 30;
            o.seed = 1000003u + 31u * (uint64_t)m;
            o.beam_lights.radius0 = a.vbl_radius0;
            o.beam_lights.alpha = a.vbl_alpha;
            run_one(scene, &a, &ref, bs->name, &o, a.budget, bm->label, csv, &runs[rc]);
            if (runs[rc].ok) ++rc;
        }
        for (size_t p = 0; a.presets && p < sizeof bench_presets / sizeof bench_presets[0]; ++p) {
            vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
            vbl_scene_render_options(scene, &o);
            if (vbl_render_options_apply_preset(bench_presets[p], &o)) {
                printf("# preset %s: %s\n", bench_presets[p], vbl_last_error_message());
                continue;
            }
            o.seed = 2000003u + 31u * (uint64_t)p;
            run_one(scene, &a, &ref, bs->name, &o, 0.0, bench_presets[p], csv, &runs[rc]);
            if (runs[rc].ok) ++rc;
        }
        /* time to 0.1 / 0.05 for beauty and volume_from_volume, end error for every layer */
        printf("\n### %s (reference floor: medium %.4f, beauty %.4f, volume_from_volume %.4f)\n\n", bs->name,
               ref.floor_rmae[BENCH_LAYER_MEDIUM], ref.floor_rmae[0], ref.floor_rmae[VFV]);
        printf("| run | settings | passes | seconds | medium rMAE | beauty rMAE | vfv rMAE | medium t(0.1) | "
               "medium t(0.05) | beauty t(0.1) | beauty t(0.05) |\n|---|---|---|---|---|---|---|---|---|---|---|\n");
        for (int i = 0; i < rc; ++i) {
            const run_summary* r = &runs[i];
            printf("| %s | %s | %d | %.2f | %.4f | %.4f | %.4f |", r->label, r->settings, r->passes, r->seconds,
                   r->err_end[BENCH_LAYER_MEDIUM], r->err_end[0], r->err_end[VFV]);
            print_time(r->t10[BENCH_LAYER_MEDIUM]);
            print_time(r->t05[BENCH_LAYER_MEDIUM]);
            print_time(r->t10[0]);
            print_time(r->t05[0]);
            putchar('\n');
        }
        printf("\n| run | end rMAE (sum / reference sum) per layer |\n|---|---|\n");
        for (int i = 0; i < rc; ++i) {
            printf("| %s |", runs[i].label);
            for (int l = 1; l < BENCH_LAYER_MEDIUM; ++l)
                if (ref.present[l]) printf(" %s %.4f (%.3f)", bench_layer_label(l), runs[i].err_end[l], runs[i].ratio_end[l]);
            printf(" |\n");
        }
        /* per layer: time to 0.1 / 0.05, rMAE at the end (budget), energy check sum / reference sum */
        printf("\n| run | layer | t(0.1) | t(0.05) | rMAE at end | sum / ref sum |\n|---|---|---|---|---|---|\n");
        for (int i = 0; i < rc; ++i)
            for (int l = 0; l <= BENCH_LAYER_MEDIUM; ++l) {
                if (!ref.present[l] || l == 1) continue; /* emission: exact in every method */
                printf("| %s | %s |", runs[i].label, bench_layer_label(l));
                print_time(runs[i].t10[l]);
                print_time(runs[i].t05[l]);
                printf(" %.4f | %.3f |\n", runs[i].err_end[l], runs[i].ratio_end[l]);
            }
        printf("\n");
        fflush(stdout);
        free(ref.halves);
        free(ref.ref);
        vbl_scene_release(scene);
    }
    fclose(csv);
    return 0;
usage:
    fprintf(stderr, "usage: bench_curves [--budget S] [--reference-seconds S] [--res WxH] [--threads N] "
                    "[--scenes cloud,dense,smoky_room] [--methods pt,vpl,vrl,vbl,beams,vrl-sel,vbl-sel] [--no-presets] [--presets-only] "
                    "[--vbl-radius0 R] [--vbl-alpha A] [--vdb FILE] [--csv FILE]\n");
    return 2;
}
