/* Fire light for every method (issue 15): photons emitted by emissive media and the camera-side
 * emission estimator let vpl, vrl, vbl and beams render emissive scenes.
 *
 * Default group (quick):
 *   - the emitting-point sampler (vbl_media_sample_emission, light_emission.h): over a box whose
 *     sigma_a Le is the square of a trilinear box profile (so the sampler must follow density
 *     AND Le), the mean flux in each of 8 slabs along x equals 4 pi int_slab sigma_a Le dV
 *     (closed form of the separable profile) within 4.5 sigma, the total within 4 sigma, and the
 *     directions are isotropic (mean of d within 4 sigma of 0, mean d_z^2 within 4 sigma of 1/3);
 *   - every method renders an emissive scattering box over a floor without lights: no NaN or
 *     negative pixel, the layers sum to the beauty, volume_emission is there, the scattered fire
 *     light reaches volume_direct and volume_from_volume (and the floor where the method shades
 *     surfaces), 1 and 2 threads give the same image;
 * "agreement" (label `slow`): pt against vpl, vrl, vbl and beams per layer (volume_emission,
 *   volume_direct, volume_from_volume) on the emissive scattering box (no lights): image means
 *   of R = 8 independent renders agree within Z_CRIT sigma; vbl and beams are consistent
 *   (kernel radius R_p), so their gap may also be up to 3 % of pt's mean (the kernel's bias on
 *   an image mean). Measured at 8x these samples (vrl, 16 renders): volume_emission +0.8 %,
 *   volume_direct -0.1 %, volume_from_volume -5 % (2.3 sigma; vpl -7.6 %, 3.4 sigma, and vpl
 *   lit by a point light instead of the fire -4 %, 1.7 sigma). That gap is the heavy right tail of
 *   the unclamped VPL (1/d^2) and VRL estimators, not a bias (the `gap` diagnostic below, emission.md
 *   "Other methods"): at 128 light paths a replicate's median is 8-13 % below pt while the mean of 64
 *   replicates agrees (vpl +0.3 %, 0.04 sigma), and at 2048 light paths the medians agree too. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/rng.h"
#include "material/material.h"
#include "media/media_emission.h"
#include "render_test_util.h"
#include "transport/common/light_emission.h"
#include "vbl/vbl.h"
#include "volume/extinction.h"

/* ---- the emitting-point sampler ------------------------------------------------------------ */

enum { BOX_N = 9 };
#define BOX_H 0.125
#define BOX_O (-0.5)
#define SIGMA 2.0
#define ALBEDO 0.7
#define LE_SCALE 3.0

/* The box profile of rt_make_box along one axis (rt_box_density is its product). */
static double profile(double x)
{
    vbl_vec3 p = vbl_v3(x, BOX_O + 0.5 * (BOX_N - 1) * BOX_H, BOX_O + 0.5 * (BOX_N - 1) * BOX_H);
    return rt_box_density(BOX_N, BOX_H, vbl_v3(BOX_O, BOX_O, BOX_O), p);
}

/* int_a^b profile(x)^2 dx: the profile is linear between voxel centres, so Simpson's rule on
 * each piece is exact for its square. */
static double profile2_integral(double a, double b)
{
    double knots[64];
    int k = 0;
    knots[k++] = a;
    for (int i = -1; i <= BOX_N; ++i) {
        double x = BOX_O + i * BOX_H;
        if (x > a && x < b) knots[k++] = x;
    }
    knots[k++] = b;
    double s = 0.0;
    for (int i = 0; i + 1 < k; ++i) {
        double x0 = knots[i], x1 = knots[i + 1], xm = 0.5 * (x0 + x1);
        double f0 = profile(x0), f1 = profile(x1), fm = profile(xm);
        s += (x1 - x0) / 6.0 * (f0 * f0 + 4.0 * fm * fm + f1 * f1);
    }
    return s;
}

/* The emissive scattering box: density and emission both rt_make_box(9, 1/8) on [-0.5, 0.5]^3,
 * sigma_t = 2 density, albedo 0.7, g 0.3, Le = 3 (1, 0.6, 0.3) E. With a floor (z = -0.8). */
