/* Issue 13, round 2: where the heavy tail of the per-VRL estimate comes from.
 *
 *   build/bench/bench_vrl_tail [--scenes cloud,dense] [--light-paths 150] [--res 32x24]
 *       [--samples 48] [--stride 5] [--threads 2] [--camera-mis 0|1|2] [--rr 0.1]
 *
 * One fixed vrl store per scene (every VRL, the default settings). For every --stride-th pixel,
 * --samples camera samples (a fresh camera transmittance cache each, as the estimator does), and
 * per camera sample one pair-sampler draw per VRL (vbl_vrl_sample_factors). The pixel's estimate
 * is the sum over VRLs; its relative variance (sum over pixels of the variance / sum of mean^2)
 * is printed for the full estimate and for variants that replace one factor:
 *   full       f Tc Tl Tw / (w^2 pdf)                 (the estimator)
 *   Tw exact   the connection's ratio-tracking estimate replaced by ray marching
 *   Tc exact   the camera cache replaced by ray marching to u
 *   T exact    both
 *   Tc exact, Tw = 1 / Tc = 1, Tw exact   one transmittance's shape alone
 *   T = 1      both transmittances dropped (the sampler against phase x sigma_s x sigma_s / w^2)
 *   no sigma   T exact and sigma_s(u) sigma_s(v) dropped (phases / w^2 and Tc Tw against the pdf)
 *   geometry   phase_geometry / pdf only (the sampler against its own target)
 * A variant that lowers the relative variance a lot names a factor the sampler should follow.
 * Also: the largest single camera sample / the pixel mean (median over pixels). --camera-mis 1
 * draws (u, v) with the transmittance-aware MIS sampler (sampling/vrl_camera_mis.h) instead of
 * the product sampler alone (default 0: the sampler before issue 13's second round); --rr sets
 * the Russian-roulette threshold of the ratio-tracked camera cache and connections (default 0.1:
 * the estimator's default); --connect-scale K > 1 draws the connections' ratio-tracking tentative
 * collisions at K x the majorant (vbl_tracking_settings.majorant_scale: lower variance, K x the
 * lookups). The estimator's own cost per camera sample is printed with each scene. --camera-mis 2
 * is vrl.pair_sampler = transmittance (sampling/vrl_tc_pair.h). Also the per-pair relative second
 * moment of the full estimate: E[x^2] / E[x]^2 of one draw for one (pixel, VRL) pair, pooled
 * (sum of E[x^2] over sum of E[x]^2) and the median over pairs with a non-zero mean. */
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_reference.h"
#include "scene/scene.h"
#include "transport/common/estimator.h"
#include "transport/common/photon_trace.h"
#include "transport/virtual_lights/vrl.h"
#include "vbl/vbl.h"
#include "volume/transmittance_cache.h"

#ifndef VBL_BENCH_DEFAULT_VDB
#define VBL_BENCH_DEFAULT_VDB "build/samples/cloud.vdb"
#endif
#ifndef VBL_BENCH_SOURCE_DIR
#define VBL_BENCH_SOURCE_DIR "."
#endif

enum { V_FULL, V_TW, V_TC, V_T, V_TCONLY, V_TWONLY, V_T1, V_NOSIG, V_GEOM, V_COUNT };
static const char* const vnames[V_COUNT] = {"full", "Tw exact", "Tc exact", "T exact", "Tc exact, Tw = 1", "Tc = 1, Tw exact", "T = 1", "no sigma", "geometry"};

static int cmp_d(const void* a, const void* b)
{
    double x = *(const double*)a, y = *(const double*)b;
    return x < y ? -1 : (x > y ? 1 : 0);
}

