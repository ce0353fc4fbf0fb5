/* Issue 13, "measure first": where a vrl / vbl pass spends its time and how many VRLs matter to
 * one camera ray.
 *
 *   build/bench/bench_vrl_profile [--scenes cloud,dense] [--light-paths 30] [--res 32x24]
 *       [--select 0,1,4,16] [--threads 1]
 *
 * Per scene (samples/cloud.json, bench/scenes/cloud_dense.json at --res):
 *   - photon trace + store build time of one pass (vrl and vbl stores), VRL count;
 *   - camera-sample time per pixel sample (one sample per pixel of the --res image) of vrl and vbl
 *     for each K of --select (0: every VRL, the method's default);
 *   - concentration: for every pixel, each VRL's estimate (vbl_vrl_contributions, 4 averaged
 *     samples); the number of VRLs that hold 50 / 90 / 99 % of the pixel's total (median over
 *     pixels with a non-zero total), and the visible fraction of the camera ray's media overlap
 *     (cached transmittance >= VBL_VRL_SELECT_VISIBLE_CUT).
 *   - efficiency on one store: per-pixel variance of 12 camera samples (every 3rd pixel), every
 *     VRL vs K selected (heavy tails make it noisy: a relative variance near 12 means one sample
 *     dominated);
 *   - selection quality: sum_j c_j^2 / pdf_j / (sum_j c_j)^2 of one light drawn from the tree
 *     (1 = ideal) and of uniform selection, median and mean over pixels.
 * Environment (diagnostics): VRL_REPS (samples per VRL for the concentration, default 4),
 * VRL_STRIDE (every n-th pixel, default 1), VRL_DEBUG / VRL_DEBUG2 (print the top VRLs of some
 * pixels by contribution and by tree pdf).
 * Times are wall clock with --threads threads (default 1: per-sample costs), on a shared machine:
 * compare ratios within one run. */
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_reference.h"
#include "scene/scene.h"
#include "transport/common/estimator.h"
#include "transport/common/photon_trace.h"
#include "transport/virtual_lights/virtual_beam_lights.h"
#include "transport/virtual_lights/vrl.h"
#include "vbl/vbl.h"

static int cmp_desc(const void* a, const void* b)
{
    double x = *(const double*)a, y = *(const double*)b;
    return x < y ? 1 : (x > y ? -1 : 0);
}

static int cmp_int(const void* a, const void* b) { return *(const int*)a - *(const int*)b; }

static void fail(void)
{
    fprintf(stderr, "bench_vrl_profile: %s\n", vbl_last_error_message());
    exit(1);
}

typedef vbl_result (*begin_fn)(const vbl_render_context*, int, void**);
static vbl_result vrl_begin(const vbl_render_context* ctx, int k, void** store)
{
    vbl_vrl_settings s;
    vbl_vrl_settings_from_options(&ctx->options, &s);
    s.select = k;
    return vbl_vl_pass_begin(ctx, &vbl_vl_kernel_ray, &s, store);
}
static vbl_result vbl_begin(const vbl_render_context* ctx, int k, void** store)
{
    vbl_beam_light_settings s;
    vbl_beam_light_settings_from_options(&ctx->options, &s);
    s.select = k;
    return vbl_vl_pass_begin(ctx, &vbl_vl_kernel_beam, &s, store);
}