static vbl_scene* fire_box(int w, int h, int floor, vbl_volume** vols)
{
    vols[0] = rt_make_box(BOX_N, BOX_H, vbl_v3(BOX_O, BOX_O, BOX_O));
    vols[1] = rt_make_box(BOX_N, BOX_H, vbl_v3(BOX_O, BOX_O, BOX_O));
    assert_non_null(vols[0]);
    assert_non_null(vols[1]);
    vbl_camera cam = rt_camera(vbl_v3(3.0, -3.0, 1.5), vbl_v3(0, 0, -0.3), 40.0, w, h);
    vbl_scene* scene = NULL;
    assert_int_equal(vbl_scene_create_empty("fire_box", &cam, &scene), VBL_SUCCESS);
    assert_int_equal(vbl_scene_add_medium(scene, vols[0], SIGMA, vbl_v3(ALBEDO, ALBEDO, ALBEDO), 0.3, NULL),
                     VBL_SUCCESS);
    assert_int_equal(vbl_scene_set_medium_emission(scene, 0, vols[1], vbl_v3(1.0, 0.6, 0.3), LE_SCALE, NULL, 1.0, 0.0,
                                                   0.0, VBL_BLACKBODY_PEAK),
                     VBL_SUCCESS);
    assert_true(scene->has_emission);
    if (floor) {
        double p[12] = {-3, -3, -0.8, 3, -3, -0.8, 3, 3, -0.8, -3, 3, -0.8};
        unsigned idx[6] = {0, 1, 2, 0, 2, 3};
        vbl_material m;
        memset(&m, 0, sizeof m);
        m.type = VBL_MATERIAL_LAMBERT;
        m.albedo = vbl_v3(0.6, 0.6, 0.6);
        assert_int_equal(vbl_scene_add_mesh(scene, p, 4, idx, 2, &m, NULL), VBL_SUCCESS);
    }
    return scene;
}

static void release(vbl_scene* scene, vbl_volume** vols)
{
    vbl_scene_release(scene);
    vbl_volume_release(vols[0]);
    vbl_volume_release(vols[1]);
}

