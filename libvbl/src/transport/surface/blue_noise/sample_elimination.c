/* Adaptive weighted sample elimination over a balanced k-d tree of boxes
 * (sample_elimination.h; Li et al. 2022, section 3.2, eqs. 1-2). */
#include "transport/surface/blue_noise/sample_elimination.h"

#include <stdlib.h>
#include <string.h>

#include "transport/surface/blue_noise/kd_tree.h"
#include "core/error.h"
#include "transport/surface/blue_noise/stop_latch.h"

#define MAX_LEVELS 6

/* ---- r_max (eqs 1-2) ------------------------------------------------------------------------ */

static vbl_result check_options(const vbl_bn_elimination_options* o)
{
    if (o->size < sizeof(vbl_bn_elimination_options))
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "sample elimination: options.size = %zu is too small", o->size);
    if (o->neighbors < 1)
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "sample elimination: options.neighbors = %zu must be >= 1",
                         o->neighbors);
    if (!(o->weight_exponent > 0.0) || !isfinite(o->weight_exponent))
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "sample elimination: options.weight_exponent = %g must be > 0",
                         o->weight_exponent);
    if (!(o->partial >= 0.0 && o->partial <= 1.0))
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "sample elimination: options.partial = %g is outside [0, 1]",
                         o->partial);
    if (!(o->uniform_area >= 0.0) || !isfinite(o->uniform_area))
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "sample elimination: options.uniform_area = %g must be >= 0",
                         o->uniform_area);
    return VBL_SUCCESS;
}

static vbl_result check_input(const vbl_vec3* points, size_t M, size_t N)
{
    if (N < 1 || N > M)
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "sample elimination: N = %zu is outside [1, M = %zu]", N, M);
    for (size_t i = 0; i < M; ++i)
        if (!isfinite(points[i].x + points[i].y + points[i].z))
            return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "sample elimination: points[%zu] is not finite", i);
    return VBL_SUCCESS;
}

vbl_result vbl_bn_compute_rmax(const vbl_vec3* points, size_t M, size_t N, const vbl_bn_elimination_options* options,
                               double* r_max)
{
    vbl_bn_elimination_options defaults = VBL_BN_ELIMINATION_DEFAULT;
    const vbl_bn_elimination_options* o = options ? options : &defaults;
    vbl_result rc = check_options(o);
    if (rc == VBL_SUCCESS) rc = check_input(points, M, N);
    if (rc != VBL_SUCCESS) return rc;
    const double two_sqrt3 = 2.0 * sqrt(3.0);
    if (o->uniform_area > 0.0) { /* eq 1 */
        double r = sqrt(o->uniform_area / (two_sqrt3 * (double)N));
        for (size_t i = 0; i < M; ++i) r_max[i] = r;
        return VBL_SUCCESS;
    }
    if (M == 1) {
        r_max[0] = 0.0;
        return VBL_SUCCESS;
    }
    size_t m = o->neighbors < M - 1 ? o->neighbors : M - 1;
    vbl_bn_kdtree tree;
    rc = vbl_bn_kdtree_build(&tree, points, NULL, M);
    if (rc != VBL_SUCCESS) return rc;
    /* eq 2 with A_i = pi d_i^2: r_i = d_i sqrt(M pi / (2 sqrt(3) N m)) */
    const double scale = sqrt((double)M * VBL_PI / (two_sqrt3 * (double)N * (double)m));
    int failed = 0, stopped = 0;
#pragma omp parallel
    {
        size_t* idx = (size_t*)malloc(m * sizeof(size_t));
        double* d2 = (double*)malloc(m * sizeof(double));
        if (!idx || !d2) {
#pragma omp atomic write
            failed = 1;
        }
#pragma omp for schedule(dynamic, 256)
        for (long long i = 0; i < (long long)M; ++i) {
            if (!idx || !d2) continue;
            if (vbl_bn_stop_latch(&stopped, i, o->stop, o->stop_user)) continue;
            size_t found = vbl_bn_kdtree_nearest(&tree, points[i], m, (size_t)i, idx, d2);
            double d = found ? sqrt(d2[found - 1]) : 0.0;
            r_max[i] = d * scale;
        }
        free(idx);
        free(d2);
    }
    vbl_bn_kdtree_free(&tree);
    if (failed) return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "sample elimination: cannot allocate query buffers");
    if (stopped) return vbl_error(VBL_ERROR_INTERRUPTED, "sample elimination: stopped (cancel or time limit)");
    double smallest = INFINITY;
    for (size_t i = 0; i < M; ++i)
        if (r_max[i] > 0.0 && r_max[i] < smallest) smallest = r_max[i];
    for (size_t i = 0; i < M; ++i)
        if (!(r_max[i] > 0.0)) r_max[i] = isfinite(smallest) ? smallest : 0.0;
    return VBL_SUCCESS;
}