/* Seconds per camera sample over the image (one sample per pixel, pixel streams as the driver). */
static double time_samples(const vbl_render_context* ctx, const void* store,
                           void (*sample)(const vbl_render_context*, const void*, vbl_thread_state*,
                                          const vbl_camera_sample*, vbl_rng*, vbl_sample_value*),
                           int threads, double* mean_vfv)
{
    const vbl_camera* cam = &ctx->scene->camera;
    const int w = cam->width, h = cam->height;
    double sum = 0.0;
    double t0 = omp_get_wtime();
#pragma omp parallel num_threads(threads) reduction(+ : sum)
    {
        vbl_thread_state ts;
        memset(&ts, 0, sizeof ts);
        vbl_extinction_cursor_init(&ts.cursor, ctx->extinction);
#pragma omp for schedule(dynamic, 4)
        for (int p = 0; p < w * h; ++p) {
            vbl_camera_sample cs;
            memset(&cs, 0, sizeof cs);
            cs.px = p % w;
            cs.py = p / w;
            cs.pixel_index = (uint64_t)p;
            cs.sx = cs.px + 0.5;
            cs.sy = cs.py + 0.5;
            vbl_camera_ray(cam, cs.sx, cs.sy, &cs.origin, &cs.direction);
            cs.t_max = INFINITY;
            vbl_rng rng = vbl_rng_make(99, 0, (uint64_t)p);
            vbl_sample_value v;
            memset(&v, 0, sizeof v);
            sample(ctx, store, &ts, &cs, &rng, &v);
            vbl_vec3 f = v.L[VBL_CLASS_VOLUME_FROM_VOLUME];
            sum += f.x + f.y + f.z;
        }
    }
    *mean_vfv = sum / (w * h);
    return (omp_get_wtime() - t0) * threads / (w * h);
}