static void test_point_sampler(void** state)
{
    (void)state;
    vbl_volume* vols[2];
    vbl_scene* scene = fire_box(4, 4, 0, vols);
    vbl_extinction_cursor cursor;
    vbl_extinction_cursor_init(&cursor, &scene->extinction);
    vbl_emission_cursor ec;
    vbl_emission_cursor_init(&ec, scene);
    enum { N = 200000, BINS = 8 };
    const double lo = BOX_O - BOX_H, hi = BOX_O + BOX_N * BOX_H; /* the support along x */
    double sum[BINS] = {0}, sq[BINS] = {0}, tot = 0.0, tot2 = 0.0, dm[3] = {0}, dm2[3] = {0}, z2 = 0.0, z22 = 0.0;
    int accepted = 0;
    vbl_rng rng = vbl_rng_make(42, 0, 0);
    for (int i = 0; i < N; ++i) {
        double u[7];
        for (int k = 0; k < 7; ++k) u[k] = vbl_rng_uniform(&rng);
        vbl_emission_sample es;
        double f = 0.0;
        int bin = -1;
        if (vbl_media_sample_emission(scene, &scene->extinction, &cursor, &ec, u, &es)) {
            ++accepted;
            assert_true(isfinite(es.flux.x) && es.flux.x >= 0.0);
            assert_true(fabs(vbl_v3_length(es.direction) - 1.0) < 1e-12);
            f = es.flux.x; /* red: Le,r = 3 E */
            bin = (int)floor((es.origin.x - lo) / (hi - lo) * BINS);
            assert_true(bin >= 0 && bin < BINS);
            const double d[3] = {es.direction.x, es.direction.y, es.direction.z};
            for (int a = 0; a < 3; ++a) {
                dm[a] += d[a];
                dm2[a] += d[a] * d[a];
            }
            z2 += d[2] * d[2];
            z22 += d[2] * d[2] * d[2] * d[2];
        }
        for (int b = 0; b < BINS; ++b) {
            double v = b == bin ? f : 0.0;
            sum[b] += v;
            sq[b] += v * v;
        }
        tot += f;
        tot2 += f * f;
    }
    const double c = 4.0 * VBL_PI * SIGMA * (1.0 - ALBEDO) * LE_SCALE; /* 4 pi sigma_a Le / (E density) */
    const double full = profile2_integral(lo, hi);
    double chi2 = 0.0;
    for (int b = 0; b < BINS; ++b) {
        double a = lo + (hi - lo) * b / BINS, e = lo + (hi - lo) * (b + 1) / BINS;
        double expected = c * profile2_integral(a, e) * full * full;
        double mean = sum[b] / N, se = sqrt(fmax(0.0, sq[b] / N - mean * mean) / (N - 1));
        double z = se > 0.0 ? (mean - expected) / se : (mean == expected ? 0.0 : INFINITY);
        printf("slab %d: mean flux %.5f (se %.5f) expected %.5f (%.2f sigma)\n", b, mean, se, expected, z);
        chi2 += z * z;
        assert_true(fabs(z) <= 4.5);
    }
    double expected = c * full * full * full, mean = tot / N, se = sqrt((tot2 / N - mean * mean) / (N - 1));
    printf("total: %.5f (se %.5f) expected %.5f; accepted %.3f; chi2 %.2f (8 dof)\n", mean, se, expected,
           (double)accepted / N, chi2);
    assert_true(fabs(mean - expected) <= 4.0 * se);
    assert_true(chi2 < 26.1); /* chi-square 8 dof, p = 0.001 */
    for (int a = 0; a < 3; ++a) {
        double m = dm[a] / accepted, s = sqrt((dm2[a] / accepted - m * m) / (accepted - 1));
        assert_true(fabs(m) <= 4.0 * s);
    }
    double mz = z2 / accepted, sz = sqrt((z22 / accepted - mz * mz) / (accepted - 1));
    assert_true(fabs(mz - 1.0 / 3.0) <= 4.0 * sz);
    /* the photon source selects the media by the bound on their power */
    assert_true(vbl_media_emission_power(scene) >= expected);
    release(scene, vols);
}

/* ---- every method renders fire light ------------------------------------------------------- */

static const char* const k_layers[] = {"volume_emission", "volume_direct", "volume_from_volume", "surface_direct",
                                       "surface_from_volume", "volume_from_surface", "surface_from_surface"};
enum { LAYERS = sizeof k_layers / sizeof k_layers[0] };

static const vbl_render_method k_methods[] = {VBL_RENDER_PT, VBL_RENDER_VPL, VBL_RENDER_VRL, VBL_RENDER_VBL,
                                              VBL_RENDER_BEAMS};
static const char* const k_names[] = {"pt", "vpl", "vrl", "vbl", "beams"};
enum { METHODS = 5 };

static vbl_render_options options(vbl_render_method method, int passes, int spp, uint64_t seed, int threads)
{
    vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
    o.hybrid = VBL_HYBRID_OFF; /* the method alone (hybrid auto is the default) */
    o.method = method;
    o.passes = passes;
    o.spp = spp;
    o.seed = seed;
    o.threads = threads;
    o.max_bounces = -1;
    o.light_paths = 64;
    return o;
}

/* Per layer: the image sum over pixels and channels (NAN if the film has no such layer). */
static void layer_sums(const vbl_film* film, double* sums)
{
    int w = vbl_film_width(film), h = vbl_film_height(film), c = 0;
    const float* beauty = vbl_film_layer(film, "", &c);
    assert_non_null(beauty);
    for (int l = 0; l < LAYERS; ++l) sums[l] = NAN;
    for (int i = 0; i < w * h; ++i)
        for (int ch = 0; ch < 3; ++ch) {
            double s = 0.0;
            for (int l = 0; l < LAYERS; ++l) {
                const float* p = vbl_film_layer_rgb(film, k_layers[l]);
                if (!p) continue;
                if (isnan(sums[l])) sums[l] = 0.0;
                assert_true(isfinite(p[3 * i + ch]) && p[3 * i + ch] >= 0.0f);
                sums[l] += p[3 * i + ch];
                s += p[3 * i + ch];
            }
            assert_true(isfinite(beauty[c * i + ch]));
            assert_true(fabs(beauty[c * i + ch] - s) <= 1e-5 * s + 1e-9);
        }
}

