/* The path tracer against closed forms: white furnace (albedo 1 in a constant environment returns
 * the environment), single scattering from a distant and a point light vs numerical quadrature
 * (pt with max_bounces 1, full pt's volume_direct layer, and vrl's, which is pt's estimator), layer
 * sums, determinism across thread counts, dense media and extreme parameters. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "quad.h"
#include "render/render_internal.h"
#include "render_test_util.h"
#include "transport/virtual_lights/vrl.h"
#include "vbl/vbl.h"
#include "volume_test_grid.h"

/* ---- helpers ------------------------------------------------------------------------------ */

typedef struct rt_box {
    int n;
    double h;
    vbl_vec3 origin;
    vbl_volume* volume;
} rt_box;

/* density 1 on [-half, half]^3 (n voxels per axis), ramping to 0 within one voxel outside */
static rt_box make_centered_box(int n, double half)
{
    rt_box b;
    b.n = n;
    b.h = 2.0 * half / (n - 1);
    b.origin = vbl_v3(-half, -half, -half);
    b.volume = rt_make_box(n, b.h, b.origin);
    assert_non_null(b.volume);
    return b;
}

static vbl_scene* make_scene(const vbl_camera* cam)
{
    vbl_scene* scene = NULL;
    assert_int_equal(vbl_scene_create_empty("test", cam, &scene), VBL_SUCCESS);
    return scene;
}

static void add_env(vbl_scene* scene, double L)
{
    vbl_light l;
    memset(&l, 0, sizeof l);
    l.type = VBL_LIGHT_ENVIRONMENT;
    l.color = vbl_v3(L, L, L);
    assert_int_equal(vbl_scene_add_light(scene, &l), VBL_SUCCESS);
}

static int all_finite(const vbl_film* film)
{
    int w = vbl_film_width(film), h = vbl_film_height(film);
    for (int i = 0; i < vbl_film_layer_count(film); ++i) {
        int c = 0;
        const float* p = vbl_film_layer(film, vbl_film_layer_name(film, i), &c);
        for (int k = 0; k < w * h * c; ++k)
            if (!isfinite(p[k])) return 0;
    }
    return 1;
}

/* Mean over all pixels of channel `ch` of a layer and the standard error from the variance AOV. */
static void image_mean(const vbl_film* film, const char* layer, int ch, double* mean, double* se)
{
    int w = vbl_film_width(film), h = vbl_film_height(film), c = 0, cv = 0;
    const float* p = vbl_film_layer(film, layer, &c);
    const float* var = vbl_film_layer(film, "variance", &cv);
    assert_non_null(p);
    double s = 0.0, v = 0.0;
    for (int i = 0; i < w * h; ++i) {
        s += p[i * c + ch];
        v += var[i * 3 + ch];
    }
    *mean = s / (w * h);
    *se = sqrt(v) / (w * h);
}

static vbl_render_options options_for(int passes, int spp, int max_bounces, uint64_t seed)
{
    vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
    o.passes = passes;
    o.spp = spp;
    o.max_bounces = max_bounces;
    o.seed = seed;
    o.threads = 2;
    return o;
}

/* ---- white furnace ------------------------------------------------------------------------ */

static void furnace(vbl_vec3 camera_position, double g)
{
    rt_box box = make_centered_box(9, 1.0);
    vbl_camera cam = rt_camera(camera_position, vbl_v3(0, 0, 0), 50.0, 16, 16);
    vbl_scene* scene = make_scene(&cam);
    add_env(scene, 1.0);
    assert_int_equal(vbl_scene_add_medium(scene, box.volume, 1.5, vbl_v3(1, 1, 1), g, NULL), VBL_SUCCESS);
    vbl_render_options o = options_for(2, 16, -1, 11);
    vbl_film* film = NULL;
    assert_int_equal(vbl_render(scene, &o, &film), VBL_SUCCESS);
    assert_true(all_finite(film));
    for (int ch = 0; ch < 3; ++ch) {
        double mean, se;
        image_mean(film, "", ch, &mean, &se);
        printf("furnace g=%.2f channel %d: mean %.5f se %.5f (%.2f se)\n", g, ch, mean, se, fabs(mean - 1.0) / se);
        assert_true(se > 0.0 && se < 0.02);
        assert_true(fabs(mean - 1.0) <= 4.0 * se);
    }
    /* pixels whose rays miss the medium see the environment exactly */
    int c;
    const float* beauty = vbl_film_layer(film, "", &c);
    for (int i = 0; i < 16 * 16; ++i)
        if (beauty[4 * i + 3] == 0.0f) assert_true(beauty[4 * i] == 1.0f);
    vbl_film_release(film);
    vbl_scene_release(scene);
    vt_free(box.volume);
}

