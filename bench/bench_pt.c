/* Issue-14 benchmark: pt's own switches on and off (equiangular NEE, MIS heuristic, shadow
 * transmittance estimator) on one scene, per layer, at equal sample count and at equal time,
 * against a long pt reference (bench_reference.h, cached in the build directory).
 *
 *   build/bench/bench_pt [--scene bench/scenes/smoky_lambert_room.json] [--res 64x48] [--spp 64]
 *       [--reference-seconds 120] [--threads 2] [--configs eq_off,eq_on,...] [--vdb build/samples/cloud.vdb]
 *       [--seed 1]
 *
 * Configurations: eq_off / eq_on (pt.equiangular), eq_off_sobol / eq_on_sobol (the same with
 * pt.sampler = sobol), eq_on_balance, tr_* (shadow transmittance estimators and majorant scales;
 * tr_mid*: pt.shadow_transmittance = residual-mid; tr_um*: unbiased-march; tr_uma: unbiased-march-adaptive; every other row sets it
 * to render), eq_quads /
 * eq_quads_mid (pt.equiangular_quads on), rr_plain / rr_guided / rr_guided8 (pt.guided_rr off / on,
 * residual-mid shadows as when they were measured).
 * Every configuration renders --spp passes of 1 sample per pixel with the same seed. Per layer it
 * prints rMAE (sum |I - Iref| / sum |Iref|) and rMAE scaled to the first configuration's CPU time,
 * rMAE * sqrt(c / c_first) (noise falls as 1/sqrt(samples), so this is the error it would reach in
 * the first configuration's time: below the first's rMAE = better at equal time). The cost is the
 * process CPU time of the vbl_render call (all threads; wall time is printed too), which other
 * processes on a shared machine disturb less than wall time. The reference's own error (ref_floor
 * row) is included in every rMAE. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bench_reference.h"
#include "vbl/vbl.h"

typedef struct bench_config {
    const char* name;
    int equiangular;                    /* options.pt.equiangular (0/1) */
    vbl_mis_heuristic mis;
    vbl_transmittance_estimator shadow; /* options.transmittance */
    double majorant_scale;              /* options.transmittance_majorant_scale (0: default) */
    vbl_pt_sampler sampler;             /* options.pt_sampler */
    vbl_pt_shadow_transmittance pt_shadow; /* options.pt.shadow_transmittance */
    int equiangular_quads;              /* options.pt.equiangular_quads */
} bench_config;

