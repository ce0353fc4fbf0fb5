/* Issue 13 item 4 benchmark: the artifact-free vbl at equal CPU time against pt (and vrl), on the
 * sample cloud and the dense bench cloud.
 *
 *   build/bench/bench_vbl_artifacts [--res 48x36] [--cpu 20] [--reference-seconds 60]
 *       [--scenes cloud,dense] [--configs pt,vrl,vbl-old,vbl-optical,vbl] [--mfp 0.5] [--threads-ref 2]
 *
 * Every configuration is ONE progressive render on one thread; its pass callback records, at the
 * process CPU time spent so far (minus the callback's own), for the "medium" light (beauty -
 * background: what the media scatter) and for volume_from_volume:
 *   - rMAE = sum |I - Iref| / sum |Iref| (R, G, B);
 *   - energy = sum I / sum Iref (a layer's bias);
 *   - fireflies = pixels whose medium (mean of R, G, B) exceeds 10 x the reference's, among pixels
 *     where the reference is above 1e-3 of its mean.
 * The render stops after the pass that passes --cpu seconds. pt's curve is then read at each
 * configuration's final CPU time (the first recorded pt pass at or past it): "pt at equal time".
 * The time to medium rMAE 0.1 is the first recorded point at or below it.
 * Configurations: pt (4 spp per pass), vrl (defaults), vbl-old (vbl with both issue-13 changes
 * off: --vbl-kernel-tolerance 0 and radius_mfp 1e30, which is bit-identical to the previous
 * estimator), vbl-optical (radius_mfp --mfp, kernel tolerance 0), vbl (the defaults).
 * The reference (bench_reference.h, pt, two halves, cached in the build dir) is rendered with
 * --threads-ref threads for --reference-seconds of wall time. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bench_reference.h"
#include "scene/scene.h"
#include "vbl/vbl.h"

typedef struct point {
    double cpu, rmae_medium, rmae_vfv, energy_medium, energy_vfv;
    int fireflies;
} point;

typedef struct curve {
    const bench_reference* ref;
    const float* ref_medium; /* n * 3 */
    double budget, start, overhead;
    float *img, *bg;
    point* p;
    int count, cap;
} curve;

static double cpu_now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

static void layer_rgb(const vbl_film* film, const char* name, int n, float* out)
{
    int ch = 0;
    const float* p = vbl_film_layer(film, name, &ch);
    for (int i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k) out[3 * i + k] = p && ch >= 3 ? p[(size_t)ch * i + k] : 0.0f;
}

static void stats(const float* img, const float* ref, int n, double* rmae, double* energy)
{
    double e = 0.0, s = 0.0, si = 0.0;
    for (int i = 0; i < 3 * n; ++i) {
        e += fabs(img[i] - ref[i]);
        s += fabs(ref[i]);
        si += img[i];
    }
    *rmae = s > 0.0 ? e / s : NAN;
    *energy = s > 0.0 ? si / s : NAN;
}

static int count_fireflies(const float* img, const float* ref, int n)
{
    double mean = 0.0;
    for (int i = 0; i < 3 * n; ++i) mean += ref[i] / (3.0 * n);
    int c = 0;
    for (int i = 0; i < n; ++i) {
        double a = (img[3 * i] + img[3 * i + 1] + img[3 * i + 2]) / 3.0;
        double b = (ref[3 * i] + ref[3 * i + 1] + ref[3 * i + 2]) / 3.0;
        if (b > 1e-3 * mean && a > 10.0 * b) ++c;
    }
    return c;
}