static void test_furnace_outside(void** state)
{
    (void)state;
    furnace(vbl_v3(0.3, -4.0, 0.5), 0.5);
}

static void test_furnace_inside(void** state)
{
    (void)state;
    furnace(vbl_v3(0.1, -0.2, 0.3), -0.3);
}

/* ---- single scattering vs quadrature ------------------------------------------------------ */

typedef struct ss_ref {
    rt_box box;
    double scale, albedo, g;
    int point;             /* 1: point light at `light_pos` with intensity I; 0: distant */
    vbl_vec3 light_pos;    /* point */
    vbl_vec3 light_dir;    /* distant: direction of travel */
    double intensity;      /* I (W/sr) or E (W/m^2) */
    vbl_vec3 o, d;         /* current camera ray */
    vbl_vec3 a, b;         /* current segment for optical depth */
} ss_ref;

static double ref_density(void* ctx, vbl_vec3 p)
{
    ss_ref* r = ctx;
    return r->scale * rt_box_density(r->box.n, r->box.h, r->box.origin, p);
}

static double segment_integrand(double s, void* ctx)
{
    ss_ref* r = ctx;
    return ref_density(r, vbl_v3_add(r->a, vbl_v3_scale(vbl_v3_sub(r->b, r->a), s)));
}

static double optical_depth(ss_ref* r, vbl_vec3 a, vbl_vec3 b)
{
    r->a = a;
    r->b = b;
    double len = vbl_v3_length(vbl_v3_sub(b, a));
    return len * vbl_quad_adaptive(segment_integrand, r, 0.0, 1.0, 1e-8, 1e-7);
}

static double hg(double g, double c) { return (1 - g * g) / (4 * VBL_PI * pow(1 + g * g - 2 * g * c, 1.5)); }

static double ray_integrand(double t, void* ctx)
{
    ss_ref* r = ctx;
    vbl_vec3 o = r->o, d = r->d;
    vbl_vec3 x = vbl_v3_madd(o, d, t);
    double sigma_t = ref_density(r, x);
    if (sigma_t <= 0.0) return 0.0;
    double Li, cos_theta;
    vbl_vec3 far;
    if (r->point) {
        vbl_vec3 to = vbl_v3_sub(r->light_pos, x);
        double d2 = vbl_v3_dot(to, to);
        Li = r->intensity / d2;
        cos_theta = vbl_v3_dot(vbl_v3_normalize(to), d); /* light travels -to, then along -d */
        far = r->light_pos;
    } else {
        Li = r->intensity;
        cos_theta = vbl_v3_dot(vbl_v3_scale(r->light_dir, -1.0), d);
        far = vbl_v3_madd(x, r->light_dir, -10.0);
    }
    double tau_light = optical_depth(r, x, far);
    double tau_cam = optical_depth(r, o, x);
    r->o = o;
    r->d = d;
    return exp(-tau_cam - tau_light) * r->albedo * sigma_t * hg(r->g, cos_theta) * Li;
}

static double reference_image_mean(ss_ref* r, const vbl_camera* cam, int grid)
{
    double sum = 0.0;
    for (int j = 0; j < grid; ++j)
        for (int i = 0; i < grid; ++i) {
            vbl_camera_ray(cam, (i + 0.5) * cam->width / grid, (j + 0.5) * cam->height / grid, &r->o, &r->d);
            sum += vbl_quad_adaptive(ray_integrand, r, 2.0, 6.5, 1e-8, 1e-6);
        }
    return sum / (grid * grid);
}

