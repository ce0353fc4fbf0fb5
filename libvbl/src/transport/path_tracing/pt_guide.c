/* The radiance cache and the decision of pt's adjoint-driven Russian roulette and splitting
 * (pt_guide.h; Vorba and Krivanek 2016, sec. 4-5). */
#include "transport/path_tracing/pt_guide.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "sampling/sphere.h"
#include "volume/volume.h"
#include "transport/path_tracing/pt.h"

/* Weight window of width s = 5 around the centre r = 1 (Vorba and Krivanek 2016, sec. 5.1). */
#define VBL_PT_GUIDE_S 5.0
#define VBL_PT_GUIDE_MIN_SURVIVAL 0.05

static double vbl_luminance(vbl_vec3 c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }

static vbl_vec3 vbl_sample_sum(const vbl_sample_value* v)
{
    vbl_vec3 s = vbl_v3(0.0, 0.0, 0.0);
    for (int c = 0; c < VBL_CLASS_COUNT; ++c) s = vbl_v3_add(s, v->L[c]);
    return s;
}

/* One unguided pt path from (origin, direction) with pre-pass stream (item, k): all classes summed. */
static vbl_vec3 vbl_pt_guide_trace(const vbl_render_context* pre, vbl_thread_state* ts, vbl_vec3 origin,
                                   vbl_vec3 direction, uint64_t item, int k, vbl_rng* rng)
{
    vbl_camera_sample cs;
    memset(&cs, 0, sizeof cs);
    cs.pixel_index = item;
    cs.sample_index = (uint32_t)k;
    cs.origin = origin;
    cs.direction = direction;
    cs.t_max = INFINITY;
    vbl_sample_value v;
    memset(&v, 0, sizeof v);
    vbl_pt_camera_sample(pre, NULL, ts, &cs, rng, &v);
    vbl_vec3 s = vbl_sample_sum(&v);
    /* a pre-pass estimate is finite by construction; a non-finite one would poison a cell */
    if (!(isfinite(s.x) && isfinite(s.y) && isfinite(s.z))) return vbl_v3(0.0, 0.0, 0.0);
    return s;
}

vbl_result vbl_pt_guide_build(const vbl_render_context* ctx, vbl_pt_guide** out)
{
    *out = NULL;
    const vbl_scene* scene = ctx->scene;
    vbl_pt_guide* g = calloc(1, sizeof *g);
    if (!g) return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory for pt.guided_rr's cache", scene->path);
    const int n = ctx->options.pt.guide_cells, paths = ctx->options.pt.guide_paths;
    g->cells = 0;
    vbl_vec3 lo, hi;
    if (ctx->extinction->count > 0 && vbl_scene_media_box(scene, &lo, &hi)) {
        g->cells = n;
        g->lo = lo;
        g->hi = hi;
        vbl_vec3 d = vbl_v3_sub(hi, lo);
        g->inv_cell = vbl_v3(d.x > 0.0 ? n / d.x : 0.0, d.y > 0.0 ? n / d.y : 0.0, d.z > 0.0 ? n / d.z : 0.0);
    }
    const size_t cell_count = (size_t)g->cells * (size_t)g->cells * (size_t)g->cells;
    const vbl_camera* cam = &scene->camera;
    g->blocks_x = (cam->width + VBL_PT_GUIDE_BLOCK - 1) / VBL_PT_GUIDE_BLOCK;
    g->blocks_y = (cam->height + VBL_PT_GUIDE_BLOCK - 1) / VBL_PT_GUIDE_BLOCK;
    const size_t block_count = (size_t)g->blocks_x * (size_t)g->blocks_y;
    g->radiance = calloc(cell_count ? cell_count * 3 : 1, sizeof *g->radiance);
    g->pixel = calloc(block_count ? block_count : 1, sizeof *g->pixel);
    if (!g->radiance || !g->pixel) {
        vbl_pt_guide_free(g);
        return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory for pt.guided_rr's %d^3 cache", scene->path, n);
    }
    /* the pre-pass: unguided, independent streams (the Sobol pattern belongs to the render) */
    vbl_render_context pre = *ctx;
    pre.pt_guide = NULL;
    pre.options.pt.sampler = VBL_PT_SAMPLER_INDEPENDENT;
    pre.deadline = 0.0;
    const uint64_t seed = ctx->options.seed ^ VBL_RNG_DOMAIN_GUIDE;
    const long long items = (long long)(cell_count + block_count);
#pragma omp parallel num_threads(ctx->threads)
    {
        vbl_thread_state ts;
        memset(&ts, 0, sizeof ts);
        vbl_extinction_cursor_init(&ts.cursor, ctx->extinction);
        if (scene->has_emission) vbl_emission_cursor_init(&ts.emission, scene);
#pragma omp for schedule(dynamic, 8)
        for (long long item = 0; item < items; ++item) {
            vbl_vec3 sum = vbl_v3(0.0, 0.0, 0.0);
            if ((size_t)item < cell_count) { /* a cell: uniform points, uniform directions */
                const size_t c = (size_t)item;
                const int ix = (int)(c % (size_t)g->cells), iy = (int)(c / (size_t)g->cells % (size_t)g->cells),
                          iz = (int)(c / ((size_t)g->cells * (size_t)g->cells));
                for (int k = 0; k < paths; ++k) {
                    vbl_rng rng = vbl_rng_make(seed, (uint64_t)item, (uint64_t)k);
                    double u[5];
                    for (int j = 0; j < 5; ++j) u[j] = vbl_rng_uniform(&rng);
                    vbl_vec3 x = vbl_v3(g->lo.x + (g->hi.x - g->lo.x) * (ix + u[0]) / g->cells,
                                        g->lo.y + (g->hi.y - g->lo.y) * (iy + u[1]) / g->cells,
                                        g->lo.z + (g->hi.z - g->lo.z) * (iz + u[2]) / g->cells);
                    vbl_vec3 w = vbl_sample_uniform_sphere(u[3], u[4], NULL);
                    sum = vbl_v3_add(sum, vbl_pt_guide_trace(&pre, &ts, x, w, (uint64_t)item, k, &rng));
                }
                sum = vbl_v3_scale(sum, 1.0 / paths);
                g->radiance[3 * c] = (float)sum.x;
                g->radiance[3 * c + 1] = (float)sum.y;
                g->radiance[3 * c + 2] = (float)sum.z;
            } else { /* a pixel block: camera paths through uniform points of the block */
                const size_t b = (size_t)item - cell_count;
                const int bx = (int)(b % (size_t)g->blocks_x), by = (int)(b / (size_t)g->blocks_x);
                const double x0 = bx * VBL_PT_GUIDE_BLOCK, y0 = by * VBL_PT_GUIDE_BLOCK;
                const double wx = fmin(VBL_PT_GUIDE_BLOCK, cam->width - x0), wy = fmin(VBL_PT_GUIDE_BLOCK, cam->height - y0);
                for (int k = 0; k < 2 * paths; ++k) {
                    vbl_rng rng = vbl_rng_make(seed, (uint64_t)item, (uint64_t)k);
                    double sx = x0 + wx * vbl_rng_uniform(&rng), sy = y0 + wy * vbl_rng_uniform(&rng);
                    vbl_vec3 o, d;
                    vbl_camera_ray(cam, sx, sy, &o, &d);
                    sum = vbl_v3_add(sum, vbl_pt_guide_trace(&pre, &ts, o, d, (uint64_t)item, k, &rng));
                }
                g->pixel[b] = vbl_luminance(sum) / (2.0 * paths);
            }
        }
    }
    g->prepass_paths = (uint64_t)cell_count * (uint64_t)paths + (uint64_t)block_count * 2u * (uint64_t)paths;
    *out = g;
    return VBL_SUCCESS;
}

