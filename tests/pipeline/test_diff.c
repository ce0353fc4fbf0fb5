/* `vbl diff` end to end: two EXRs with known differences are written with vbl_exr_write into a
 * mkdtemp folder, the real binary compares them, and the printed numbers are checked against
 * values computed here from the formulas (independently of image_metrics.c), plus the
 * image_metrics functions directly and the refusals (sizes, no common layer: exit 3). */
#define _POSIX_C_SOURCE 200809L /* mkdtemp, popen */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmocka.h>

#include "image_metrics.h"
#include "vbl_exr.h"

#define W 8
#define H 6
#define N (W * H)

static char* dt_dir;

static const char* dt_path(const char* name)
{
    static char buffers[4][1024];
    static int slot;
    char* b = buffers[slot++ & 3];
    snprintf(b, 1024, "%s/%s", dt_dir, name);
    return b;
}

/* Runs `vbl diff ARGS` with stdout+stderr captured; returns the exit status. */
static int dt_run(const char* args, char** output)
{
    const char* bin = getenv("VBL_BINARY_DIR");
    char command[4096];
    snprintf(command, sizeof command, "'%s/bin/vbl' diff %s 2>&1", bin ? bin : ".", args);
    FILE* p = popen(command, "r");
    assert_non_null(p);
    size_t cap = 1 << 16, n = 0, got;
    char* text = malloc(cap);
    assert_non_null(text);
    while ((got = fread(text + n, 1, cap - n - 1, p)) > 0) n += got;
    text[n] = 0;
    int status = pclose(p);
    *output = text;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/* Reference values of an image: smooth, positive and with zeros (so the offset matters). */
static float dt_ref(int layer, int c, int p)
{
    if ((p + c) % 7 == 0) return 0.0f;
    return (float)(0.25 * (layer + 1) + 0.1 * c + 0.013 * p);
}

/* A's values: the reference plus a known perturbation. */
static float dt_test(int layer, int c, int p)
{
    return dt_ref(layer, c, p) + (float)((layer + 1) * 0.01 * ((p * 3 + c) % 5 - 2));
}

typedef struct dt_expected {
    double rmae, rmse, max_abs;
} dt_expected;

/* The metrics straight from the definition over float values. */
static dt_expected dt_expect(int layer, int channels)
{
    double sum_ref = 0.0;
    for (int c = 0; c < channels; ++c)
        for (int p = 0; p < N; ++p) sum_ref += fabs((double)dt_ref(layer, c, p));
    double offset = 0.01 * sum_ref / (channels * N);
    double rel = 0.0, sq = 0.0, mx = 0.0;
    for (int c = 0; c < channels; ++c)
        for (int p = 0; p < N; ++p) {
            double a = dt_test(layer, c, p), b = dt_ref(layer, c, p);
            rel += fabs(a - b) / (fabs(b) + offset);
            sq += (a - b) * (a - b);
            mx = fmax(mx, fabs(a - b));
        }
    dt_expected e = {rel / (channels * N), sqrt(sq / (channels * N)), mx};
    return e;
}

/* Writes an EXR with a beauty (RGB, layer 0), "emission" (RGB, layer 1) and optionally an extra
 * layer `extra` (RGB, layer 2); `test` selects A's perturbed values. */
static void dt_write(const char* path, int width, int height, int test, const char* extra)
{
    float* px[3];
    for (int l = 0; l < 3; ++l) {
        px[l] = malloc(sizeof(float) * 3 * (size_t)width * (size_t)height);
        assert_non_null(px[l]);
        for (int p = 0; p < width * height; ++p)
            for (int c = 0; c < 3; ++c)
                px[l][p * 3 + c] = test ? dt_test(l, c, p % N) : dt_ref(l, c, p % N);
    }
    vbl_exr_layer layers[3] = {
        {"", 3, NULL, px[0], 0},
        {"emission", 3, NULL, px[1], 0},
        {extra ? extra : "unused", 3, NULL, extra ? px[2] : NULL, 0},
    };
    vbl_exr_write_options options = VBL_EXR_WRITE_OPTIONS_DEFAULT;
    assert_int_equal(vbl_exr_write(path, width, height, layers, 3, &options), VBL_SUCCESS);
    for (int l = 0; l < 3; ++l) free(px[l]);
}

/* Finds the table row of `layer` and parses channels, pixels, rMAE, RMSE, max. */
static int dt_row(const char* text, const char* layer, int* ch, long* pixels, double v[3])
{
    const char* line = text;
    while (line && *line) {
        char name[256];
        if (sscanf(line, "%255s %d %ld %lf %lf %lf", name, ch, pixels, &v[0], &v[1], &v[2]) == 6 &&
            !strcmp(name, layer))
            return 1;
        line = strchr(line, '\n');
        if (line) ++line;
    }
    return 0;
}

static void dt_check_close(double got, double want)
{
    if (fabs(got - want) > 1e-6 * fabs(want) + 1e-12) fail_msg("got %.9g, want %.9g", got, want);
}

static int dt_setup(void** state)
{
    (void)state;
    const char* tmp = getenv("TMPDIR");
    char buffer[1024];
    snprintf(buffer, sizeof buffer, "%s/vbl_diff_XXXXXX", tmp && tmp[0] ? tmp : "/tmp");
    assert_non_null(mkdtemp(buffer));
    dt_dir = strdup(buffer);
    dt_write(dt_path("a.exr"), W, H, 1, "volume_direct");
    dt_write(dt_path("b.exr"), W, H, 0, NULL);
    dt_write(dt_path("big.exr"), W + 1, H, 0, NULL);
    /* Only a "Z"-less, differently named single layer: no channel in common with a.exr. */
    float z[N];
    for (int p = 0; p < N; ++p) z[p] = (float)p;
    const char* zname[] = {"Y"};
    vbl_exr_layer other = {"depth", 1, zname, z, 0};
    vbl_exr_write_options options = VBL_EXR_WRITE_OPTIONS_DEFAULT;
    assert_int_equal(vbl_exr_write(dt_path("other.exr"), W, H, &other, 1, &options), VBL_SUCCESS);
    return 0;
}

static int dt_teardown(void** state)
{
    (void)state;
    const char* names[] = {"a.exr", "b.exr", "big.exr", "other.exr"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; ++i) remove(dt_path(names[i]));
    rmdir(dt_dir);
    free(dt_dir);
    return 0;
}

static void test_table_matches_formulas(void** state)
{
    (void)state;
    char args[3072], *out;
    snprintf(args, sizeof args, "'%s' '%s'", dt_path("a.exr"), dt_path("b.exr"));
    int code = dt_run(args, &out);
    if (code != 0) fail_msg("exit %d: %s", code, out);
    const char* layers[] = {"beauty", "emission"};
    for (int l = 0; l < 2; ++l) {
        int ch;
        long pixels;
        double v[3];
        if (!dt_row(out, layers[l], &ch, &pixels, v)) fail_msg("no row for %s in:\n%s", layers[l], out);
        assert_int_equal(ch, 3);
        assert_int_equal(pixels, N);
        dt_expected e = dt_expect(l, 3);
        assert_true(e.rmae > 0.01); /* the perturbation is not negligible */
        dt_check_close(v[0], e.rmae);
        dt_check_close(v[1], e.rmse);
        dt_check_close(v[2], e.max_abs);
    }
    /* volume_direct is only in A: not compared. */
    assert_null(strstr(out, "volume_direct"));
    free(out);
}

static void test_json_and_layer_filter(void** state)
{
    (void)state;
    char args[3072], *out;
    snprintf(args, sizeof args, "'%s' '%s' --layer emission --json", dt_path("a.exr"), dt_path("b.exr"));
    int code = dt_run(args, &out);
    if (code != 0) fail_msg("exit %d: %s", code, out);
    assert_non_null(strstr(out, "\"name\": \"emission\""));
    assert_null(strstr(out, "\"name\": \"\""));
    const char* r = strstr(out, "\"rmae\": ");
    assert_non_null(r);
    dt_check_close(strtod(r + 8, NULL), dt_expect(1, 3).rmae);
    const char* m = strstr(out, "\"max_abs\": ");
    assert_non_null(m);
    dt_check_close(strtod(m + 11, NULL), dt_expect(1, 3).max_abs);
    assert_non_null(strstr(out, "\"pixels\": 48"));
    free(out);
    /* Identical files: zero error. */
    snprintf(args, sizeof args, "'%s' '%s' --layer beauty", dt_path("b.exr"), dt_path("b.exr"));
    code = dt_run(args, &out);
    assert_int_equal(code, 0);
    int ch;
    long pixels;
    double v[3];
    assert_true(dt_row(out, "beauty", &ch, &pixels, v));
    assert_true(v[0] == 0.0 && v[1] == 0.0 && v[2] == 0.0);
    free(out);
}

static void test_refusals(void** state)
{
    (void)state;
    char args[3072], *out;
    snprintf(args, sizeof args, "'%s' '%s'", dt_path("a.exr"), dt_path("big.exr"));
    assert_int_equal(dt_run(args, &out), 3);
    assert_non_null(strstr(out, "big.exr"));
    assert_non_null(strstr(out, "9x6"));
    free(out);
    snprintf(args, sizeof args, "'%s' '%s'", dt_path("a.exr"), dt_path("other.exr"));
    assert_int_equal(dt_run(args, &out), 3);
    assert_non_null(strstr(out, "other.exr"));
    assert_non_null(strstr(out, "no layer"));
    free(out);
    snprintf(args, sizeof args, "'%s' '%s' --layer volume_direct", dt_path("a.exr"), dt_path("b.exr"));
    assert_int_equal(dt_run(args, &out), 3);
    assert_non_null(strstr(out, "volume_direct"));
    free(out);
    snprintf(args, sizeof args, "'%s' '%s'", dt_path("a.exr"), dt_path("missing.exr"));
    assert_int_equal(dt_run(args, &out), 3);
    assert_non_null(strstr(out, "missing.exr"));
    free(out);
    assert_int_equal(dt_run("only_one.exr", &out), 2);
    free(out);
}

static void test_metrics_functions(void** state)
{
    (void)state;
    /* Interleaved RGB, stride 3, and an all-zero reference (offset 0.01: finite). */
    float a[6] = {1, 2, 3, 1, 2, 5}, b[6] = {1, 2, 3, 1, 2, 3}, zero[6] = {0};
    const float* pa[3] = {a, a + 1, a + 2};
    const float* pb[3] = {b, b + 1, b + 2};
    const float* pz[3] = {zero, zero + 1, zero + 2};
    vbl_image_metrics m;
    vbl_image_metrics_compute(pa, pb, 3, 2, 3, &m);
    double mean_ref = 12.0 / 6.0;
    assert_true(fabs(m.mean_abs_ref - mean_ref) < 1e-12);
    assert_true(fabs(m.rmae - (2.0 / (3.0 + 0.01 * mean_ref)) / 6.0) < 1e-12);
    assert_true(fabs(m.rmse - sqrt(4.0 / 6.0)) < 1e-12);
    assert_true(m.max_abs == 2.0);
    vbl_image_metrics_compute(pa, pz, 3, 2, 3, &m);
    assert_true(isfinite(m.rmae) && m.rmae > 0.0);
    assert_true(fabs(m.rmae - (14.0 / 0.01) / 6.0) < 1e-9);
    /* NaN values are counted and left out. */
    a[0] = NAN;
    vbl_image_metrics_compute(pa, pb, 3, 2, 3, &m);
    assert_int_equal(m.non_finite, 1);
    assert_true(isfinite(m.rmae));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_table_matches_formulas),
        cmocka_unit_test(test_json_and_layer_filter),
        cmocka_unit_test(test_refusals),
        cmocka_unit_test(test_metrics_functions),
    };
    return cmocka_run_group_tests(tests, dt_setup, dt_teardown);
}