static const bench_config bench_configs[] = {
    {"eq_off", 0, VBL_MIS_POWER, VBL_TRANSMITTANCE_RATIO_TRACKING, 0.0, VBL_PT_SAMPLER_INDEPENDENT, VBL_PT_SHADOW_RENDER, 0},
    {"eq_on", 1, VBL_MIS_POWER, VBL_TRANSMITTANCE_RATIO_TRACKING, 0.0, VBL_PT_SAMPLER_INDEPENDENT, VBL_PT_SHADOW_RENDER, 0},
    {"eq_on_balance", 1, VBL_MIS_BALANCE, VBL_TRANSMITTANCE_RATIO_TRACKING, 0.0, VBL_PT_SAMPLER_INDEPENDENT, VBL_PT_SHADOW_RENDER, 0},
    {"tr_ratio", 1, VBL_MIS_POWER, VBL_TRANSMITTANCE_RATIO_TRACKING, 0.0, VBL_PT_SAMPLER_INDEPENDENT, VBL_PT_SHADOW_RENDER, 0},
    {"tr_residual", 1, VBL_MIS_POWER, VBL_TRANSMITTANCE_RESIDUAL_RATIO_TRACKING, 0.0, VBL_PT_SAMPLER_INDEPENDENT, VBL_PT_SHADOW_RENDER, 0},
    {"tr_delta", 1, VBL_MIS_POWER, VBL_TRANSMITTANCE_DELTA_TRACKING, 0.0, VBL_PT_SAMPLER_INDEPENDENT, VBL_PT_SHADOW_RENDER, 0},
    {"tr_march", 1, VBL_MIS_POWER, VBL_TRANSMITTANCE_RAY_MARCHING, 0.0, VBL_PT_SAMPLER_INDEPENDENT, VBL_PT_SHADOW_RENDER, 0},
    {"tr_ratio_k2", 1, VBL_MIS_POWER, VBL_TRANSMITTANCE_RATIO_TRACKING, 2.0, VBL_PT_SAMPLER_INDEPENDENT, VBL_PT_SHADOW_RENDER, 0},
    {"tr_ratio_k4", 1, VBL_MIS_POWER, VBL_TRANSMITTANCE_RATIO_TRACKING, 4.0, VBL_PT_SAMPLER_INDEPENDENT, VBL_PT_SHADOW_RENDER, 0},
    {"tr_residual_k2", 1, VBL_MIS_POWER, VBL_TRANSMITTANCE_RESIDUAL_RATIO_TRACKING, 2.0, VBL_PT_SAMPLER_INDEPENDENT, VBL_PT_SHADOW_RENDER, 0},
    {"tr_ratio_k8", 1, VBL_MIS_POWER, VBL_TRANSMITTANCE_RATIO_TRACKING, 8.0, VBL_PT_SAMPLER_INDEPENDENT, VBL_PT_SHADOW_RENDER, 0},
    {"tr_residual_k4", 1, VBL_MIS_POWER, VBL_TRANSMITTANCE_RESIDUAL_RATIO_TRACKING, 4.0, VBL_PT_SAMPLER_INDEPENDENT, VBL_PT_SHADOW_RENDER, 0},
    {"tr_residual_k8", 1, VBL_MIS_POWER, VBL_TRANSMITTANCE_RESIDUAL_RATIO_TRACKING, 8.0, VBL_PT_SAMPLER_INDEPENDENT, VBL_PT_SHADOW_RENDER, 0},
    {"eq_off_sobol", 0, VBL_MIS_POWER, VBL_TRANSMITTANCE_RATIO_TRACKING, 0.0, VBL_PT_SAMPLER_SOBOL, VBL_PT_SHADOW_RENDER, 0},
    {"eq_on_sobol", 1, VBL_MIS_POWER, VBL_TRANSMITTANCE_RATIO_TRACKING, 0.0, VBL_PT_SAMPLER_SOBOL, VBL_PT_SHADOW_RENDER, 0},
    /* issue 14 item 4: residual ratio tracking with the mid-bound control (pt.shadow_transmittance) */
    {"tr_mid", 1, VBL_MIS_POWER, VBL_TRANSMITTANCE_RATIO_TRACKING, 0.0, VBL_PT_SAMPLER_INDEPENDENT, VBL_PT_SHADOW_RESIDUAL_MID, 0},
    {"tr_mid_k2", 1, VBL_MIS_POWER, VBL_TRANSMITTANCE_RATIO_TRACKING, 2.0, VBL_PT_SAMPLER_INDEPENDENT, VBL_PT_SHADOW_RESIDUAL_MID, 0},
    {"tr_mid_k4", 1, VBL_MIS_POWER, VBL_TRANSMITTANCE_RATIO_TRACKING, 4.0, VBL_PT_SAMPLER_INDEPENDENT, VBL_PT_SHADOW_RESIDUAL_MID, 0},
    {"tr_mid_k8", 1, VBL_MIS_POWER, VBL_TRANSMITTANCE_RATIO_TRACKING, 8.0, VBL_PT_SAMPLER_INDEPENDENT, VBL_PT_SHADOW_RESIDUAL_MID, 0},
    /* issue 14 item 1: quad lights in the equiangular NEE (pt.equiangular_quads) */
    {"eq_quads", 1, VBL_MIS_POWER, VBL_TRANSMITTANCE_RATIO_TRACKING, 0.0, VBL_PT_SAMPLER_INDEPENDENT, VBL_PT_SHADOW_RENDER, 1},
    {"eq_quads_mid", 1, VBL_MIS_POWER, VBL_TRANSMITTANCE_RATIO_TRACKING, 0.0, VBL_PT_SAMPLER_INDEPENDENT, VBL_PT_SHADOW_RESIDUAL_MID, 1},
    /* issue 14 item 4: unbiased ray marching (pt.shadow_transmittance = unbiased-march); the
     * majorant scale multiplies the march density at the camera-visible vertex */
    {"tr_um", 1, VBL_MIS_POWER, VBL_TRANSMITTANCE_RATIO_TRACKING, 0.0, VBL_PT_SAMPLER_INDEPENDENT, VBL_PT_SHADOW_UNBIASED_MARCH, 0},
    {"tr_um_k2", 1, VBL_MIS_POWER, VBL_TRANSMITTANCE_RATIO_TRACKING, 2.0, VBL_PT_SAMPLER_INDEPENDENT, VBL_PT_SHADOW_UNBIASED_MARCH, 0},
    {"tr_um_k4", 1, VBL_MIS_POWER, VBL_TRANSMITTANCE_RATIO_TRACKING, 4.0, VBL_PT_SAMPLER_INDEPENDENT, VBL_PT_SHADOW_UNBIASED_MARCH, 0},
    /* session 6: the adaptive march (pt.shadow_transmittance = unbiased-march-adaptive) */
    {"tr_uma", 1, VBL_MIS_POWER, VBL_TRANSMITTANCE_RATIO_TRACKING, 0.0, VBL_PT_SAMPLER_INDEPENDENT, VBL_PT_SHADOW_UNBIASED_MARCH_ADAPTIVE, 0},
    /* issue 14 item 3: the defaults with throughput roulette (rr_plain) and pt.guided_rr (rr_guided*,
     * the name's suffix picks pt.guide_cells / pt.guide_paths: rr_guided = 16/8, rr_guided8 = 8/8) */
    {"rr_plain", 1, VBL_MIS_POWER, VBL_TRANSMITTANCE_RATIO_TRACKING, 0.0, VBL_PT_SAMPLER_INDEPENDENT, VBL_PT_SHADOW_RESIDUAL_MID, 1},
    {"rr_guided", 1, VBL_MIS_POWER, VBL_TRANSMITTANCE_RATIO_TRACKING, 0.0, VBL_PT_SAMPLER_INDEPENDENT, VBL_PT_SHADOW_RESIDUAL_MID, 1},
    {"rr_guided8", 1, VBL_MIS_POWER, VBL_TRANSMITTANCE_RATIO_TRACKING, 0.0, VBL_PT_SAMPLER_INDEPENDENT, VBL_PT_SHADOW_RESIDUAL_MID, 1},
};
#define BENCH_CONFIG_COUNT ((int)(sizeof bench_configs / sizeof bench_configs[0]))