static void test_every_method(void** state)
{
    (void)state;
    vbl_volume* vols[2];
    vbl_scene* scene = fire_box(8, 8, 1, vols);
    for (int m = 0; m < METHODS; ++m) {
        vbl_film* films[2] = {NULL, NULL};
        for (int t = 0; t < 2; ++t) {
            vbl_render_options o = options(k_methods[m], 1, 2, 11, t + 1);
            vbl_result r = vbl_render(scene, &o, &films[t]);
            if (r) printf("%s: %s\n", k_names[m], vbl_last_error_message());
            assert_int_equal(r, VBL_SUCCESS);
        }
        double sums[LAYERS];
        layer_sums(films[0], sums);
        printf("%-5s:", k_names[m]);
        for (int l = 0; l < LAYERS; ++l) printf(" %s %.4g", k_layers[l], sums[l]);
        printf("\n");
        assert_true(sums[0] > 0.0 && sums[1] > 0.0 && sums[2] > 0.0);
        if (k_methods[m] != VBL_RENDER_BEAMS) assert_true(sums[3] > 0.0); /* beams shade no surfaces */
        int w = vbl_film_width(films[0]), h = vbl_film_height(films[0]), c = 0;
        const float* a = vbl_film_layer(films[0], "", &c);
        const float* b = vbl_film_layer(films[1], "", &c);
        assert_memory_equal(a, b, sizeof(float) * (size_t)(c * w * h));
        vbl_film_release(films[0]);
        vbl_film_release(films[1]);
    }
    release(scene, vols);
}

/* Mean over R renders of each layer's image mean (3 channels summed), and its standard error. */
static void layer_means(const vbl_scene* scene, vbl_render_method method, int R, int passes, int spp, uint64_t seed0,
                        int light_paths, double* mean, double* se)
{
    double sum[LAYERS] = {0}, sq[LAYERS] = {0};
    const int np = scene->camera.width * scene->camera.height;
    for (int r = 0; r < R; ++r) {
        vbl_render_options o = options(method, passes, spp, seed0 + 7919u * (uint64_t)r, 2);
        if (light_paths > 0) o.light_paths = light_paths;
        vbl_film* film = NULL;
        assert_int_equal(vbl_render(scene, &o, &film), VBL_SUCCESS);
        double s[LAYERS];
        layer_sums(film, s);
        for (int l = 0; l < LAYERS; ++l) {
            double v = isnan(s[l]) ? 0.0 : s[l] / np;
            sum[l] += v;
            sq[l] += v * v;
        }
        vbl_film_release(film);
    }
    for (int l = 0; l < LAYERS; ++l) {
        mean[l] = sum[l] / R;
        se[l] = sqrt(fmax(0.0, sq[l] / R - mean[l] * mean[l]) / (R - 1));
    }
}

/* 12 comparisons of R = 8 replicates (Student t, 7 dof): |t| > 5.5 has probability ~1e-3 each */
#define Z_CRIT 5.5

static void compare(const char* name, const double* ref, const double* ref_se, const double* m, const double* se,
                    int layers, double rel_bias)
{
    for (int l = 0; l < layers; ++l) {
        double sigma = sqrt(ref_se[l] * ref_se[l] + se[l] * se[l]), diff = m[l] - ref[l];
        printf("%-5s %-18s: %.5f (se %.5f) vs pt %.5f (se %.5f): %.2f sigma, %.2f %%\n", name, k_layers[l], m[l], se[l],
               ref[l], ref_se[l], fabs(diff) / sigma, 100.0 * diff / ref[l]);
        assert_true(ref[l] > 0.0 && m[l] > 0.0);
        assert_true(fabs(diff) <= Z_CRIT * sigma + rel_bias * ref[l]);
    }
}