int main(int argc, char** argv)
{
    const char* scenes = "cloud,dense";
    int light_paths = 150, width = 32, height = 24, R = 48, stride = 5, threads = 2, camera_mis = 0;
    double rr = 0.1, connect_scale = 0.0;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!strcmp(argv[i], "--scenes")) scenes = argv[i + 1];
        else if (!strcmp(argv[i], "--light-paths")) light_paths = atoi(argv[i + 1]);
        else if (!strcmp(argv[i], "--samples")) R = atoi(argv[i + 1]);
        else if (!strcmp(argv[i], "--stride")) stride = atoi(argv[i + 1]);
        else if (!strcmp(argv[i], "--threads")) threads = atoi(argv[i + 1]);
        else if (!strcmp(argv[i], "--camera-mis")) camera_mis = atoi(argv[i + 1]);
        else if (!strcmp(argv[i], "--rr")) rr = atof(argv[i + 1]);
        else if (!strcmp(argv[i], "--connect-scale")) connect_scale = atof(argv[i + 1]);
        else if (!strcmp(argv[i], "--res")) {
            if (sscanf(argv[i + 1], "%dx%d", &width, &height) != 2) return 2;
        } else {
            fprintf(stderr, "usage: bench_vrl_tail [--scenes cloud,dense] [--light-paths N] [--res WxH] [--samples N] "
                            "[--stride N] [--threads N] [--camera-mis 0|1|2] [--rr T] [--connect-scale K]\n");
            return 2;
        }
    }
    static const char* const names[2] = {"cloud", "dense"};
    static const char* const files[2] = {"samples/cloud.json", "bench/scenes/cloud_dense.json"};
    printf("# bench_vrl_tail: %dx%d, %d light paths, %d samples, every %d-th pixel, camera MIS %d, "
           "transmittance RR threshold %g\n", width, height, light_paths, R, stride, camera_mis, rr);
    for (int sc = 0; sc < 2; ++sc) {
        if (!bench_in_list(scenes, names[sc])) continue;
        vbl_scene* scene = bench_load_scene("bench_vrl_tail", VBL_BENCH_SOURCE_DIR, files[sc], VBL_BENCH_DEFAULT_VDB,
                                            width, height);
        vbl_render_context ctx;
        memset(&ctx, 0, sizeof ctx);
        ctx.scene = scene;
        ctx.extinction = &scene->extinction;
        vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
        if (vbl_scene_render_options(scene, &o)) return 1;
        o.light_paths = light_paths;
        ctx.options = o;
        ctx.tracking.estimator = VBL_TRANSMITTANCE_RATIO_TRACKING;
        ctx.tracking.majorant_scale = connect_scale; /* the store copies it for its connections */
        ctx.threads = threads;
        vbl_vrl_settings st;
        vbl_vrl_settings_from_options(&o, &st);
        st.camera_mis = camera_mis;
        st.transmittance_rr = rr;
        void* store = NULL;
        if (vbl_vl_pass_begin(&ctx, &vbl_vl_kernel_ray, &st, &store)) return 1;
        const vbl_photon_store* ph = vbl_vl_photons(store);
        const int M = o.max_bounces;
        const int np = (width * height + stride - 1) / stride;
        double* var = calloc((size_t)np * V_COUNT, sizeof(double));
        double* mean = calloc((size_t)np * V_COUNT, sizeof(double));
        double* peak = calloc((size_t)np, sizeof(double));
        const size_t nv = ph->vrl_count;
        double* pm1 = calloc((size_t)np * nv, sizeof(double)); /* per (pixel, VRL): sum of x, x^2 */
        double* pm2 = calloc((size_t)np * nv, sizeof(double));
#pragma omp parallel num_threads(threads)
        {
            vbl_thread_state ts;
            memset(&ts, 0, sizeof ts);
            vbl_extinction_cursor_init(&ts.cursor, ctx.extinction);
#pragma omp for schedule(dynamic, 1)
            for (int q = 0; q < np; ++q) {
                int p = q * stride;
                vbl_vec3 org, dir;
                vbl_camera_ray(&scene->camera, p % width + 0.5, p / width + 0.5, &org, &dir);
                double s1[V_COUNT] = {0}, s2[V_COUNT] = {0}, mx = 0.0;
                for (int r = 0; r < R; ++r) {
                    vbl_rng rng = vbl_rng_make(11, (uint32_t)r, (uint64_t)p);
                    vbl_vl_camera cam;
                    double x[V_COUNT] = {0};
                    if (vbl_vl_camera_cache(&ctx, store, &ts, org, dir, INFINITY, &rng, &cam)) {
                        for (size_t j = 0; j < ph->vrl_count; ++j) {
                            if (M >= 0 && ph->vrls[j].bounce + 2 > M) continue;
                            vbl_vrl_factors f;
                            if (!vbl_vrl_sample_factors(&ctx, store, &ts, j, &cam, &rng, &f)) continue;
                            if (!(f.f > 0.0)) continue;
                            double base = f.f * f.tl / (f.w2 * f.pdf);
                            x[V_FULL] += base * f.tc * f.tw;
                            pm1[(size_t)q * nv + j] += base * f.tc * f.tw;
                            pm2[(size_t)q * nv + j] += (base * f.tc * f.tw) * (base * f.tc * f.tw);
                            x[V_TW] += base * f.tc * f.tw_march;
                            x[V_TC] += base * f.tc_march * f.tw;
                            x[V_T] += base * f.tc_march * f.tw_march;
                            x[V_TCONLY] += base * f.tc_march;
                            x[V_TWONLY] += base * f.tw_march;
                            x[V_T1] += base;
                            x[V_NOSIG] += base * f.tc_march * f.tw_march / (f.sigma_u * f.sigma_v);
                            x[V_GEOM] += f.power * f.phase_geometry / f.pdf;
                        }
                    }
                    for (int v = 0; v < V_COUNT; ++v) {
                        s1[v] += x[v];
                        s2[v] += x[v] * x[v];
                    }
                    if (x[V_FULL] > mx) mx = x[V_FULL];
                }
                for (int v = 0; v < V_COUNT; ++v) {
                    double m = s1[v] / R;
                    mean[q * V_COUNT + v] = m;
                    var[q * V_COUNT + v] = fmax(0.0, (s2[v] / R - m * m) * R / (R - 1));
                }
                peak[q] = s1[V_FULL] > 0.0 ? mx / (s1[V_FULL] / R) : -1.0;
            }
        }
        /* cost of the estimator itself (vbl_vl_camera_sample, 4 samples per pixel of the subset) */
        double t0 = omp_get_wtime();
#pragma omp parallel num_threads(threads)
        {
            vbl_thread_state ts;
            memset(&ts, 0, sizeof ts);
            vbl_extinction_cursor_init(&ts.cursor, ctx.extinction);
#pragma omp for schedule(dynamic, 1)
            for (int q = 0; q < np; ++q) {
                int p = q * stride;
                vbl_camera_sample cs;
                memset(&cs, 0, sizeof cs);
                vbl_camera_ray(&scene->camera, p % width + 0.5, p / width + 0.5, &cs.origin, &cs.direction);
                cs.t_max = INFINITY;
                for (int r = 0; r < 4; ++r) {
                    vbl_rng rng = vbl_rng_make(13, (uint32_t)r, (uint64_t)p);
                    vbl_sample_value v;
                    memset(&v, 0, sizeof v);
                    vbl_vl_camera_sample(&ctx, store, &ts, &cs, &rng, &v);
                }
            }
        }
        const double us = 1e6 * (omp_get_wtime() - t0) * threads / (4.0 * np);
        printf("\n## %s (%zu VRLs; the estimator: %.0f us per camera sample)\n\n"
               "| variant | relative variance of one camera sample |\n|---|---|\n",
               names[sc], ph->vrl_count, us);
        for (int v = 0; v < V_COUNT; ++v) {
            double sv = 0.0, sm = 0.0;
            for (int q = 0; q < np; ++q) {
                sv += var[q * V_COUNT + v];
                sm += mean[q * V_COUNT + v] * mean[q * V_COUNT + v];
            }
            printf("| %s | %.3g |\n", vnames[v], sm > 0.0 ? sv / sm : NAN);
        }
        int lit = 0;
        for (int q = 0; q < np; ++q)
            if (peak[q] >= 0.0) peak[lit++] = peak[q];
        qsort(peak, (size_t)lit, sizeof(double), cmp_d);
        if (lit)
            printf("\nlargest camera sample / pixel mean (full, %d lit pixels): median %.3g, 90%% %.3g, max %.3g (%d samples)\n",
                   lit, peak[lit / 2], peak[(int)(0.9 * lit)], peak[lit - 1], R);
        {
            double a2 = 0.0, a1 = 0.0;
            size_t cnt = 0;
            double* rel = malloc(sizeof(double) * ((size_t)np * nv + 1));
            for (size_t k = 0; k < (size_t)np * nv; ++k) {
                double m1 = pm1[k] / R, m2 = pm2[k] / R;
                if (!(m1 > 0.0)) continue;
                a2 += m2;
                a1 += m1 * m1;
                rel[cnt++] = m2 / (m1 * m1);
            }
            qsort(rel, cnt, sizeof(double), cmp_d);
            if (cnt)
                printf("per-pair relative second moment (full, %zu pairs): pooled %.3g, median %.3g, 90%% %.3g\n", cnt,
                       a2 / a1, rel[cnt / 2], rel[(size_t)(0.9 * cnt)]);
            free(rel);
        }
        free(pm1);
        free(pm2);
        free(var);
        free(mean);
        free(peak);
        vbl_vl_pass_end(&ctx, store);
        vbl_scene_release(scene);
        fflush(stdout);
    }
    return 0;
}