int main(int argc, char** argv)
{
    const char* scene_file = "bench/scenes/smoky_lambert_room.json";
    const char* configs = "eq_off,eq_on";
    const char* vdb = VBL_BENCH_DEFAULT_VDB;
    int width = 64, height = 48, spp = 64, threads = 2;
    unsigned long long seed = 1;
    double reference_seconds = 120.0;
    for (int i = 1; i < argc; ++i) {
        const char* a = argv[i];
        const char* v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!v) {
            fprintf(stderr, "bench_pt: %s needs a value\n", a);
            return 2;
        }
        if (!strcmp(a, "--scene")) scene_file = v;
        else if (!strcmp(a, "--configs")) configs = v;
        else if (!strcmp(a, "--vdb")) vdb = v;
        else if (!strcmp(a, "--spp")) spp = atoi(v);
        else if (!strcmp(a, "--seed")) seed = strtoull(v, NULL, 10);
        else if (!strcmp(a, "--threads")) threads = atoi(v);
        else if (!strcmp(a, "--reference-seconds")) reference_seconds = atof(v);
        else if (!strcmp(a, "--res")) {
            if (sscanf(v, "%dx%d", &width, &height) != 2) return 2;
        } else {
            fprintf(stderr, "bench_pt: unknown argument %s\n", a);
            return 2;
        }
        ++i;
    }
    vbl_scene* scene = bench_load_scene("bench_pt", VBL_BENCH_SOURCE_DIR, scene_file, vdb, width, height);
    const char* base = strrchr(scene_file, '/');
    char name[256];
    snprintf(name, sizeof name, "pt_%s", base ? base + 1 : scene_file);
    bench_reference_request q = {"bench_pt", VBL_BENCH_CACHE_DIR, name, scene_file, vdb, width, height, threads,
                                 reference_seconds, 0};
    bench_reference ref;
    bench_reference_make(scene, &q, &ref);
    printf("# %s %dx%d, %d spp (1 per pass), %d threads, seed %llu; reference %.0f s\n", scene_file, width, height, spp, threads, seed,
           ref.seconds);
    printf("%-14s %8s %8s", "config", "wall_s", "cpu_s");
    for (int l = 0; l < BENCH_LAYERS; ++l)
        if (ref.present[l]) printf(" %12.12s", bench_layer_label(l));
    printf("\n%-14s %8s %8s", "ref_floor", "", "");
    for (int l = 0; l < BENCH_LAYERS; ++l)
        if (ref.present[l]) printf(" %12.5f", ref.floor_rmae[l]);
    printf("\n");
    float* img = malloc(sizeof(float) * 3 * (size_t)ref.n);
    double t_first = 0.0;
    for (int c = 0; c < BENCH_CONFIG_COUNT; ++c) {
        const bench_config* bc = &bench_configs[c];
        if (!bench_in_list(configs, bc->name)) continue;
        vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
        vbl_scene_render_options(scene, &o);
        o.method = VBL_RENDER_PT;
        o.spp = 1;
        o.passes = spp;
        o.seed = seed;
        o.threads = threads;
        o.pt.equiangular = bc->equiangular;
        o.pt.sampler = bc->sampler;
        o.pt.shadow_transmittance = bc->pt_shadow;
        o.pt.equiangular_quads = bc->equiangular_quads;
        o.pt.guided_rr = !strncmp(bc->name, "rr_guided", 9);
        if (!strcmp(bc->name, "rr_guided8")) o.pt.guide_cells = 8;
        o.mis = bc->mis;
        o.transmittance = bc->shadow;
        if (bc->majorant_scale > 0.0) o.transmittance_majorant_scale = bc->majorant_scale;
        vbl_film* film = NULL;
        clock_t c0 = clock();
        int failed = vbl_render(scene, &o, &film) != VBL_SUCCESS;
        double cpu = (double)(clock() - c0) / CLOCKS_PER_SEC;
        if (failed) {
            fprintf(stderr, "bench_pt: %s\n", vbl_last_error_message());
            return 1;
        }
        vbl_film_stats st;
        memset(&st, 0, sizeof st);
        st.size = sizeof st;
        vbl_film_get_stats(film, &st);
        if (t_first <= 0.0) t_first = cpu;
        double scale = sqrt(cpu / t_first);
        printf("%-14s %8.2f %8.2f", bc->name, st.render_seconds, cpu);
        double e[BENCH_LAYERS] = {0};
        for (int l = 0; l < BENCH_LAYERS; ++l) {
            if (!ref.present[l]) continue;
            bench_film_rgb(film, l, ref.n, img);
            e[l] = bench_rmae(img, ref.ref + (size_t)l * 3 * ref.n, 3 * ref.n);
            printf(" %12.5f", e[l]);
        }
        printf("\n%-14s %8s %8s", "  @equal_cpu", "", "");
        for (int l = 0; l < BENCH_LAYERS; ++l)
            if (ref.present[l]) printf(" %12.5f", e[l] * scale);
        printf("\n");
        fflush(stdout);
        vbl_film_release(film);
    }
    free(img);
    free(ref.halves);
    free(ref.ref);
    vbl_scene_release(scene);
    return 0;
}