/* ---- elimination within one box -------------------------------------------------------------- */

typedef struct edge { size_t i, j; double w; } edge;

typedef struct gather_ctx {
    size_t i;
    const vbl_vec3* p;
    const double* r;
    const size_t* g;
    double beta;
    edge* edges;
    size_t count, capacity;
    int oom;
} gather_ctx;

static void gather_visit(void* ctx, size_t j, double d2)
{
    gather_ctx* c = (gather_ctx*)ctx;
    size_t i = c->i;
    if (j == i) return;
    /* each pair once, from its member with the larger radius (ties: lower global index) */
    double ri = c->r[i], rj = c->r[j];
    if (!(ri > rj || (ri == rj && c->g[i] < c->g[j]))) return;
    double d = sqrt(d2), two_rij = ri + rj; /* 2 r_ij with r_ij = (r_i + r_j) / 2 */
    if (!(d < two_rij)) return;
    double w = pow(1.0 - d / two_rij, c->beta);
    if (c->count == c->capacity) {
        size_t cap = c->capacity ? 2 * c->capacity : 1024;
        edge* e = (edge*)realloc(c->edges, cap * sizeof(edge));
        if (!e) {
            c->oom = 1;
            return;
        }
        c->edges = e;
        c->capacity = cap;
    }
    edge e = {i, j, w};
    c->edges[c->count++] = e;
}

typedef struct heap {
    size_t* h;     /* local indices */
    size_t* pos;   /* position of local index in h */
    const double* W;
    const size_t* g;
    size_t n;
} heap;

static inline int heap_above(const heap* hp, size_t a, size_t b)
{
    return hp->W[a] > hp->W[b] || (hp->W[a] == hp->W[b] && hp->g[a] < hp->g[b]);
}

static void heap_down(heap* hp, size_t k)
{
    for (;;) {
        size_t l = 2 * k + 1, r = l + 1, top = k;
        if (l < hp->n && heap_above(hp, hp->h[l], hp->h[top])) top = l;
        if (r < hp->n && heap_above(hp, hp->h[r], hp->h[top])) top = r;
        if (top == k) return;
        size_t t = hp->h[k];
        hp->h[k] = hp->h[top];
        hp->h[top] = t;
        hp->pos[hp->h[k]] = k;
        hp->pos[hp->h[top]] = top;
        k = top;
    }
}

/* o->stop said stop (asked every 1024 gathers and eliminations). */
static int box_stop(const vbl_bn_elimination_options* o, size_t step)
{
    return (step & 1023) == 1023 && o->stop && o->stop(o->stop_user);
}

/* Eliminates k of the alive members (global indices) of one box. Returns 0, -1 when out of
 * memory, 1 when o->stop said stop (alive then holds a partial elimination: the caller fails). */