static void single_scatter_case(int point)
{
    ss_ref r;
    memset(&r, 0, sizeof r);
    r.box = make_centered_box(9, 1.0);
    r.scale = 0.25;
    r.albedo = 0.8;
    r.g = 0.4;
    r.point = point;
    r.light_pos = vbl_v3(0.5, 0.5, 1.6);
    r.light_dir = vbl_v3_normalize(vbl_v3(0.3, 0.5, -1.0));
    r.intensity = point ? 3.0 : 2.0;
    vbl_camera cam = rt_camera(vbl_v3(0.2, -4.0, 0.1), vbl_v3(0, 0, 0), 30.0, 16, 16);
    vbl_scene* scene = make_scene(&cam);
    vbl_light l;
    memset(&l, 0, sizeof l);
    l.type = point ? VBL_LIGHT_POINT : VBL_LIGHT_DISTANT;
    l.position = r.light_pos;
    l.direction = r.light_dir;
    l.color = vbl_v3(r.intensity, r.intensity, r.intensity);
    assert_int_equal(vbl_scene_add_light(scene, &l), VBL_SUCCESS);
    assert_int_equal(vbl_scene_add_medium(scene, r.box.volume, r.scale, vbl_v3(r.albedo, r.albedo, r.albedo), r.g, NULL),
                     VBL_SUCCESS);
    double ref = reference_image_mean(&r, &cam, 16);

    struct {
        const char* label;
        int max_bounces;
        const vbl_estimator* est;
        const char* layer;
        int pt_equiangular;
    } runs[4] = {{"pt max_bounces=1", 1, NULL, "volume_direct", 1},
                 {"pt unlimited (volume_direct layer)", -1, NULL, "volume_direct", 1},
                 {"vrl (pt_camera_classes.h)", -1, &vbl_estimator_vrl, "volume_direct", 1},
                 {"pt max_bounces=1, equiangular off", 1, NULL, "volume_direct", 0}};
    for (int k = 0; k < 4; ++k) {
        vbl_render_options o = options_for(2, 32, runs[k].max_bounces, 100 + k);
        o.pt.equiangular = runs[k].pt_equiangular;
        o.light_paths = 16; /* vrl: its volume_direct needs no light paths */
        vbl_film* film = NULL;
        if (runs[k].est)
            assert_int_equal(vbl_render_with_estimator(scene, &o, runs[k].est, &film), VBL_SUCCESS);
        else
            assert_int_equal(vbl_render(scene, &o, &film), VBL_SUCCESS);
        assert_true(all_finite(film));
        double mean, se;
        image_mean(film, runs[k].layer, 1, &mean, &se);
        printf("%s light, %s: mean %.6f ref %.6f se %.6f (%.2f se)\n", point ? "point" : "distant", runs[k].label, mean,
               ref, se, fabs(mean - ref) / se);
        assert_true(se > 0.0 && se < 0.05 * ref);
        assert_true(fabs(mean - ref) <= 4.0 * se + 1e-3 * ref);
        vbl_film_release(film);
    }
    vbl_scene_release(scene);
    vt_free(r.box.volume);
}

static void test_single_scatter_distant(void** state)
{
    (void)state;
    single_scatter_case(0);
}

static void test_single_scatter_point(void** state)
{
    (void)state;
    single_scatter_case(1);
}

/* ---- layers, determinism, robustness ------------------------------------------------------ */

static vbl_scene* mixed_scene(rt_box* a, rt_box* b, double scale, double g, vbl_vec3 cam_pos, int res)
{
    vbl_camera cam = rt_camera(cam_pos, vbl_v3(0, 0, 0), 45.0, res, res);
    vbl_scene* scene = make_scene(&cam);
    add_env(scene, 0.2);
    vbl_light l;
    memset(&l, 0, sizeof l);
    l.type = VBL_LIGHT_POINT;
    l.position = vbl_v3(1.5, -1.5, 2.0);
    l.color = vbl_v3(5, 4, 3);
    assert_int_equal(vbl_scene_add_light(scene, &l), VBL_SUCCESS);
    memset(&l, 0, sizeof l);
    l.type = VBL_LIGHT_QUAD;
    l.corner = vbl_v3(-0.5, -0.5, 2.0);
    l.edge1 = vbl_v3(0, 1, 0);
    l.edge2 = vbl_v3(1, 0, 0); /* normal -z: emits downward */
    l.area = 1.0;
    l.normal = vbl_v3(0, 0, -1);
    l.color = vbl_v3(2, 2, 2);
    assert_int_equal(vbl_scene_add_light(scene, &l), VBL_SUCCESS);
    *a = make_centered_box(9, 1.0);
    *b = make_centered_box(5, 0.6);
    vbl_affine shift = {{{1, 0, 0, 0.5}, {0, 1, 0, 0}, {0, 0, 1, 0.3}}};
    assert_int_equal(vbl_scene_add_medium(scene, a->volume, scale, vbl_v3(0.9, 0.8, 0.7), g, NULL), VBL_SUCCESS);
    assert_int_equal(vbl_scene_add_medium(scene, b->volume, 2.0 * scale, vbl_v3(0.5, 0.9, 0.99), -g * 0.5, &shift),
                     VBL_SUCCESS);
    return scene;
}

