/* Volume core on the generated fixture files ($VBL_FIXTURE_DIR): PNanoVDB point/trilinear sampling
 * equals OpenVDB's PointSampler/BoxSampler at the points of every <name>.samples.txt, and the
 * majorant grid bounds trilinear density along random rays through each loaded fixture. */
#include <dirent.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "core/rng.h"
#include "volume/transmittance.h"

static const char* fixture_dir(void)
{
    const char* dir = getenv("VBL_FIXTURE_DIR");
    if (!dir || !dir[0]) {
        fprintf(stderr, "VBL_FIXTURE_DIR is not set (run through ctest)\n");
        fail();
    }
    return dir;
}

static vbl_volume* load_fixture(const char* dir, const char* base)
{
    char path[2048];
    vbl_volume_load_options opt = VBL_VOLUME_LOAD_OPTIONS_DEFAULT;
    opt.bad_voxels = VBL_BAD_VOXELS_SANITIZE;
    vbl_volume* v = NULL;
    snprintf(path, sizeof path, "%s/%s.vdb", dir, base);
    vbl_result r = vbl_volume_load(path, &opt, &v);
    if (r != VBL_SUCCESS) {
        fprintf(stderr, "cannot load %s: %s\n", path, vbl_last_error_message());
        return NULL;
    }
    return v;
}

static void check_majorant_along_rays(const vbl_volume* v, uint64_t seed)
{
    vbl_volume_info info;
    info.size = sizeof info;
    assert_int_equal(vbl_volume_get_info(v, &info), VBL_SUCCESS);
    vbl_grid_accessor acc;
    vbl_grid_accessor_init(&acc, v);
    vbl_rng rng = vbl_rng_make(seed, 1, 2);
    double ext[3], ctr[3];
    for (int a = 0; a < 3; ++a) {
        ext[a] = info.world_bbox_max[a] - info.world_bbox_min[a];
        ctr[a] = 0.5 * (info.world_bbox_max[a] + info.world_bbox_min[a]);
    }
    double diag = sqrt(ext[0] * ext[0] + ext[1] * ext[1] + ext[2] * ext[2]);
    if (!(diag > 0.0)) return;
    for (int r = 0; r < 300; ++r) {
        vbl_vec3 o = vbl_v3(ctr[0] + ext[0] * (vbl_rng_uniform(&rng) - 0.5), ctr[1] + ext[1] * (vbl_rng_uniform(&rng) - 0.5),
                            ctr[2] + ext[2] * (vbl_rng_uniform(&rng) - 0.5));
        vbl_vec3 d = vbl_v3_normalize(vbl_v3(vbl_rng_uniform(&rng) - 0.5, vbl_rng_uniform(&rng) - 0.5, vbl_rng_uniform(&rng) - 0.5));
        if (r % 4 == 0) d = vbl_v3(r % 8 == 0 ? 1.0 : 0.0, r % 8 == 0 ? 0.0 : -1.0, 0.0);
        vbl_majorant_iter it;
        vbl_majorant_segment s;
        vbl_majorant_iter_init(&it, v, o, d, -diag, diag);
        double prev = NAN;
        while (vbl_majorant_iter_next(&it, &s)) {
            if (!isnan(prev)) assert_true(s.t0 == prev);
            prev = s.t1;
            for (int k = 0; k < 4; ++k) {
                double t = s.t0 + (s.t1 - s.t0) * vbl_rng_uniform(&rng);
                double x = vbl_grid_sample_world(&acc, vbl_v3_madd(o, d, t), VBL_FILTER_TRILINEAR);
                assert_true(x <= s.majorant + 1e-12 * fabs(s.majorant));
                assert_true(x >= s.minorant - 1e-12 * fabs(s.minorant));
            }
        }
    }
}

static void test_sampling_matches_openvdb(void** state)
{
    (void)state;
    const char* dir = fixture_dir();
    DIR* d = opendir(dir);
    if (!d) {
        fprintf(stderr, "fixture directory %s is missing (build target vbl_fixtures)\n", dir);
        fail();
    }
    struct dirent* e;
    int files = 0;
    long points = 0;
    while ((e = readdir(d)) != NULL) {
        const char* suffix = ".samples.txt";
        size_t n = strlen(e->d_name), ns = strlen(suffix);
        if (n <= ns || strcmp(e->d_name + n - ns, suffix) != 0) continue;
        char base[512];
        snprintf(base, sizeof base, "%.*s", (int)(n - ns), e->d_name);
        vbl_volume* v = load_fixture(dir, base);
        assert_non_null(v);
        char path[2048];
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        FILE* f = fopen(path, "r");
        assert_non_null(f);
        double x, y, z, point, box, maxabs = 0.0;
        double (*rows)[5] = malloc(sizeof(double[5]) * 100000);
        int count = 0;
        char line[512];
        while (fgets(line, sizeof line, f) && count < 100000) {
            if (line[0] == '#') continue;
            if (sscanf(line, "%lf %lf %lf %lf %lf", &x, &y, &z, &point, &box) != 5) continue;
            rows[count][0] = x, rows[count][1] = y, rows[count][2] = z, rows[count][3] = point, rows[count][4] = box;
            if (isfinite(point) && fabs(point) > maxabs) maxabs = fabs(point);
            count++;
        }
        fclose(f);
        assert_true(count > 0);
        int bad = 0;
        for (int i = 0; i < count; ++i) {
            if (!isfinite(rows[i][3]) || !isfinite(rows[i][4])) continue; /* NaN fixture: sanitized here */
            double p[3] = {rows[i][0], rows[i][1], rows[i][2]};
            double a = vbl_volume_sample(v, p, VBL_FILTER_NEAREST), b = vbl_volume_sample(v, p, VBL_FILTER_TRILINEAR);
            double floor_tol = 1e-6 * 1e-3 * maxabs;
            if (fabs(a - rows[i][3]) > 1e-6 * fabs(rows[i][3]) + floor_tol ||
                fabs(b - rows[i][4]) > 1e-6 * fabs(rows[i][4]) + floor_tol) {
                if (bad++ < 5)
                    fprintf(stderr, "%s: (%.9g %.9g %.9g) nearest %.9g vs %.9g, trilinear %.9g vs %.9g\n", base, p[0],
                            p[1], p[2], a, rows[i][3], b, rows[i][4]);
            }
            points++;
        }
        free(rows);
        if (bad) fprintf(stderr, "%s: %d of %d points differ\n", base, bad, count);
        assert_int_equal(bad, 0);
        check_majorant_along_rays(v, (uint64_t)files);
        vbl_volume_release(v);
        files++;
    }
    closedir(d);
    if (files == 0) {
        fprintf(stderr, "no *.samples.txt in %s (build target vbl_fixtures)\n", dir);
        fail();
    }
    fprintf(stderr, "compared %ld points in %d fixtures\n", points, files);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sampling_matches_openvdb),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
