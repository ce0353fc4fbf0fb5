/* The transmittance grid towards a distant light (sun_grid.h): one sweep from the light's side. */
#include "volume/sun_grid.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

static double vbl_v3_at(vbl_vec3 v, int a) { return a == 0 ? v.x : (a == 1 ? v.y : v.z); }

static double vbl_affine_det(const vbl_affine* m)
{
    const double(*a)[4] = m->m;
    return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
           a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
}

/* The media's finest voxel edge in scene units (the cube root of a voxel's scene volume);
 * INFINITY without components. */
static double vbl_sun_grid_voxel(const vbl_extinction* ext)
{
    double best = INFINITY;
    for (int c = 0; c < ext->count; ++c) {
        const vbl_medium_component* m = &ext->components[c];
        const double det = fabs(vbl_affine_det(&m->volume->world_to_index) * vbl_affine_det(&m->scene_to_volume));
        if (det > 0.0 && isfinite(det)) {
            const double v = cbrt(1.0 / det);
            if (v < best) best = v;
        }
    }
    return best;
}

static size_t vbl_sun_grid_index(const vbl_sun_grid* g, const int idx[3])
{
    return ((size_t)idx[0] * (size_t)g->n[1] + (size_t)idx[1]) * (size_t)g->n[2] + (size_t)idx[2];
}

vbl_result vbl_sun_grid_build(vbl_sun_grid* g, const vbl_extinction* ext, vbl_vec3 lo, vbl_vec3 hi, vbl_vec3 w,
                              size_t max_nodes, int threads, vbl_sun_grid_occluded_fn occluded, void* user)
{
    memset(g, 0, sizeof *g);
    const double e[3] = {hi.x - lo.x, hi.y - lo.y, hi.z - lo.z};
    if (!(e[0] > 0.0 && e[1] > 0.0 && e[2] > 0.0) || !isfinite(e[0] * e[1] * e[2]))
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_sun_grid_build: empty or unbounded box");
    if (!(fabs(vbl_v3_dot(w, w) - 1.0) < 1e-6))
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_sun_grid_build: the direction is not a unit vector");
    if (max_nodes < 8) max_nodes = 8;
    const double voxel = vbl_sun_grid_voxel(ext);
    double h = cbrt(e[0] * e[1] * e[2] / (double)max_nodes);
    if (h < voxel) h = voxel; /* no finer than the data */
    for (;;) {                /* the +1 of the corners may overshoot max_nodes: widen until it fits */
        double nodes = 1.0;
        for (int a = 0; a < 3; ++a) {
            const double n = ceil(e[a] / h) + 1.0;
            g->n[a] = n < 2.0 ? 2 : (n > 1e6 ? 1000000 : (int)n);
            nodes *= g->n[a];
        }
        if (nodes <= (double)max_nodes || nodes <= 8.0) break;
        h *= 1.02;
    }
    for (int a = 0; a < 3; ++a) {
        g->h[a] = e[a] / (g->n[a] - 1);
        g->inv_h[a] = 1.0 / g->h[a];
    }
    g->lo = lo;
    g->hi = hi;
    g->w = w;
    const size_t count = (size_t)g->n[0] * (size_t)g->n[1] * (size_t)g->n[2];
    g->T = malloc(count * sizeof *g->T);
    if (!g->T) return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "out of memory for a %zu-node sun transmittance grid", count);

    /* sweep along the axis w leans on most, from the box face the light enters by (T = 1 there:
     * no media beyond the box); each node's upstream point x + s w lies on the previous slice */
    int a = 0;
    for (int k = 1; k < 3; ++k)
        if (fabs(vbl_v3_at(w, k)) > fabs(vbl_v3_at(w, a))) a = k;
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    const int dir = vbl_v3_at(w, a) > 0.0 ? 1 : -1;
    const int first = dir > 0 ? g->n[a] - 1 : 0;
    const double s = g->h[a] / fabs(vbl_v3_at(w, a));
    int m = isfinite(voxel) ? (int)ceil(s / voxel) : 1; /* midpoint-rule points per segment: ~1 per voxel */
    if (m < 1) m = 1;
    if (m > 64) m = 64;
    const double wb = vbl_v3_at(w, b) * s / g->h[b], wc = vbl_v3_at(w, c) * s / g->h[c]; /* upstream offset, nodes */
    for (int step = 0; step < g->n[a]; ++step) { /* step 0: the entry face, T = 1 (0 if blocked) */
        const int ia = first - dir * step, iu = ia + dir;
#pragma omp parallel num_threads(threads > 0 ? threads : 1)
        {
            vbl_extinction_cursor cursor;
            vbl_extinction_cursor_init(&cursor, ext);
#pragma omp for schedule(static)
            for (int ib = 0; ib < g->n[b]; ++ib)
                for (int ic = 0; ic < g->n[c]; ++ic) {
                    int idx[3];
                    idx[a] = ia;
                    idx[b] = ib;
                    idx[c] = ic;
                    const vbl_vec3 x = vbl_v3(lo.x + idx[0] * g->h[0], lo.y + idx[1] * g->h[1], lo.z + idx[2] * g->h[2]);
                    float* node = &g->T[vbl_sun_grid_index(g, idx)];
                    if (occluded && occluded(user, x, w)) {
                        *node = 0.0f;
                        continue;
                    }
                    if (step == 0) {
                        *node = 1.0f;
                        continue;
                    }
                    double tau = 0.0;
                    for (int q = 0; q < m; ++q)
                        tau += vbl_extinction_eval(ext, &cursor, vbl_v3_madd(x, w, (q + 0.5) * s / m), NULL);
                    tau *= s / m;
                    /* T at the upstream point, bilinear on slice iu; beyond the box's side faces 1 */
                    const double fb = ib + wb, fc = ic + wc;
                    double up = 1.0;
                    if (fb >= 0.0 && fb <= g->n[b] - 1 && fc >= 0.0 && fc <= g->n[c] - 1) {
                        int jb = (int)fb, jc = (int)fc;
                        if (jb > g->n[b] - 2) jb = g->n[b] - 2;
                        if (jc > g->n[c] - 2) jc = g->n[c] - 2;
                        const double ub = fb - jb, uc = fc - jc;
                        int u[3];
                        u[a] = iu;
                        double v[2][2];
                        for (int db = 0; db < 2; ++db)
                            for (int dc = 0; dc < 2; ++dc) {
                                u[b] = jb + db;
                                u[c] = jc + dc;
                                v[db][dc] = g->T[vbl_sun_grid_index(g, u)];
                            }
                        up = (1.0 - ub) * ((1.0 - uc) * v[0][0] + uc * v[0][1]) + ub * ((1.0 - uc) * v[1][0] + uc * v[1][1]);
                    }
                    *node = (float)(up * exp(-tau));
                }
        }
    }
    return VBL_SUCCESS;
}