static void test_layers_sum_and_determinism(void** state)
{
    (void)state;
    rt_box a, b;
    vbl_scene* scene = mixed_scene(&a, &b, 1.0, 0.6, vbl_v3(0.3, -4.0, 0.5), 16);
    vbl_film* films[2] = {NULL, NULL};
    for (int k = 0; k < 2; ++k) {
        vbl_render_options o = options_for(2, 2, -1, 5);
        o.threads = k + 1;
        assert_int_equal(vbl_render(scene, &o, &films[k]), VBL_SUCCESS);
        assert_true(all_finite(films[k]));
    }
    assert_int_equal(vbl_film_layer_count(films[0]), vbl_film_layer_count(films[1]));
    for (int i = 0; i < vbl_film_layer_count(films[0]); ++i) {
        const char* name = vbl_film_layer_name(films[0], i);
        int c0 = 0, c1 = 0;
        const float* p0 = vbl_film_layer(films[0], name, &c0);
        const float* p1 = vbl_film_layer(films[1], name, &c1);
        assert_int_equal(c0, c1);
        assert_memory_equal(p0, p1, sizeof(float) * 16 * 16 * c0);
    }
    /* layers present and summing to the beauty exactly in float */
    const float* e = vbl_film_layer_rgb(films[0], "background");
    const float* d = vbl_film_layer_rgb(films[0], "volume_direct");
    const float* m = vbl_film_layer_rgb(films[0], "volume_from_volume");
    int c = 0;
    const float* beauty = vbl_film_layer(films[0], "", &c);
    assert_non_null(e);
    assert_non_null(d);
    assert_non_null(m);
    assert_int_equal(c, 4);
    assert_non_null(vbl_film_layer(films[0], "Z", NULL));
    double dsum = 0.0, msum = 0.0;
    for (int i = 0; i < 16 * 16; ++i)
        for (int k = 0; k < 3; ++k) {
            float s = e[3 * i + k];
            s += d[3 * i + k];
            s += m[3 * i + k];
            assert_true(s == beauty[4 * i + k]);
            dsum += d[3 * i + k];
            msum += m[3 * i + k];
        }
    assert_true(dsum > 0.0 && msum > 0.0);
    vbl_film_stats stats;
    memset(&stats, 0, sizeof stats);
    stats.size = sizeof stats;
    assert_int_equal(vbl_film_get_stats(films[1], &stats), VBL_SUCCESS);
    assert_int_equal(stats.passes, 2);
    assert_int_equal(stats.threads, 2);
    /* a different seed gives a different image */
    vbl_render_options o = options_for(2, 2, -1, 6);
    vbl_film* other = NULL;
    assert_int_equal(vbl_render(scene, &o, &other), VBL_SUCCESS);
    assert_true(memcmp(vbl_film_layer(other, "", NULL), beauty, sizeof(float) * 16 * 16 * 4) != 0);
    vbl_film_release(other);
    vbl_film_release(films[0]);
    vbl_film_release(films[1]);
    vbl_scene_release(scene);
    vt_free(a.volume);
    vt_free(b.volume);
}

static int stop_after_one(const vbl_render_progress* p, void* user)
{
    (void)user;
    return p->pass >= 1;
}