void vbl_pt_guide_free(vbl_pt_guide* guide)
{
    if (!guide) return;
    free(guide->radiance);
    free(guide->pixel);
    free(guide);
}

static int vbl_pt_guide_axis(double x, double lo, double inv_cell, int n)
{
    double f = (x - lo) * inv_cell;
    if (!(f >= 0.0) || !(f <= n)) return -1;
    int i = (int)f;
    return i >= n ? n - 1 : i;
}

vbl_vec3 vbl_pt_guide_radiance(const vbl_pt_guide* g, vbl_vec3 x)
{
    const int n = g->cells;
    if (n <= 0) return vbl_v3(0.0, 0.0, 0.0);
    int ix = vbl_pt_guide_axis(x.x, g->lo.x, g->inv_cell.x, n), iy = vbl_pt_guide_axis(x.y, g->lo.y, g->inv_cell.y, n),
        iz = vbl_pt_guide_axis(x.z, g->lo.z, g->inv_cell.z, n);
    if (ix < 0 || iy < 0 || iz < 0) return vbl_v3(0.0, 0.0, 0.0);
    const float* r = &g->radiance[3 * (((size_t)iz * n + iy) * n + ix)];
    return vbl_v3(r[0], r[1], r[2]);
}

double vbl_pt_guide_pixel(const vbl_pt_guide* g, int px, int py)
{
    int bx = px / VBL_PT_GUIDE_BLOCK, by = py / VBL_PT_GUIDE_BLOCK;
    if (px < 0 || py < 0 || bx >= g->blocks_x || by >= g->blocks_y) return 0.0;
    return g->pixel[(size_t)by * g->blocks_x + bx];
}

int vbl_pt_guide_decide(const vbl_pt_guide* g, vbl_vec3 x, int px, int py, int max_copies, vbl_rng* rng,
                        vbl_vec3* beta)
{
    const double I = vbl_pt_guide_pixel(g, px, py);
    if (!(I > 0.0)) return -1;
    const vbl_vec3 L = vbl_pt_guide_radiance(g, x);
    const double r = vbl_luminance(vbl_v3_mul(*beta, L)) / I; /* expected contribution / pixel */
    if (!(r > 0.0) || !isfinite(r)) return -1;
    const double lower = 2.0 / (1.0 + VBL_PT_GUIDE_S), upper = VBL_PT_GUIDE_S * lower;
    if (r < lower) { /* roulette to the window's centre */
        const double q = fmax(r, VBL_PT_GUIDE_MIN_SURVIVAL);
        if (vbl_rng_uniform(rng) >= q) return 0;
        *beta = vbl_v3_scale(*beta, 1.0 / q);
        return 1;
    }
    if (r > upper && max_copies > 1) { /* split to the window's centre */
        int n = (int)fmin(floor(r + 0.5), (double)max_copies);
        if (n > VBL_PT_GUIDE_MAX_SPLIT) n = VBL_PT_GUIDE_MAX_SPLIT;
        if (n < 2) return 1;
        *beta = vbl_v3_scale(*beta, 1.0 / n);
        return n;
    }
    return 1;
}