static int eliminate_box(const vbl_vec3* points, const double* r_max, unsigned char* alive, const size_t* members,
                         size_t count, size_t k, const vbl_bn_elimination_options* o)
{
    const double beta = o->weight_exponent;
    if (k == 0) return 0;
    int status = -1;
    size_t n = 0;
    size_t* g = (size_t*)malloc((count ? count : 1) * sizeof(size_t));
    vbl_vec3* p = NULL;
    double *r = NULL, *W = NULL, *wgt = NULL;
    size_t *start = NULL, *nbr = NULL, *hh = NULL, *pos = NULL;
    unsigned char* removed = NULL;
    vbl_bn_kdtree tree = {0};
    gather_ctx c = {0};
    if (!g) goto done;
    for (size_t i = 0; i < count; ++i)
        if (alive[members[i]]) g[n++] = members[i];
    if (k > n) k = n;
    p = (vbl_vec3*)malloc((n ? n : 1) * sizeof(vbl_vec3));
    r = (double*)malloc((n ? n : 1) * sizeof(double));
    W = (double*)calloc(n ? n : 1, sizeof(double));
    start = (size_t*)calloc(n + 1, sizeof(size_t));
    hh = (size_t*)malloc((n ? n : 1) * sizeof(size_t));
    pos = (size_t*)malloc((n ? n : 1) * sizeof(size_t));
    removed = (unsigned char*)calloc(n ? n : 1, 1);
    if (!p || !r || !W || !start || !hh || !pos || !removed) goto done;
    for (size_t i = 0; i < n; ++i) {
        p[i] = points[g[i]];
        r[i] = r_max[g[i]];
    }
    if (vbl_bn_kdtree_build(&tree, p, NULL, n) != VBL_SUCCESS) goto done;
    c.p = p;
    c.r = r;
    c.g = g;
    c.beta = beta;
    for (size_t i = 0; i < n; ++i) {
        c.i = i;
        vbl_bn_kdtree_within(&tree, p[i], 2.0 * r[i], gather_visit, &c);
        if (c.oom) goto done;
        if (box_stop(o, i)) {
            status = 1;
            goto done;
        }
    }
    /* symmetric adjacency (CSR) in edge order: deterministic */
    for (size_t e = 0; e < c.count; ++e) {
        ++start[c.edges[e].i + 1];
        ++start[c.edges[e].j + 1];
    }
    for (size_t i = 0; i < n; ++i) start[i + 1] += start[i];
    nbr = (size_t*)malloc((c.count ? 2 * c.count : 1) * sizeof(size_t));
    wgt = (double*)malloc((c.count ? 2 * c.count : 1) * sizeof(double));
    if (!nbr || !wgt) goto done;
    {
        size_t* fill = pos; /* reused as a cursor before the heap needs it */
        for (size_t i = 0; i < n; ++i) fill[i] = start[i];
        for (size_t e = 0; e < c.count; ++e) {
            size_t a = c.edges[e].i, b = c.edges[e].j;
            nbr[fill[a]] = b;
            wgt[fill[a]++] = c.edges[e].w;
            nbr[fill[b]] = a;
            wgt[fill[b]++] = c.edges[e].w;
        }
    }
    for (size_t i = 0; i < n; ++i)
        for (size_t e = start[i]; e < start[i + 1]; ++e) W[i] += wgt[e];
    heap hp = {hh, pos, W, g, n};
    for (size_t i = 0; i < n; ++i) {
        hh[i] = i;
        pos[i] = i;
    }
    for (size_t i = n / 2; i-- > 0;) heap_down(&hp, i);
    for (size_t step = 0; step < k; ++step) {
        if (box_stop(o, step)) {
            status = 1;
            goto done;
        }
        size_t top = hh[0];
        hh[0] = hh[--hp.n];
        pos[hh[0]] = 0;
        heap_down(&hp, 0);
        removed[top] = 1;
        alive[g[top]] = 0;
        for (size_t e = start[top]; e < start[top + 1]; ++e) {
            size_t j = nbr[e];
            if (removed[j]) continue;
            W[j] -= wgt[e];
            heap_down(&hp, pos[j]);
        }
    }
    status = 0;
done:
    vbl_bn_kdtree_free(&tree);
    free(c.edges);
    free(g);
    free(p);
    free(r);
    free(W);
    free(start);
    free(nbr);
    free(wgt);
    free(hh);
    free(pos);
    free(removed);
    return status;
}

/* ---- balanced k-d tree of boxes ---------------------------------------------------------------- */

static void split_boxes(const vbl_vec3* points, size_t* order, size_t lo, size_t hi, int depth, size_t* bounds,
                        size_t* nb)
{
    if (depth == 0) {
        bounds[(*nb)++] = lo;
        return;
    }
    size_t mid = lo + (hi - lo) / 2;
    if (hi - lo > 1) {
        int axis = vbl_bn_widest_axis(points, order + lo, hi - lo);
        vbl_bn_select(points, order + lo, hi - lo, mid - lo, axis);
    }
    split_boxes(points, order, lo, mid, depth - 1, bounds, nb);
    split_boxes(points, order, mid, hi, depth - 1, bounds, nb);
}

vbl_result vbl_bn_eliminate(const vbl_vec3* points, size_t M, size_t N, const vbl_bn_elimination_options* options,
                            size_t* kept, double* kept_r_max, vbl_bn_elimination_stats* stats)
{
    return vbl_bn_eliminate_with_rmax(points, M, N, NULL, options, kept, kept_r_max, stats);
}