static void test_cancel_and_time_limit(void** state)
{
    (void)state;
    rt_box a, b;
    vbl_scene* scene = mixed_scene(&a, &b, 0.5, 0.2, vbl_v3(0.3, -4.0, 0.5), 8);
    vbl_render_options o = options_for(5, 1, -1, 1);
    o.callback = stop_after_one;
    vbl_film* film = NULL;
    assert_int_equal(vbl_render(scene, &o, &film), VBL_ERROR_INTERRUPTED);
    assert_non_null(film);
    const float* samples = vbl_film_layer(film, "samples", NULL);
    assert_true(samples[0] == 1.0f);
    vbl_film_release(film);
    o = options_for(1000, 1, -1, 1);
    o.time_limit = 1e-9; /* with min_passes 1: stops after the first pass */
    o.min_passes = 1;
    assert_int_equal(vbl_render(scene, &o, &film), VBL_SUCCESS);
    vbl_film_stats stats;
    memset(&stats, 0, sizeof stats);
    stats.size = sizeof stats;
    vbl_film_get_stats(film, &stats);
    assert_int_equal(stats.passes, 1);
    assert_int_equal(stats.time_limited, 1);
    vbl_film_release(film);
    vbl_scene_release(scene);
    vt_free(a.volume);
    vt_free(b.volume);
}

static void test_dense_medium(void** state)
{
    (void)state;
    rt_box box = make_centered_box(9, 1.0);
    vbl_camera cam = rt_camera(vbl_v3(0.2, -4.0, 0.3), vbl_v3(0, 0, 0), 40.0, 12, 12);
    vbl_scene* scene = make_scene(&cam);
    add_env(scene, 1.0);
    assert_int_equal(vbl_scene_add_medium(scene, box.volume, 30.0, vbl_v3(0.99, 0.99, 0.99), 0.3, NULL), VBL_SUCCESS);
    vbl_render_options o = options_for(1, 8, -1, 3);
    vbl_film* film = NULL;
    assert_int_equal(vbl_render(scene, &o, &film), VBL_SUCCESS);
    assert_true(all_finite(film));
    int c;
    const float* beauty = vbl_film_layer(film, "", &c);
    int opaque = 0;
    for (int i = 0; i < 12 * 12; ++i)
        if (beauty[4 * i + 3] > 0.99f) {
            ++opaque;
            assert_true(beauty[4 * i] > 0.0f);
        }
    assert_true(opaque > 10);
    vbl_film_release(film);
    vbl_scene_release(scene);
    vt_free(box.volume);
}

static void test_extremes(void** state)
{
    (void)state;
    struct {
        double scale, g;
        vbl_vec3 cam;
    } cases[] = {
        {1.0, 0.999, {0.3, -4.0, 0.5}},  {1.0, -0.999, {0.3, -4.0, 0.5}}, {1e-6, 0.3, {0.3, -4.0, 0.5}},
        {1e5, 0.3, {0.3, -4.0, 0.5}},    {2.0, 0.5, {0.1, 0.1, 0.1}},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
        rt_box a, b;
        vbl_scene* scene = mixed_scene(&a, &b, cases[k].scale, cases[k].g, cases[k].cam, 8);
        vbl_render_options o = options_for(1, 2, -1, 9);
        vbl_film* film = NULL;
        assert_int_equal(vbl_render(scene, &o, &film), VBL_SUCCESS);
        assert_true(all_finite(film));
        vbl_film_release(film);
        vbl_scene_release(scene);
        vt_free(a.volume);
        vt_free(b.volume);
    }
}

/* `test_render_pt` runs the quick group; `test_render_pt reference` the quadrature comparisons
 * (labelled slow: they run in the optimized build only). */
int main(int argc, char** argv)
{
    const struct CMUnitTest quick[] = {
        cmocka_unit_test(test_furnace_outside),
        cmocka_unit_test(test_furnace_inside),
        cmocka_unit_test(test_layers_sum_and_determinism),
        cmocka_unit_test(test_cancel_and_time_limit),
        cmocka_unit_test(test_dense_medium),
        cmocka_unit_test(test_extremes),
    };
    const struct CMUnitTest reference[] = {
        cmocka_unit_test(test_single_scatter_distant),
        cmocka_unit_test(test_single_scatter_point),
    };
    if (argc > 1 && !strcmp(argv[1], "reference")) return cmocka_run_group_tests(reference, NULL, NULL);
    return cmocka_run_group_tests(quick, NULL, NULL);
}