static int on_pass(const vbl_render_progress* progress, void* user)
{
    curve* c = user;
    double t0 = cpu_now();
    double cpu = t0 - c->start - c->overhead;
    vbl_film* film = NULL;
    if (vbl_render_snapshot(progress, &film)) {
        fprintf(stderr, "bench_vbl_artifacts: %s\n", vbl_last_error_message());
        exit(1);
    }
    const int n = c->ref->n;
    if (c->count == c->cap) {
        c->cap = c->cap ? 2 * c->cap : 64;
        c->p = realloc(c->p, sizeof *c->p * (size_t)c->cap);
        if (!c->p) exit(1);
    }
    point* p = &c->p[c->count++];
    p->cpu = cpu;
    layer_rgb(film, "", n, c->img);
    layer_rgb(film, "background", n, c->bg);
    for (int i = 0; i < 3 * n; ++i) c->img[i] -= c->bg[i];
    stats(c->img, c->ref_medium, n, &p->rmae_medium, &p->energy_medium);
    p->fireflies = count_fireflies(c->img, c->ref_medium, n);
    layer_rgb(film, "volume_from_volume", n, c->img);
    stats(c->img, c->ref->ref + (size_t)7 * 3 * n, n, &p->rmae_vfv, &p->energy_vfv);
    vbl_film_release(film);
    c->overhead += cpu_now() - t0;
    return cpu >= c->budget;
}

static void run(const vbl_scene* scene, const vbl_render_options* base, curve* c)
{
    vbl_render_options o = *base;
    o.threads = 1;
    o.passes = 1000000;
    o.callback = on_pass;
    o.callback_user_data = c;
    c->count = 0;
    c->overhead = 0.0;
    c->start = cpu_now();
    vbl_film* film = NULL;
    vbl_result r = vbl_render(scene, &o, &film);
    if (film) vbl_film_release(film);
    if (r && r != VBL_ERROR_INTERRUPTED) {
        fprintf(stderr, "bench_vbl_artifacts: %s\n", vbl_last_error_message());
        exit(1);
    }
}

static double time_to(const curve* c, double thr)
{
    for (int i = 0; i < c->count; ++i)
        if (c->p[i].rmae_medium <= thr) return c->p[i].cpu;
    return NAN;
}

static const point* at_time(const curve* c, double cpu)
{
    for (int i = 0; i < c->count; ++i)
        if (c->p[i].cpu >= cpu) return &c->p[i];
    return c->count ? &c->p[c->count - 1] : NULL;
}

