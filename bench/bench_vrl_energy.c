/* Issue 13 (energy): replicas of a render through the public API, one line per replica.
 *
 *   build/bench/bench_vrl_energy SCENE.json REPLICAS SEED0 [key=value ...]
 *     key=value: render options by name (vbl_render_option_set), e.g. method=vrl passes=1
 *     DUMP=1   prints "rep k mean" (volume_from_volume, mean over pixels and RGB) per replica
 *     REF=f    raw float RGB beauty reference (from WRITE=): rMAE of the running mean at 1, 2, 4, ...
 *              replicas with the CPU seconds so far ("rmae n cpu_s rmae"), vbl diff's definition
 *     WRITE=f  writes the replicas' mean beauty as raw floats
 *     REF_VFV=f / WRITE_VFV=f  the same for the volume_from_volume layer ("rmae_vfv n cpu_s rmae")
 * Per-layer means and standard errors across replicas at the end. Replica k uses seed
 * SEED0 + 7919 k. bench/vrl_energy_boot.py turns the DUMP lines into energy against passes. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "vbl/vbl.h"
/* REF_VFV / WRITE_VFV: the running mean of volume_from_volume against a reference, as for beauty */
static void vfv_track(const vbl_film* f, int r, int n, clock_t c0)
{
    static double* acc = NULL;
    static float* ref = NULL;
    static size_t np = 0;
    static double refmean = 0.0;
    int w = vbl_film_width(f), h = vbl_film_height(f), c = 0;
    size_t N = (size_t)w * h * 3;
    const float* p = vbl_film_layer(f, "volume_from_volume", &c);
    if (!p) return;
    if (!acc) {
        acc = calloc(N, sizeof(double));
        if (getenv("REF_VFV")) {
            FILE* fr = fopen(getenv("REF_VFV"), "rb");
            ref = malloc(sizeof(float) * N);
            np = fr ? fread(ref, sizeof(float), N, fr) : 0;
            if (fr) fclose(fr);
            for (size_t i = 0; i < np; ++i) refmean += fabs(ref[i]);
            refmean /= np ? (double)np : 1.0;
        }
    }
    for (size_t i = 0; i < (size_t)w * h; ++i)
        for (int ch = 0; ch < 3; ++ch) acc[i * 3 + ch] += p[i * c + ch];
    if (ref && np == N && ((r + 1) & r) == 0) {
        double e = 0;
        for (size_t i = 0; i < N; ++i) e += fabs(acc[i] / (r + 1) - ref[i]) / (fabs(ref[i]) + 0.01 * refmean);
        printf("rmae_vfv %d %.2f %.5f\n", r + 1, (double)(clock() - c0) / CLOCKS_PER_SEC, e / N);
        fflush(stdout);
    }
    if (getenv("WRITE_VFV") && r == n - 1) {
        FILE* fw = fopen(getenv("WRITE_VFV"), "wb");
        for (size_t i = 0; fw && i < N; ++i) {
            float v = (float)(acc[i] / n);
            fwrite(&v, 4, 1, fw);
        }
        if (fw) fclose(fw);
    }
}

int main(int argc, char** argv)
{
    vbl_scene* scene = NULL;
    if (vbl_scene_load(argv[1], &scene)) { fprintf(stderr, "%s\n", vbl_last_error_message()); return 1; }
    int n = atoi(argv[2]);
    unsigned long long seed0 = strtoull(argv[3], 0, 10);
    vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
    vbl_scene_render_options(scene, &o);
    for (int i = 4; i < argc; ++i) {
        char k[128]; const char* eq = strchr(argv[i], '=');
        snprintf(k, sizeof k, "%.*s", (int)(eq - argv[i]), argv[i]);
        if (vbl_render_option_set(&o, k, eq + 1)) { fprintf(stderr, "opt %s: %s\n", k, vbl_last_error_message()); return 1; }
    }
    const char* layers[] = {"", "volume_direct", "volume_from_volume", "volume_indirect"};
    double s[4] = {0}, s2[4] = {0};
    clock_t c0 = clock();
    double* acc = NULL; float* ref = NULL; size_t np = 0; double refmean = 0;
    if (getenv("REF")) { FILE* fr = fopen(getenv("REF"), "rb"); ref = malloc(sizeof(float) * 3 << 22); np = fread(ref, sizeof(float), 3 << 22, fr); fclose(fr);
        for (size_t i = 0; i < np; ++i) { refmean += fabs(ref[i]); } refmean /= np; }
    for (int r = 0; r < n; ++r) {
        o.seed = seed0 + (unsigned long long)r * 7919ull;
        vbl_film* f = NULL;
        if (vbl_render(scene, &o, &f)) { fprintf(stderr, "%s\n", vbl_last_error_message()); return 1; }
        int w = vbl_film_width(f), h = vbl_film_height(f);
        for (int l = 0; l < 4; ++l) {
            int c = 0; const float* p = vbl_film_layer(f, layers[l], &c);
            if (!p) continue;
            double m = 0; for (int i = 0; i < w * h; ++i) for (int ch = 0; ch < 3; ++ch) m += p[i * c + ch];
            m /= 3.0 * w * h; s[l] += m; s2[l] += m * m;
            if (getenv("DUMP") && l == 2) { printf("rep %d %.8g\n", r, m); fflush(stdout); }
        }
        { int c = 0; const float* p = vbl_film_layer(f, "", &c); size_t N = (size_t)w * h * 3;
          if (!acc) acc = calloc(N, sizeof(double));
          for (size_t i = 0; i < (size_t)w * h; ++i) for (int ch = 0; ch < 3; ++ch) acc[i * 3 + ch] += p[i * c + ch];
          if (ref && ((r + 1) & r) == 0) { double e = 0; for (size_t i = 0; i < N; ++i) e += fabs(acc[i] / (r + 1) - ref[i]) / (fabs(ref[i]) + 0.01 * refmean);
              printf("rmae %d %.2f %.5f\n", r + 1, (double)(clock() - c0) / CLOCKS_PER_SEC, e / N); fflush(stdout); }
          if (getenv("WRITE") && r == n - 1) { FILE* fw = fopen(getenv("WRITE"), "wb"); for (size_t i = 0; i < N; ++i) { float v = (float)(acc[i] / n); fwrite(&v, 4, 1, fw); } fclose(fw); } }
        if (getenv("REF_VFV") || getenv("WRITE_VFV")) vfv_track(f, r, n, c0);
        vbl_film_release(f);
    }
    double cpu = (double)(clock() - c0) / CLOCKS_PER_SEC;
    for (int l = 0; l < 4; ++l) {
        double m = s[l] / n, se = n > 1 ? sqrt(fmax(0, (s2[l] - n * m * m) / (n - 1.0)) / n) : 0;
        if (s[l] != 0) printf("%-20s %.6f +- %.6f\n", l ? layers[l] : "beauty", m, se);
    }
    printf("cpu %.1f s\n", cpu);
    return 0;
}