/* Trilinear at fractional node coordinates f (clamped into the grid). */
static double vbl_sun_grid_trilinear(const vbl_sun_grid* g, const double f_in[3])
{
    int i[3];
    double u[3];
    for (int a = 0; a < 3; ++a) {
        double f = f_in[a];
        if (!(f > 0.0)) f = 0.0;
        if (f > g->n[a] - 1) f = g->n[a] - 1;
        i[a] = (int)f;
        if (i[a] > g->n[a] - 2) i[a] = g->n[a] - 2;
        u[a] = f - i[a];
    }
    const size_t s1 = (size_t)g->n[2], s0 = (size_t)g->n[1] * s1;
    const float* T = g->T + (size_t)i[0] * s0 + (size_t)i[1] * s1 + (size_t)i[2];
    const double x00 = T[0] + u[2] * (T[1] - T[0]), x01 = T[s1] + u[2] * (T[s1 + 1] - T[s1]);
    const double x10 = T[s0] + u[2] * (T[s0 + 1] - T[s0]), x11 = T[s0 + s1] + u[2] * (T[s0 + s1 + 1] - T[s0 + s1]);
    const double y0 = x00 + u[1] * (x01 - x00), y1 = x10 + u[1] * (x11 - x10);
    return y0 + u[0] * (y1 - y0);
}

double vbl_sun_grid_eval(const vbl_sun_grid* g, vbl_vec3 x)
{
    if (!g->T) return 1.0;
    if (x.x >= g->lo.x && x.x <= g->hi.x && x.y >= g->lo.y && x.y <= g->hi.y && x.z >= g->lo.z && x.z <= g->hi.z) {
        const double f[3] = {(x.x - g->lo.x) * g->inv_h[0], (x.y - g->lo.y) * g->inv_h[1], (x.z - g->lo.z) * g->inv_h[2]};
        return vbl_sun_grid_trilinear(g, f); /* inside: most calls (the camera walk's candidates) */
    }
    const double p[3] = {x.x, x.y, x.z}, d[3] = {g->w.x, g->w.y, g->w.z};
    const double lo[3] = {g->lo.x, g->lo.y, g->lo.z}, hi[3] = {g->hi.x, g->hi.y, g->hi.z};
    double t0 = 0.0, t1 = INFINITY;
    for (int a = 0; a < 3; ++a) { /* the ray x + t w against the box's slabs (t >= 0) */
        if (!isfinite(p[a])) return 1.0;
        if (d[a] == 0.0) {
            if (p[a] < lo[a] || p[a] > hi[a]) return 1.0;
            continue;
        }
        double ta = (lo[a] - p[a]) / d[a], tb = (hi[a] - p[a]) / d[a];
        if (ta > tb) {
            const double tmp = ta;
            ta = tb;
            tb = tmp;
        }
        if (ta > t0) t0 = ta;
        if (tb < t1) t1 = tb;
    }
    if (!(t0 <= t1)) return 1.0; /* the ray misses the box */
    double f[3];
    for (int a = 0; a < 3; ++a) f[a] = (p[a] + t0 * d[a] - lo[a]) * g->inv_h[a];
    return vbl_sun_grid_trilinear(g, f);
}

void vbl_sun_grid_free(vbl_sun_grid* g)
{
    if (!g) return;
    free(g->T);
    g->T = NULL;
}
