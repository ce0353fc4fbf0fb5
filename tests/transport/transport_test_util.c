#include "transport_test_util.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "volume_test_grid.h"

static const char* tt_layer_names[TT_LAYERS] = {"volume_direct", "volume_from_volume"};

int tt_film_finite(const vbl_film* film)
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

void tt_replicate(const vbl_scene* scene, const vbl_estimator* est, const vbl_render_options* options, int K,
                  int block, tt_stats* out)
{
    memset(out, 0, sizeof *out);
    out->finite = 1;
    int bx = 0, by = 0;
    double sum[TT_LAYERS][TT_MAX_BLOCKS + 1], sq[TT_LAYERS][TT_MAX_BLOCKS + 1];
    memset(sum, 0, sizeof sum);
    memset(sq, 0, sizeof sq);
    for (int r = 0; r < K; ++r) {
        vbl_render_options o = *options;
        o.seed = options->seed + 7919u * (uint64_t)r;
        vbl_film* film = NULL;
        if (vbl_render_with_estimator(scene, &o, est, &film) != VBL_SUCCESS) abort();
        if (!tt_film_finite(film)) out->finite = 0;
        int w = vbl_film_width(film), h = vbl_film_height(film);
        bx = w / block;
        by = h / block;
        if (bx * by > TT_MAX_BLOCKS) abort();
        for (int l = 0; l < TT_LAYERS; ++l) {
            const float* p = vbl_film_layer_rgb(film, tt_layer_names[l]);
            double blocks[TT_MAX_BLOCKS] = {0}, img = 0.0;
            for (int y = 0; y < by * block; ++y)
                for (int x = 0; x < bx * block; ++x) {
                    double v = p ? (p[3 * (y * w + x)] + p[3 * (y * w + x) + 1] + p[3 * (y * w + x) + 2]) / 3.0 : 0.0;
                    blocks[(y / block) * bx + x / block] += v / (block * block);
                    img += v / (bx * by * block * block);
                }
            for (int b = 0; b < bx * by; ++b) {
                sum[l][b] += blocks[b];
                sq[l][b] += blocks[b] * blocks[b];
            }
            sum[l][TT_MAX_BLOCKS] += img;
            sq[l][TT_MAX_BLOCKS] += img * img;
        }
        vbl_film_release(film);
    }
    out->blocks = bx * by;
    for (int l = 0; l < TT_LAYERS; ++l)
        for (int b = 0; b <= TT_MAX_BLOCKS; ++b) {
            if (b < TT_MAX_BLOCKS && b >= out->blocks) continue;
            double m = sum[l][b] / K;
            double var = K > 1 ? fmax(0.0, (sq[l][b] - K * m * m) / (K - 1)) : 0.0;
            double se = sqrt(var / K);
            if (b == TT_MAX_BLOCKS) {
                out->image_mean[l] = m;
                out->image_se[l] = se;
            } else {
                out->mean[l][b] = m;
                out->se[l][b] = se;
            }
        }
}

static double tt_z(double ma, double sa, double mb, double sb)
{
    double s = sqrt(sa * sa + sb * sb);
    double diff = fabs(ma - mb);
    if (s > 0.0) return diff / s;
    return diff > 1e-12 * (fabs(ma) + fabs(mb)) ? INFINITY : 0.0;
}

double tt_compare(const tt_stats* a, const tt_stats* b, double scale, double* image_z, const char* tag)
{
    double zmax = 0.0;
    *image_z = 0.0;
    for (int l = 0; l < TT_LAYERS; ++l) {
        double s = l == 1 ? scale : 1.0;
        for (int k = 0; k < a->blocks; ++k) {
            double z = tt_z(a->mean[l][k], a->se[l][k], s * b->mean[l][k], s * b->se[l][k]);
            if (z > zmax) zmax = z;
        }
        double z = tt_z(a->image_mean[l], a->image_se[l], s * b->image_mean[l], s * b->image_se[l]);
        if (z > *image_z) *image_z = z;
        printf("%s %-18s image: %.5g +- %.2g vs %.5g +- %.2g (z %.2f)\n", tag, tt_layer_names[l], a->image_mean[l],
               a->image_se[l], s * b->image_mean[l], s * b->image_se[l], z);
    }
    printf("%s max block z %.2f over %d blocks x %d layers\n", tag, zmax, a->blocks, TT_LAYERS);
    return zmax;
}

vbl_scene* tt_scene(const vbl_camera* cam)
{
    vbl_scene* scene = NULL;
    if (vbl_scene_create_empty("test", cam, &scene) != VBL_SUCCESS) abort();
    return scene;
}

static void tt_add(vbl_scene* s, const vbl_light* l)
{
    if (vbl_scene_add_light(s, l) != VBL_SUCCESS) abort();
}

void tt_add_point(vbl_scene* s, vbl_vec3 p, double I)
{
    vbl_light l;
    memset(&l, 0, sizeof l);
    l.type = VBL_LIGHT_POINT;
    l.position = p;
    l.color = vbl_v3(I, 0.8 * I, 0.6 * I);
    tt_add(s, &l);
}

void tt_add_spot(vbl_scene* s, vbl_vec3 p, vbl_vec3 dir, double I, double inner_deg, double outer_deg)
{
    vbl_light l;
    memset(&l, 0, sizeof l);
    l.type = VBL_LIGHT_SPOT;
    l.position = p;
    l.direction = vbl_v3_normalize(dir);
    l.color = vbl_v3(I, I, I);
    l.cos_inner = cos(inner_deg * VBL_PI / 180.0);
    l.cos_outer = cos(outer_deg * VBL_PI / 180.0);
    tt_add(s, &l);
}

void tt_add_distant(vbl_scene* s, vbl_vec3 dir, double E)
{
    vbl_light l;
    memset(&l, 0, sizeof l);
    l.type = VBL_LIGHT_DISTANT;
    l.direction = vbl_v3_normalize(dir);
    l.color = vbl_v3(E, E, 0.7 * E);
    tt_add(s, &l);
}

typedef struct tt_sphere_param {
    int n;
} tt_sphere_param;

static double tt_sphere_voxel(int i, int j, int k, void* user)
{
    const tt_sphere_param* p = user;
    double c = 0.5 * (p->n - 1);
    double x = (i - c) / c, y = (j - c) / c, z = (k - c) / c;
    double r2 = x * x + y * y + z * z;
    if (r2 >= 1.0) return 0.0;
    return (1.0 - r2) * (1.0 - r2);
}

vbl_volume* tt_make_sphere(int n, double r)
{
    static tt_sphere_param param;
    param.n = n;
    int bmin[3] = {0, 0, 0}, bmax[3] = {n - 1, n - 1, n - 1};
    double h = 2.0 * r / (n - 1), m[3][4];
    vt_uniform_map(m, h, -r, -r, -r);
    return vt_make(bmin, bmax, tt_sphere_voxel, &param, m);
}

vbl_render_options tt_options(int passes, int spp, int light_paths, uint64_t seed)
{
    vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
    o.hybrid = VBL_HYBRID_OFF; /* the method alone (hybrid auto is the default) */
    o.passes = passes;
    o.spp = spp;
    o.light_paths = light_paths;
    o.seed = seed;
    o.threads = 2;
    o.max_bounces = -1;
    return o;
}
