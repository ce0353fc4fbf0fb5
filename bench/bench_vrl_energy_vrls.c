/* Issue 13 item 3: which VRLs carry a vrl pass's volume_from_volume (internal API, diagnostics).
 *
 *   build/bench/bench_vrl_energy_vrls SCENE.json PASSES SPP [SELECT [LIGHT_PATHS]]
 * SELECT 0: one line per VRL and pass: "pass path bounce length power energy best_T", energy the
 * VRL's share of the image mean (vbl_vrl_contributions, SPP jittered camera samples per pixel),
 * best_T the largest transmittance to the camera over 9 points of the VRL (4 ratio-tracking
 * estimates each); bench/vrl_energy_vrls.py summarises. SELECT K > 0: per pass, the relative
 * second moment sum_j c_j^2 / pdf_j / (sum_j c_j)^2 of one light-tree draw over the lit camera
 * samples (1 for a selection pdf proportional to the contributions), and "ZEROPDF" lines if a
 * contributing VRL had selection probability 0 (a bias). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "scene/scene.h"
#include "transport/common/estimator.h"
#include "transport/common/photon_trace.h"
#include "transport/virtual_lights/vrl.h"
#include "vbl/vbl.h"
#include "volume/transmittance_cache.h"
int cmpd(const void* a, const void* b) { double x = *(const double*)a, y = *(const double*)b; return (x > y) - (x < y); }
int main(int argc, char** argv)
{
    vbl_scene* scene = NULL;
    if (vbl_scene_load(argv[1], &scene)) { fprintf(stderr, "%s\n", vbl_last_error_message()); return 1; }
    int P = atoi(argv[2]), spp = atoi(argv[3]), sel = argc > 4 ? atoi(argv[4]) : 0;
    int W = scene->camera.width, H = scene->camera.height;
    vbl_render_context ctx; memset(&ctx, 0, sizeof ctx);
    ctx.scene = scene; ctx.extinction = &scene->extinction;
    vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
    vbl_scene_render_options(scene, &o);
    o.light_paths = argc > 5 ? atoi(argv[5]) : 10; o.seed = 1; o.vrl.select = sel;
    ctx.options = o;
    ctx.tracking.estimator = VBL_TRANSMITTANCE_RATIO_TRACKING;
    ctx.threads = 1;
    vbl_vec3 cam = scene->camera.position;
    double allM2 = 0, allF2 = 0;
    for (int p = 0; p < P; ++p) {
        ctx.pass = p;
        vbl_vrl_settings st; vbl_vrl_settings_from_options(&o, &st);
        void* store = NULL;
        if (vbl_vl_pass_begin(&ctx, &vbl_vl_kernel_ray, &st, &store)) { fprintf(stderr, "%s\n", vbl_last_error_message()); return 1; }
        const vbl_photon_store* ph = vbl_vl_photons(store);
        size_t n = ph->vrl_count;
        double* E = calloc(n + 1, sizeof(double)); double* c = calloc(n + 1, sizeof(double)); double* pdf = calloc(n + 1, sizeof(double));
        double sumF = 0, sumM2 = 0, sumF2 = 0; int nsamp = 0; static double m2s[100000]; int nm2 = 0;
        vbl_thread_state ts; memset(&ts, 0, sizeof ts); vbl_extinction_cursor_init(&ts.cursor, ctx.extinction);
        for (int px = 0; px < W * H; ++px)
            for (int s = 0; s < spp; ++s) {
                vbl_rng rng = vbl_rng_make(77 + p, (uint32_t)s, (uint64_t)px);
                vbl_camera_sample cs; memset(&cs, 0, sizeof cs);
                vbl_camera_ray(&scene->camera, px % W + vbl_rng_uniform(&rng), px / W + vbl_rng_uniform(&rng), &cs.origin, &cs.direction);
                cs.t_max = INFINITY;
                double vis;
                if (!vbl_vrl_contributions(&ctx, store, &ts, &cs, &rng, c, &vis, sel ? pdf : NULL)) continue;
                for (size_t j = 0; j < n; ++j) E[j] += c[j] / (3.0 * W * H * spp);
                if (sel) { double F = 0, M2 = 0, covered = 0; for (size_t j = 0; j < n; ++j) { F += c[j]; if (c[j] > 0 && pdf[j] > 0) M2 += c[j] * c[j] / pdf[j]; if (c[j] > 0 && pdf[j] <= 0) covered += c[j]; }
                  if (F > 0) { sumF += F; sumM2 += M2; sumF2 += F * F; allM2 += M2; allF2 += F * F; nsamp++; if (nm2 < 100000) m2s[nm2++] = M2 / (F * F); if (covered > 0) printf("ZEROPDF %g of %g\n", covered, F); } }
            }
        if (sel && nm2) { int cmpd(const void* a, const void* b); qsort(m2s, nm2, sizeof(double), cmpd);
            printf("SEL pass %d: %d lit samples, relative second moment of one draw: median %.3g, 90%% %.3g, max %.3g, pooled %.3g\n", p, nm2, m2s[nm2/2], m2s[nm2*9/10], m2s[nm2-1], sumM2 / sumF2); }
        int path = -1; if (sel) { free(E); free(c); free(pdf); vbl_vl_pass_end(&ctx, store); continue; }
        for (size_t j = 0; j < n; ++j) {
            const vbl_vrl* l = &ph->vrls[j];
            if (l->bounce == 0) ++path;
            /* best transmittance to the camera over 9 points of the VRL (4 estimates each) */
            double best = 0.0;
            vbl_rng rng = vbl_rng_make(99, (uint32_t)p, (uint64_t)j);
            for (int k = 0; k < 9; ++k) {
                vbl_vec3 x = vbl_v3_madd(l->origin, l->direction, l->length * (k + 0.5) / 9.0);
                vbl_vec3 to = vbl_v3_sub(cam, x); double d = vbl_v3_length(to); to = vbl_v3_scale(to, 1.0 / d);
                double t = 0; for (int r = 0; r < 4; ++r) t += 0.25 * vbl_vrl_connect_transmittance(&ctx, &ctx.tracking, &ts, x, to, d, &rng);
                if (t > best) best = t;
            }
            printf("%d %d %d %.5g %.5g %.6g %.4g\n", p, path, l->bounce, l->length, vbl_v3_max_component(l->power), E[j], best);
        }
        free(E); free(c);
        vbl_vl_pass_end(&ctx, store);
    }
    if (sel) printf("SEL all passes: pooled relative second moment %.4g\n", allM2 / allF2);
    return 0;
}