vbl_result vbl_bn_eliminate_with_rmax(const vbl_vec3* points, size_t M, size_t N, const double* r_given,
                                      const vbl_bn_elimination_options* options, size_t* kept, double* kept_r_max,
                                      vbl_bn_elimination_stats* stats)
{
    vbl_bn_elimination_options defaults = VBL_BN_ELIMINATION_DEFAULT;
    const vbl_bn_elimination_options* o = options ? options : &defaults;
    vbl_result rc = check_options(o);
    if (rc == VBL_SUCCESS) rc = check_input(points, M, N);
    if (rc != VBL_SUCCESS) return rc;

    int levels = 0;
    size_t leaves = 1;
    while (levels < MAX_LEVELS && o->leaf_size > 0 && M / (leaves * 8) >= o->leaf_size) {
        ++levels;
        leaves *= 8;
    }
    double* r = (double*)malloc(M * sizeof(double));
    size_t* order = (size_t*)malloc(M * sizeof(size_t));
    size_t* bounds = (size_t*)malloc((leaves + 1) * sizeof(size_t));
    unsigned char* alive = (unsigned char*)malloc(M);
    if (!r || !order || !bounds || !alive) {
        rc = vbl_error(VBL_ERROR_OUT_OF_MEMORY, "sample elimination: cannot allocate %zu samples", M);
        goto done;
    }
    if (r_given) {
        for (size_t i = 0; i < M; ++i) {
            if (!(r_given[i] >= 0.0) || !isfinite(r_given[i])) {
                rc = vbl_error(VBL_ERROR_INVALID_ARGUMENT, "sample elimination: r_max[%zu] = %g is not finite and >= 0", i,
                               r_given[i]);
                goto done;
            }
            r[i] = r_given[i];
        }
    } else {
        rc = vbl_bn_compute_rmax(points, M, N, o, r);
        if (rc != VBL_SUCCESS) goto done;
    }
    memset(alive, 1, M);
    for (size_t i = 0; i < M; ++i) order[i] = i;
    size_t nb = 0;
    split_boxes(points, order, 0, M, 3 * levels, bounds, &nb);
    bounds[leaves] = M;

    size_t before_root = 0;
    int failed = 0;
    size_t span = 1; /* leaves per box at this level */
    for (int level = 0; level < levels && !failed; ++level, span *= 8) {
        long long boxes = (long long)(leaves / span);
        size_t removed = 0;
#pragma omp parallel for schedule(dynamic, 1) reduction(+ : removed)
        for (long long b = 0; b < boxes; ++b) {
            int f;
#pragma omp atomic read
            f = failed;
            if (f) continue;
            size_t lo = bounds[(size_t)b * span], hi = bounds[((size_t)b + 1) * span];
            size_t alive_b = 0;
            for (size_t i = lo; i < hi; ++i) alive_b += alive[order[i]];
            double share = (double)N * (double)(hi - lo) / (double)M;
            double excess = (double)alive_b - share;
            size_t k = excess > 0.0 ? (size_t)floor(o->partial * excess) : 0;
            int s = eliminate_box(points, r, alive, order + lo, hi - lo, k, o);
            if (s != 0) {
#pragma omp atomic write
                failed = s; /* -1: out of memory, 1: stopped */
            } else {
                removed += k;
            }
        }
        before_root += removed;
    }
    size_t alive_n = 0;
    for (size_t i = 0; i < M && !failed; ++i) alive_n += alive[i];
    if (!failed) failed = eliminate_box(points, r, alive, order, M, alive_n - N, o);
    if (failed) {
        rc = failed > 0 ? vbl_error(VBL_ERROR_INTERRUPTED, "sample elimination: stopped (cancel or time limit)")
                        : vbl_error(VBL_ERROR_OUT_OF_MEMORY, "sample elimination: out of memory in a box");
        goto done;
    }
    size_t out = 0;
    for (size_t i = 0; i < M; ++i) {
        if (!alive[i]) continue;
        if (out < N) {
            kept[out] = i;
            if (kept_r_max) kept_r_max[out] = r[i];
        }
        ++out;
    }
    if (out != N) {
        rc = vbl_error(VBL_ERROR_INTERNAL, "sample elimination: kept %zu samples instead of N = %zu", out, N);
        goto done;
    }
    if (stats) {
        stats->levels = levels;
        stats->leaf_boxes = leaves;
        stats->eliminated_before_root = before_root;
    }
done:
    free(r);
    free(order);
    free(bounds);
    free(alive);
    return rc;
}
