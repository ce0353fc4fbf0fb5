/* pt.direct_strata (issue 14): stratified single scattering along camera rays
 * (transport/path_tracing/pt_direct_strata.h).
 *   - quick group: volume_direct of a homogeneous box seen head-on and lit by a distant light
 *     from behind the camera against its closed form (K = 4 and K = 1); bit-identical at 1 and 2
 *     threads, layers summing to the beauty and different from K = 1 (the option takes effect);
 *     finite images at density scales 1e-8 and 1e6;
 *   - agreement group (slow): every layer's image mean at K = 4 agrees with K = 1 within Z_CRIT
 *     standard errors on a heterogeneous sphere lit by a distant, a point (pt.equiangular off, so
 *     the strata feed it too) and a quad light (still the collision's NEE). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "render_test_util.h"
#include "surface_render_util.h"
#include "transport_test_util.h"
#include "vbl/vbl.h"
#include "volume_test_grid.h"

#define Z_CRIT 4.5

static int g_max_bounces = -1; /* render_pt's max_bounces */

static vbl_film* render_pt(const vbl_scene* scene, int strata, int equiangular, int passes, int spp,
                           uint64_t seed, int threads)
{
    vbl_render_options o = tt_options(passes, spp, 0, seed);
    o.method = VBL_RENDER_PT;
    o.threads = threads;
    o.pt.equiangular = equiangular;
    o.pt.direct_strata = strata;
    o.max_bounces = g_max_bounces;
    vbl_film* film = NULL;
    if (vbl_render(scene, &o, &film) != VBL_SUCCESS) fail_msg("render: %s", vbl_last_error_message());
    return film;
}

/* ---- closed form -------------------------------------------------------------------------- */

/* A box of density scale * rho(x, y, z) (rt_make_box: n voxels of size hv, 1 inside, a one-voxel
 * linear ramp outside), seen along +y through its centre with a tiny field of view, lit by a
 * distant light travelling along +y too (from behind the camera). On that line the camera's and
 * the light's optical depths to a point are the same tau(s), so with sigma_s = albedo sigma_t
 * and the phase function at cos = -1 (back-scattering, HG: (1 - g) / (4 pi (1 + g)^2)):
 *   L = albedo E p(-1) int sigma_t(s) exp(-2 tau(s)) ds = albedo E p(-1) (1 - exp(-2 tau_1)) / 2
 * with tau_1 = scale n hv (the ramps add hv / 2 each), whatever the profile along the line. */
static void closed_form_case(double scale, int strata)
{
    const int n = 9, px = 4;
    const double hv = 0.25, albedo = 0.8, g = 0.4, E = 2.0;
    const vbl_vec3 origin = vbl_v3(-0.5 * (n - 1) * hv, -0.5 * (n - 1) * hv, -0.5 * (n - 1) * hv);
    vbl_volume* box = rt_make_box(n, hv, origin);
    assert_non_null(box);
    vbl_camera cam = rt_camera(vbl_v3(0, -4.0, 0), vbl_v3(0, 0, 0), 0.5, px, px);
    vbl_scene* scene = tt_scene(&cam);
    vbl_light l;
    memset(&l, 0, sizeof l);
    l.type = VBL_LIGHT_DISTANT;
    l.direction = vbl_v3(0, 1, 0);
    l.color = vbl_v3(E, E, E);
    assert_int_equal(vbl_scene_add_light(scene, &l), VBL_SUCCESS);
    assert_int_equal(vbl_scene_add_medium(scene, box, scale, vbl_v3(albedo, albedo, albedo), g, NULL), VBL_SUCCESS);
    double tau1 = scale * n * hv;
    double ref = albedo * E * (1.0 - g) / (4.0 * VBL_PI * (1.0 + g) * (1.0 + g)) * 0.5 * -expm1(-2.0 * tau1);
    const int R = 12;
    double s = 0.0, s2 = 0.0;
    for (int k = 0; k < R; ++k) {
        vbl_film* film = render_pt(scene, strata, 1, 1, 16, 31 + 977u * (uint64_t)k, 2);
        check_sum_to_beauty(film);
        double m = layer_total(film, "volume_direct") / (3.0 * px * px);
        s += m;
        s2 += m * m;
        vbl_film_release(film);
    }
    double mean = s / R, se = sqrt(fmax((s2 - R * mean * mean) / (R - 1), 0.0) / R);
    printf("scale %g, direct_strata %d: volume_direct %.6f (se %.6f), closed form %.6f, z = %+.2f\n", scale, strata,
           mean, se, ref, (mean - ref) / se);
    assert_true(se > 0.0 && se < 0.05 * ref);
    assert_true(fabs(mean - ref) <= Z_CRIT * se);
    vbl_scene_release(scene);
    vt_free(box);
}

static void test_closed_form(void** state)
{
    (void)state;
    closed_form_case(0.4, 4); /* tau_1 = 0.9 */
    closed_form_case(3.0, 4); /* tau_1 = 6.75 */
    closed_form_case(3.0, 1);
}

/* ---- a heterogeneous sphere with three light types ---------------------------------------- */

#define W 12
#define H 10

typedef struct strata_case {
    vbl_scene* scene;
    vbl_volume* volume;
} strata_case;