static void test_agreement(void** state)
{
    (void)state;
    vbl_volume* vols[2];
    vbl_scene* scene = fire_box(8, 8, 0, vols);
    double ref[LAYERS], ref_se[LAYERS];
    layer_means(scene, VBL_RENDER_PT, 8, 2, 24, 1000, 0, ref, ref_se);
    for (int m = 1; m < METHODS; ++m) {
        double mean[LAYERS], se[LAYERS];
        layer_means(scene, k_methods[m], 8, 3, 2, 2000, 128, mean, se);
        const int biased = k_methods[m] == VBL_RENDER_VBL || k_methods[m] == VBL_RENDER_BEAMS;
        compare(k_names[m], ref, ref_se, mean, se, 3, biased ? 0.03 : 0.0);
    }
    release(scene, vols);
}

/* Diagnostic (not a ctest): `test_render_emission_methods gap R PASSES LIGHT_PATHS [CLAMP]` renders the
 * emissive box R times with pt (2 passes x 24 spp as the agreement test) and with vpl and vrl
 * (PASSES x 2 spp, LIGHT_PATHS paths, vpl.clamp_distance CLAMP), and prints for volume_from_volume
 * the mean, its standard error, the median and the largest replicate's share of the sum: a heavy
 * right tail (an estimator of infinite variance) shows as median < mean and a large share. */
static int cmp_double(const void* a, const void* b)
{
    double x = *(const double*)a, y = *(const double*)b;
    return (x > y) - (x < y);
}

static void gap_row(const vbl_scene* scene, const char* name, vbl_render_method method, int R, int passes, int spp,
                    int light_paths, double clamp, uint64_t seed0)
{
    double* v = calloc((size_t)R, sizeof *v);
    const int np = scene->camera.width * scene->camera.height;
    double sum = 0.0, sq = 0.0, mx = 0.0;
    for (int r = 0; r < R; ++r) {
        vbl_render_options o = options(method, passes, spp, seed0 + 7919u * (uint64_t)r, 2);
        if (light_paths > 0) o.light_paths = light_paths;
        o.vpl.clamp_distance = clamp;
        vbl_film* film = NULL;
        if (vbl_render(scene, &o, &film) != VBL_SUCCESS) {
            printf("%s: %s\n", name, vbl_last_error_message());
            free(v);
            return;
        }
        double s[LAYERS];
        layer_sums(film, s);
        v[r] = s[2] / np;
        sum += v[r];
        sq += v[r] * v[r];
        mx = fmax(mx, v[r]);
        vbl_film_release(film);
    }
    qsort(v, (size_t)R, sizeof *v, cmp_double);
    const double mean = sum / R, se = sqrt(fmax(0.0, sq / R - mean * mean) / (R - 1));
    printf("%-4s R %d passes %d lp %d clamp %g: volume_from_volume mean %.5f se %.5f median %.5f max share %.3f\n",
           name, R, passes, light_paths, clamp, mean, se, 0.5 * (v[(R - 1) / 2] + v[R / 2]), mx / sum);
    fflush(stdout);
    free(v);
}

static int gap(int argc, char** argv)
{
    const int R = argc > 2 ? atoi(argv[2]) : 16, passes = argc > 3 ? atoi(argv[3]) : 3,
              lp = argc > 4 ? atoi(argv[4]) : 128;
    const double clamp = argc > 5 ? atof(argv[5]) : 0.0;
    vbl_volume* vols[2];
    vbl_scene* scene = fire_box(8, 8, 0, vols);
    gap_row(scene, "pt", VBL_RENDER_PT, R, 2, 24, 0, 0.0, 1000);
    gap_row(scene, "vpl", VBL_RENDER_VPL, R, passes, 2, lp, clamp, 2000);
    gap_row(scene, "vrl", VBL_RENDER_VRL, R, passes, 2, lp, 0.0, 2000);
    release(scene, vols);
    return 0;
}

int main(int argc, char** argv)
{
    if (argc > 1 && !strcmp(argv[1], "gap")) return gap(argc, argv);
    if (argc > 1 && !strcmp(argv[1], "agreement")) {
        const struct CMUnitTest slow[] = {cmocka_unit_test(test_agreement)};
        return cmocka_run_group_tests(slow, NULL, NULL);
    }
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_point_sampler),
        cmocka_unit_test(test_every_method),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