int main(int argc, char** argv)
{
    const char* scenes = "cloud,dense";
    const char* selects = "0,1,4,16";
    int light_paths = 30, width = 32, height = 24, threads = 1;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!strcmp(argv[i], "--scenes")) scenes = argv[i + 1];
        else if (!strcmp(argv[i], "--select")) selects = argv[i + 1];
        else if (!strcmp(argv[i], "--light-paths")) light_paths = atoi(argv[i + 1]);
        else if (!strcmp(argv[i], "--threads")) threads = atoi(argv[i + 1]);
        else if (!strcmp(argv[i], "--res")) {
            if (sscanf(argv[i + 1], "%dx%d", &width, &height) != 2) return 2;
        } else {
            fprintf(stderr, "usage: bench_vrl_profile [--scenes cloud,dense] [--light-paths N] [--res WxH] "
                            "[--select 0,1,4,16] [--threads N]\n");
            return 2;
        }
    }
    static const char* const names[2] = {"cloud", "dense"};
    static const char* const files[2] = {"samples/cloud.json", "bench/scenes/cloud_dense.json"};
    double load = -1.0;
    FILE* lf = fopen("/proc/loadavg", "r");
    if (lf) {
        if (fscanf(lf, "%lf", &load) != 1) load = -1.0;
        fclose(lf);
    }
    printf("# bench_vrl_profile: %dx%d, %d light paths, %d threads, load %.2f\n", width, height, light_paths, threads,
           load);
    for (int sc = 0; sc < 2; ++sc) {
        if (!bench_in_list(scenes, names[sc])) continue;
        vbl_scene* scene = bench_load_scene("bench_vrl_profile", VBL_BENCH_SOURCE_DIR, files[sc], VBL_BENCH_DEFAULT_VDB,
                                            width, height);
        vbl_render_context ctx;
        memset(&ctx, 0, sizeof ctx);
        ctx.scene = scene;
        ctx.extinction = &scene->extinction;
        vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
        if (vbl_scene_render_options(scene, &o)) fail();
        o.light_paths = light_paths;
        ctx.options = o;
        ctx.tracking.estimator = VBL_TRANSMITTANCE_RATIO_TRACKING;
        ctx.threads = threads;
        printf("\n## %s\n\n", names[sc]);
        /* pass preparation */
        for (int m = 0; m < 2; ++m) {
            void* store = NULL;
            double t0 = omp_get_wtime();
            if ((m ? vbl_begin : vrl_begin)(&ctx, 0, &store)) fail();
            double t1 = omp_get_wtime();
            const vbl_photon_store* ph = m ? vbl_vl_photons(store) : vbl_vl_photons(store);
            size_t n = ph->vrl_count;
            if (m) vbl_vl_pass_end(&ctx, store);
            else vbl_vl_pass_end(&ctx, store);
            void* tstore = NULL;
            double t2 = omp_get_wtime();
            if ((m ? vbl_begin : vrl_begin)(&ctx, 4, &tstore)) fail();
            double t3 = omp_get_wtime();
            if (m) vbl_vl_pass_end(&ctx, tstore);
            else vbl_vl_pass_end(&ctx, tstore);
            printf("%s pass begin: %zu VRLs, %.4f s (with the light tree %.4f s)\n", m ? "vbl" : "vrl", n, t1 - t0,
                   t3 - t2);
        }
        /* camera samples */
        printf("\n| method | select K | us per camera sample | mean volume_from_volume (sum RGB) |\n|---|---|---|---|\n");
        for (int m = 0; m < 2; ++m) {
            char list[256];
            snprintf(list, sizeof list, "%s", selects);
            for (char* tok = strtok(list, ","); tok; tok = strtok(NULL, ",")) {
                int k = atoi(tok);
                void* store = NULL;
                if ((m ? vbl_begin : vrl_begin)(&ctx, k, &store)) fail();
                double mean = 0.0;
                double t = time_samples(&ctx, store, m ? vbl_vl_camera_sample : vbl_vl_camera_sample, threads, &mean);
                printf("| %s | %d | %.1f | %.5g |\n", m ? "vbl" : "vrl", k, 1e6 * t, mean);
                if (m) vbl_vl_pass_end(&ctx, store);
                else vbl_vl_pass_end(&ctx, store);
            }
        }
        /* efficiency on one store: per-pixel variance of volume_from_volume over R camera samples
         * (every 3rd pixel), every VRL vs K selected, and the time of those samples */
        {
            const int R = 12;
            char list[256];
            snprintf(list, sizeof list, "%s", selects);
            printf("\n| method | select K | relative variance (sum var / sum mean^2) | mean | us per sample | efficiency vs K = 0 |\n"
                   "|---|---|---|---|---|---|\n");
            for (int m = 0; m < 2; ++m) {
                double base = 0.0;
                for (char* tok = strtok(list, ","); tok; tok = strtok(NULL, ",")) {
                    int k = atoi(tok);
                    void* st = NULL;
                    if ((m ? vbl_begin : vrl_begin)(&ctx, k, &st)) fail();
                    double sv = 0.0, sm2 = 0.0, smean = 0.0;
                    int np = 0;
                    double t0 = omp_get_wtime();
#pragma omp parallel num_threads(threads) reduction(+ : sv, sm2, smean, np)
                    {
                        vbl_thread_state ts;
                        memset(&ts, 0, sizeof ts);
                        vbl_extinction_cursor_init(&ts.cursor, ctx.extinction);
#pragma omp for schedule(dynamic, 1)
                        for (int p = 0; p < width * height; p += 3) {
                            vbl_camera_sample cs;
                            memset(&cs, 0, sizeof cs);
                            vbl_camera_ray(&scene->camera, p % width + 0.5, p / width + 0.5, &cs.origin, &cs.direction);
                            cs.t_max = INFINITY;
                            double s1 = 0.0, s2 = 0.0;
                            for (int r = 0; r < R; ++r) {
                                vbl_rng rng = vbl_rng_make(5, (uint32_t)r, (uint64_t)p);
                                vbl_sample_value v;
                                memset(&v, 0, sizeof v);
                                (m ? vbl_vl_camera_sample : vbl_vl_camera_sample)(&ctx, st, &ts, &cs, &rng, &v);
                                vbl_vec3 f = v.L[VBL_CLASS_VOLUME_FROM_VOLUME];
                                double x = f.x + f.y + f.z;
                                s1 += x;
                                s2 += x * x;
                            }
                            double mean = s1 / R;
                            sv += (s2 / R - mean * mean) * R / (R - 1);
                            sm2 += mean * mean;
                            smean += mean;
                            ++np;
                        }
                    }
                    double us = 1e6 * (omp_get_wtime() - t0) * threads / (np * R);
                    double rel = sm2 > 0.0 ? sv / sm2 : NAN;
                    double eff = 1.0 / (rel * us);
                    if (k == 0) base = eff;
                    printf("| %s | %d | %.4g | %.4g | %.1f | %.3g |\n", m ? "vbl" : "vrl", k, rel, smean / np, us,
                           base > 0.0 ? eff / base : NAN);
                    if (m) vbl_vl_pass_end(&ctx, st);
                    else vbl_vl_pass_end(&ctx, st);
                }
                snprintf(list, sizeof list, "%s", selects);
            }
        }
        /* concentration */
        void* store = NULL;
        if (vrl_begin(&ctx, 4, &store)) fail();
        const vbl_photon_store* ph = vbl_vl_photons(store);
        size_t n = ph->vrl_count;
        double* c = calloc(n ? n : 1, sizeof *c);
        double* acc = calloc(n ? n : 1, sizeof *acc);
        double* pdf = calloc(n ? n : 1, sizeof *pdf);
        double* m2 = malloc(sizeof(double) * (size_t)(width * height));
        double* m2u = malloc(sizeof(double) * (size_t)(width * height));
        int* q50 = malloc(sizeof(int) * (size_t)(width * height));
        int* q90 = malloc(sizeof(int) * (size_t)(width * height));
        int* q99 = malloc(sizeof(int) * (size_t)(width * height));
        double vis_sum = 0.0;
        int counted = 0, hit = 0;
        vbl_thread_state ts;
        memset(&ts, 0, sizeof ts);
        vbl_extinction_cursor_init(&ts.cursor, ctx.extinction);
        const int reps = getenv("VRL_REPS") ? atoi(getenv("VRL_REPS")) : 4;
        const int stride = getenv("VRL_STRIDE") ? atoi(getenv("VRL_STRIDE")) : 1;
        for (int p = 0; p < width * height; p += stride) {
            vbl_camera_sample cs;
            memset(&cs, 0, sizeof cs);
            cs.px = p % width;
            cs.py = p / width;
            vbl_camera_ray(&scene->camera, cs.px + 0.5, cs.py + 0.5, &cs.origin, &cs.direction);
            cs.t_max = INFINITY;
            memset(acc, 0, n * sizeof *acc);
            double vis = 0.0;
            int any = 0;
            for (int r = 0; r < reps; ++r) {
                vbl_rng rng = vbl_rng_make(7, (uint32_t)r, (uint64_t)p);
                double v;
                if (!vbl_vrl_contributions(&ctx, store, &ts, &cs, &rng, c, &v, pdf)) continue;
                any = 1;
                vis += v / reps;
                for (size_t j = 0; j < n; ++j) acc[j] += c[j];
            }
            if (!any) continue;
            ++hit;
            vis_sum += vis;
            double total = 0.0;
            for (size_t j = 0; j < n; ++j) total += acc[j];
            if (!(total > 0.0)) continue;
            /* relative second moment of a one-light selection estimate c_j / pdf_j (the per-light
             * estimates taken as exact): sum c_j^2 / pdf_j / total^2 (1: ideal), and for uniform
             * selection among the tree's lights */
            double s2 = 0.0, s2u = 0.0;
            int lights = 0;
            for (size_t j = 0; j < n; ++j) lights += pdf[j] > 0.0;
            for (size_t j = 0; j < n; ++j) {
                if (acc[j] == 0.0) continue;
                s2 += pdf[j] > 0.0 ? acc[j] * acc[j] / pdf[j] : INFINITY;
                s2u += acc[j] * acc[j] * lights;
            }
            if (getenv("VRL_DEBUG2") && counted == 0) {
                int* idx = malloc(sizeof(int) * n);
                for (size_t j = 0; j < n; ++j) idx[j] = (int)j;
                for (int pass = 0; pass < 2; ++pass) {
                    /* selection sort of the top 8 by contribution (pass 0) or by pdf (pass 1) */
                    for (int a = 0; a < 8 && a < (int)n; ++a) {
                        int b = a;
                        for (size_t j = a + 1; j < n; ++j) {
                            double x = pass ? pdf[idx[j]] : acc[idx[j]], y = pass ? pdf[idx[b]] : acc[idx[b]];
                            if (x > y) b = (int)j;
                        }
                        int t = idx[a]; idx[a] = idx[b]; idx[b] = t;
                        const vbl_vrl* l = &ph->vrls[idx[a]];
                        double h = vbl_segment_distance(cs.origin, cs.direction, 20.0, l->origin, l->direction, l->length);
                        printf("  by %s: VRL %d share %.3f pdf %.3g h %.3g len %.3g bounce %d\n", pass ? "pdf" : "contribution",
                               idx[a], acc[idx[a]] / total, pdf[idx[a]], h, l->length, l->bounce);
                    }
                }
                free(idx);
            }
            if (getenv("VRL_DEBUG") && counted % 10 == 0) {
                size_t best = 0;
                for (size_t j = 1; j < n; ++j)
                    if (acc[j] > acc[best]) best = j;
                const vbl_vrl* l = &ph->vrls[best];
                int rank = 0;
                for (size_t j = 0; j < n; ++j) rank += pdf[j] > pdf[best];
                double h = vbl_segment_distance(cs.origin, cs.direction, 20.0, l->origin, l->direction, l->length);
                printf("px %d: top VRL %zu share %.3f pdf %.3g (rank %d, uniform %.3g) h %.3g len %.3g bounce %d P %.3g\n",
                       p, best, acc[best] / total, pdf[best], rank, 1.0 / n, h, l->length, l->bounce,
                       l->power.x + l->power.y + l->power.z);
            }
            m2[counted] = s2 / (total * total);
            m2u[counted] = s2u / (total * total);
            qsort(acc, n, sizeof *acc, cmp_desc);
            double run = 0.0;
            int a50 = -1, a90 = -1, a99 = -1;
            for (size_t j = 0; j < n; ++j) {
                run += acc[j];
                if (a50 < 0 && run >= 0.5 * total) a50 = (int)j + 1;
                if (a90 < 0 && run >= 0.9 * total) a90 = (int)j + 1;
                if (a99 < 0 && run >= 0.99 * total) a99 = (int)j + 1;
            }
            q50[counted] = a50;
            q90[counted] = a90;
            q99[counted] = a99;
            ++counted;
        }
        if (counted) {
            qsort(q50, (size_t)counted, sizeof(int), cmp_int);
            qsort(q90, (size_t)counted, sizeof(int), cmp_int);
            qsort(q99, (size_t)counted, sizeof(int), cmp_int);
            qsort(m2, (size_t)counted, sizeof(double), cmp_desc);
            qsort(m2u, (size_t)counted, sizeof(double), cmp_desc);
            double mm = 0.0, mmu = 0.0;
            for (int i = 0; i < counted; ++i) {
                mm += m2[i] / counted;
                mmu += m2u[i] / counted;
            }
            printf("selection quality (relative second moment of one light drawn, 1 = ideal): tree median %.3g, mean "
                   "%.3g; uniform median %.3g, mean %.3g\n",
                   m2[counted / 2], mm, m2u[counted / 2], mmu);
            printf("\nconcentration over %d lit pixels (%zu VRLs): median VRLs holding 50%% %d, 90%% %d, 99%% %d "
                   "(%.2f%% / %.2f%% / %.2f%% of the VRLs); visible fraction of the media overlap %.3f\n",
                   counted, n, q50[counted / 2], q90[counted / 2], q99[counted / 2], 100.0 * q50[counted / 2] / n,
                   100.0 * q90[counted / 2] / n, 100.0 * q99[counted / 2] / n, hit ? vis_sum / hit : 0.0);
        }
        free(c);
        free(acc);
        free(pdf);
        free(m2);
        free(m2u);
        free(q50);
        free(q90);
        free(q99);
        vbl_vl_pass_end(&ctx, store);
        vbl_scene_release(scene);
        fflush(stdout);
    }
    return 0;
}