static strata_case make_case_sized(double scale, int w, int h)
{
    strata_case c;
    vbl_camera cam = rt_camera(vbl_v3(0.3, -4.0, 0.6), vbl_v3(0, 0, -0.2), 40.0, w, h);
    c.scene = tt_scene(&cam);
    c.volume = tt_make_sphere(16, 0.9);
    assert_int_equal(vbl_scene_add_medium(c.scene, c.volume, scale, vbl_v3(0.9, 0.8, 0.7), 0.5, NULL), VBL_SUCCESS);
    tt_add_distant(c.scene, vbl_v3(0.3, 0.5, -1.0), 1.5);
    tt_add_point(c.scene, vbl_v3(0.3, -0.2, 1.1), 2.0);
    vbl_light q;
    memset(&q, 0, sizeof q);
    q.type = VBL_LIGHT_QUAD;
    q.corner = vbl_v3(-1.0, -0.6, 1.4);
    q.edge1 = vbl_v3(0, 1, 0);
    q.edge2 = vbl_v3(1, 0, 0); /* normal -z: emits downward */
    q.area = 1.0;
    q.normal = vbl_v3(0, 0, -1);
    q.color = vbl_v3(1, 1, 1);
    assert_int_equal(vbl_scene_add_light(c.scene, &q), VBL_SUCCESS);
    return c;
}

static strata_case make_case(double scale) { return make_case_sized(scale, W, H); }

static void free_case(strata_case* c)
{
    vbl_scene_release(c->scene);
    vt_free(c->volume);
}

static void test_deterministic_and_active(void** state)
{
    (void)state;
    strata_case c = make_case(3.0);
    vbl_film* a = render_pt(c.scene, 4, 0, 2, 2, 5, 1);
    vbl_film* b = render_pt(c.scene, 4, 0, 2, 2, 5, 2);
    vbl_film* d = render_pt(c.scene, 1, 0, 2, 2, 5, 2);
    check_sum_to_beauty(a);
    check_identical_and_differs(a, b, d);
    vbl_film_release(a);
    vbl_film_release(b);
    vbl_film_release(d);
    free_case(&c);
}

static void test_extreme_densities(void** state)
{
    (void)state;
    /* at 1e6 every shadow ray through the core costs ~1e4 lookups whatever the estimator, so a
     * few pixels and single scattering only (the strata feed volume_direct) */
    const double scales[] = {1e-8, 1e6};
    for (int i = 0; i < 2; ++i) {
        strata_case c = make_case_sized(scales[i], i == 0 ? 4 : 2, i == 0 ? 3 : 2);
        g_max_bounces = i == 0 ? -1 : 1;
        for (int eq = 0; eq <= (i == 0); ++eq) { /* eq off: the strata feed the point light too */
            vbl_film* film = render_pt(c.scene, 8, eq, 1, i == 0 ? 2 : 1, 9, 2);
            check_sum_to_beauty(film); /* and finite */
            vbl_film_release(film);
        }
        free_case(&c);
    }
    g_max_bounces = -1;
}

/* layer_stats's render (surface_render_util.h): config points at the strata count. */
#define K 16
static vbl_film* render_strata(const vbl_scene* scene, const void* config, uint64_t seed)
{
    return render_pt(scene, *(const int*)config, 0, 4, 16, seed, 2);
}

static void test_agrees_per_layer(void** state)
{
    (void)state;
    strata_case c = make_case(3.0);
    double m4[VBL_CLASS_COUNT], se4[VBL_CLASS_COUNT], m1[VBL_CLASS_COUNT], se1[VBL_CLASS_COUNT];
    const int four = 4, one = 1;
    layer_stats(render_strata, c.scene, &four, K, 11, m4, se4);
    layer_stats(render_strata, c.scene, &one, K, 22, m1, se1);
    int checked = 0;
    for (int l = 0; l < VBL_CLASS_COUNT; ++l) {
        if (!(m1[l] > 0.0)) continue;
        double se = sqrt(se4[l] * se4[l] + se1[l] * se1[l]);
        double z = (m4[l] - m1[l]) / se;
        printf("%-22s K=4 %.6f (se %.6f)  K=1 %.6f (se %.6f)  z = %+.2f  se ratio %.2f\n", layer_names[l], m4[l],
               se4[l], m1[l], se1[l], z, se4[l] / se1[l]);
        assert_true(se > 0.0 && se < 0.1 * m1[l]);
        assert_true(fabs(z) <= Z_CRIT);
        ++checked;
    }
    assert_true(checked >= 2); /* volume_direct, volume_from_volume */
    free_case(&c);
}

/* `test_render_pt_direct_strata` runs the quick group; `... agreement` the statistical renders. */
int main(int argc, char** argv)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_closed_form),
        cmocka_unit_test(test_deterministic_and_active),
        cmocka_unit_test(test_extreme_densities),
    };
    const struct CMUnitTest agreement[] = {
        cmocka_unit_test(test_agrees_per_layer),
    };
    if (argc > 1 && !strcmp(argv[1], "agreement")) return cmocka_run_group_tests(agreement, NULL, NULL);
    return cmocka_run_group_tests(tests, NULL, NULL);
}