int main(int argc, char** argv)
{
    int width = 48, height = 36, threads_ref = 2;
    double cpu_budget = 20.0, ref_seconds = 60.0, mfp = 0.5;
    const char* scenes = "cloud,dense";
    const char* configs = "pt,vrl,vbl-old,vbl-optical,vbl";
    for (int i = 1; i + 1 < argc; i += 2) {
        const char* v = argv[i + 1];
        if (!strcmp(argv[i], "--res")) sscanf(v, "%dx%d", &width, &height);
        else if (!strcmp(argv[i], "--cpu")) cpu_budget = atof(v);
        else if (!strcmp(argv[i], "--reference-seconds")) ref_seconds = atof(v);
        else if (!strcmp(argv[i], "--scenes")) scenes = v;
        else if (!strcmp(argv[i], "--configs")) configs = v;
        else if (!strcmp(argv[i], "--mfp")) mfp = atof(v);
        else if (!strcmp(argv[i], "--threads-ref")) threads_ref = atoi(v);
        else {
            fprintf(stderr, "bench_vbl_artifacts: unknown option %s\n", argv[i]);
            return 2;
        }
    }
    const char* names[2] = {"cloud", "dense"};
    const char* files[2] = {"samples/cloud.json", "bench/scenes/cloud_dense.json"};
    const double ref_factor[2] = {1.0, 2.5};
    const char* labels[5] = {"pt", "vrl", "vbl-old", "vbl-optical", "vbl"};
    for (int s = 0; s < 2; ++s) {
        if (!bench_in_list(scenes, names[s])) continue;
        vbl_scene* scene =
            bench_load_scene("bench_vbl_artifacts", VBL_BENCH_SOURCE_DIR, files[s], VBL_BENCH_DEFAULT_VDB, width, height);
        bench_reference ref;
        bench_reference_request q = {"bench_vbl_artifacts", VBL_BENCH_CACHE_DIR, names[s], files[s],
                                     VBL_BENCH_DEFAULT_VDB, width, height, threads_ref, ref_seconds * ref_factor[s], 0};
        bench_reference_make(scene, &q, &ref);
        const int n = ref.n;
        /* the reference's medium: beauty - background, the background (seen directly, the same in
         * every method) from one 16-pass pt render */
        float* ref_medium = malloc(sizeof(float) * 3 * (size_t)n);
        float* img = malloc(sizeof(float) * 3 * (size_t)n);
        float* bg = malloc(sizeof(float) * 3 * (size_t)n);
        if (!ref_medium || !img || !bg) return 1;
        curve curves[5];
        memset(curves, 0, sizeof curves);
        {
            vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
            vbl_scene_render_options(scene, &o);
            o.method = VBL_RENDER_PT;
            o.passes = 16;
            o.threads = threads_ref;
            vbl_film* f = NULL;
            if (vbl_render(scene, &o, &f)) {
                fprintf(stderr, "bench_vbl_artifacts: %s\n", vbl_last_error_message());
                return 1;
            }
            layer_rgb(f, "background", n, bg);
            vbl_film_release(f);
            for (int i = 0; i < 3 * n; ++i) ref_medium[i] = ref.ref[i] - bg[i];
        }
        printf("# %s %dx%d: reference %.0f s, own rMAE beauty %.4f volume_from_volume %.4f\n", names[s], width, height,
               ref.seconds, ref.floor_rmae[0], ref.floor_rmae[7]);
        printf("| scene | config | CPU s | passes | medium rMAE | medium energy | vfv energy | fireflies | pt at that CPU: "
               "medium rMAE, energy, fireflies | time to medium rMAE 0.1 |\n|---|---|---|---|---|---|---|---|---|---|\n");
        for (int k = 0; k < 5; ++k) {
            if (!bench_in_list(configs, labels[k])) continue;
            curve* c = &curves[k];
            c->ref = &ref;
            c->ref_medium = ref_medium;
            c->budget = cpu_budget;
            c->img = img;
            c->bg = bg;
            vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
            vbl_scene_render_options(scene, &o);
            o.light_paths = 0; /* the method's default */
            if (k == 0) {
                o.method = VBL_RENDER_PT;
                o.spp = 4;
            } else {
                o.method = k == 1 ? VBL_RENDER_VRL : VBL_RENDER_VBL;
                o.spp = 1;
                if (k == 2) {
                    o.beam_lights.kernel_tolerance = 0.0;
                    o.beam_lights.radius_mfp = 1e30;
                } else if (k == 3) {
                    o.beam_lights.kernel_tolerance = 0.0;
                    o.beam_lights.radius_mfp = mfp;
                } else {
                    o.beam_lights.radius_mfp = mfp;
                }
            }
            run(scene, &o, c);
            const point* e = &c->p[c->count - 1];
            const point* pt = curves[0].count ? at_time(&curves[0], e->cpu) : NULL;
            printf("| %s | %s | %.1f | %d | %.3f | %.3f | %.3f | %d |", names[s], labels[k], e->cpu, c->count,
                   e->rmae_medium, e->energy_medium, e->energy_vfv, e->fireflies);
            if (pt && k > 0) printf(" %.3f, %.3f, %d |", pt->rmae_medium, pt->energy_medium, pt->fireflies);
            else printf(" |");
            double t = time_to(c, 0.1);
            if (isnan(t)) printf(" not reached |\n");
            else printf(" %.2f s |\n", t);
            fflush(stdout);
        }
        for (int k = 0; k < 5; ++k) free(curves[k].p);
        free(ref_medium);
        free(img);
        free(bg);
        free(ref.halves);
        free(ref.ref);
        vbl_scene_release(scene);
    }
    return 0;
}
