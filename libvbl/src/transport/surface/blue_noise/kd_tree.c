/* Balanced 3D k-d tree (kd_tree.h): deterministic quickselect build, m-nearest and radius
 * queries by recursion over the implicit median layout. */
#include "transport/surface/blue_noise/kd_tree.h"

#include <stdint.h>
#include <stdlib.h>

#include "core/error.h"

static inline int key_less(const vbl_vec3* p, size_t a, size_t b, int axis)
{
    double ka = vbl_v3_get(p[a], axis), kb = vbl_v3_get(p[b], axis);
    return ka < kb || (ka == kb && a < b);
}

static inline void swap_size(size_t* a, size_t* b)
{
    size_t t = *a;
    *a = *b;
    *b = t;
}

void vbl_bn_select(const vbl_vec3* points, size_t* order, size_t n, size_t k, int axis)
{
    size_t lo = 0, hi = n; /* the rank-k element lies in order[lo, hi) */
    while (hi - lo > 1) {
        /* median of three as pivot, moved to hi - 1 */
        size_t mid = lo + (hi - lo) / 2, last = hi - 1;
        if (key_less(points, order[mid], order[lo], axis)) swap_size(&order[mid], &order[lo]);
        if (key_less(points, order[last], order[lo], axis)) swap_size(&order[last], &order[lo]);
        if (key_less(points, order[mid], order[last], axis)) swap_size(&order[mid], &order[last]);
        size_t pivot = order[last], store = lo;
        for (size_t i = lo; i < last; ++i)
            if (key_less(points, order[i], pivot, axis)) swap_size(&order[i], &order[store++]);
        swap_size(&order[store], &order[last]);
        if (store == k) return;
        if (k < store) hi = store;
        else lo = store + 1;
    }
}

int vbl_bn_widest_axis(const vbl_vec3* points, const size_t* order, size_t n)
{
    if (n == 0) return 0;
    vbl_vec3 lo = points[order[0]], hi = lo;
    for (size_t i = 1; i < n; ++i) {
        vbl_vec3 p = points[order[i]];
        lo = vbl_v3(fmin(lo.x, p.x), fmin(lo.y, p.y), fmin(lo.z, p.z));
        hi = vbl_v3(fmax(hi.x, p.x), fmax(hi.y, p.y), fmax(hi.z, p.z));
    }
    vbl_vec3 e = vbl_v3_sub(hi, lo);
    return (e.x >= e.y && e.x >= e.z) ? 0 : (e.y >= e.z ? 1 : 2);
}

static void build_range(vbl_bn_kdtree* t, size_t lo, size_t hi)
{
    while (hi - lo > 1) {
        int axis = vbl_bn_widest_axis(t->points, t->order + lo, hi - lo);
        size_t mid = lo + (hi - lo) / 2;
        vbl_bn_select(t->points, t->order + lo, hi - lo, mid - lo, axis);
        t->axis[mid] = (unsigned char)axis;
        build_range(t, lo, mid);
        lo = mid + 1; /* right child iteratively */
    }
}

vbl_result vbl_bn_kdtree_build(vbl_bn_kdtree* tree, const vbl_vec3* points, const size_t* subset, size_t count)
{
    tree->points = points;
    tree->count = count;
    tree->subtree_radius = NULL;
    tree->order = (size_t*)malloc((count ? count : 1) * sizeof(size_t));
    tree->axis = (unsigned char*)calloc(count ? count : 1, 1);
    if (!tree->order || !tree->axis) {
        vbl_bn_kdtree_free(tree);
        return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "blue noise k-d tree: cannot allocate %zu points", count);
    }
    for (size_t i = 0; i < count; ++i) tree->order[i] = subset ? subset[i] : i;
    build_range(tree, 0, count);
    return VBL_SUCCESS;
}

void vbl_bn_kdtree_free(vbl_bn_kdtree* tree)
{
    free(tree->order);
    free(tree->axis);
    free(tree->subtree_radius);
    tree->order = NULL;
    tree->axis = NULL;
    tree->subtree_radius = NULL;
    tree->count = 0;
}

/* ---- m nearest: a bounded max-heap keyed by (d2, index) ------------------------------------ */

typedef struct knn_state {
    const vbl_bn_kdtree* t;
    vbl_vec3 q;
    size_t m, exclude, n;
    size_t* idx;
    double* d2;
} knn_state;

static inline int entry_greater(double da, size_t ia, double db, size_t ib)
{
    return da > db || (da == db && ia > ib);
}

static void heap_sift_down(size_t* idx, double* d2, size_t n, size_t i)
{
    for (;;) {
        size_t l = 2 * i + 1, r = l + 1, big = i;
        if (l < n && entry_greater(d2[l], idx[l], d2[big], idx[big])) big = l;
        if (r < n && entry_greater(d2[r], idx[r], d2[big], idx[big])) big = r;
        if (big == i) return;
        double td = d2[i];
        d2[i] = d2[big];
        d2[big] = td;
        swap_size(&idx[i], &idx[big]);
        i = big;
    }
}

static void knn_offer(knn_state* s, size_t index, double d2)
{
    if (index == s->exclude) return;
    if (s->n < s->m) {
        size_t i = s->n++;
        s->idx[i] = index;
        s->d2[i] = d2;
        while (i > 0) { /* sift up */
            size_t p = (i - 1) / 2;
            if (!entry_greater(s->d2[i], s->idx[i], s->d2[p], s->idx[p])) break;
            double td = s->d2[i];
            s->d2[i] = s->d2[p];
            s->d2[p] = td;
            swap_size(&s->idx[i], &s->idx[p]);
            i = p;
        }
    } else if (entry_greater(s->d2[0], s->idx[0], d2, index)) {
        s->idx[0] = index;
        s->d2[0] = d2;
        heap_sift_down(s->idx, s->d2, s->n, 0);
    }
}

/* Arya-Mount incremental distance: off[a] is the offset from q to the cell along axis a, rd the
 * squared distance from q to the cell (sum of off^2); far cells farther than the current m-th
 * neighbour are skipped. */
static void knn_range(knn_state* s, size_t lo, size_t hi, double off[3], double rd)
{
    while (hi > lo) {
        size_t mid = lo + (hi - lo) / 2, pi = s->t->order[mid];
        vbl_vec3 d = vbl_v3_sub(s->q, s->t->points[pi]);
        knn_offer(s, pi, vbl_v3_dot(d, d));
        if (hi - lo == 1) return;
        int axis = s->t->axis[mid];
        double diff = vbl_v3_get(d, axis);
        size_t near_lo = diff < 0.0 ? lo : mid + 1, near_hi = diff < 0.0 ? mid : hi;
        size_t far_lo = diff < 0.0 ? mid + 1 : lo, far_hi = diff < 0.0 ? hi : mid;
        knn_range(s, near_lo, near_hi, off, rd);
        double old = off[axis], far_rd = rd - old * old + diff * diff;
        if (s->n == s->m && far_rd > s->d2[0]) return;
        off[axis] = diff;
        knn_range(s, far_lo, far_hi, off, far_rd);
        off[axis] = old;
        return;
    }
}

size_t vbl_bn_kdtree_nearest(const vbl_bn_kdtree* tree, vbl_vec3 q, size_t m, size_t exclude, size_t* idx,
                             double* d2)
{
    if (m == 0 || tree->count == 0) return 0;
    double* dist = d2;
    double* tmp = NULL;
    if (!dist) {
        tmp = (double*)malloc(m * sizeof(double));
        if (!tmp) return 0;
        dist = tmp;
    }
    knn_state s = {tree, q, m, exclude, 0, idx, dist};
    double off[3] = {0.0, 0.0, 0.0};
    knn_range(&s, 0, tree->count, off, 0.0);
    /* heap sort ascending */
    for (size_t n = s.n; n > 1; --n) {
        double td = dist[0];
        dist[0] = dist[n - 1];
        dist[n - 1] = td;
        swap_size(&idx[0], &idx[n - 1]);
        heap_sift_down(idx, dist, n - 1, 0);
    }
    free(tmp);
    return s.n;
}

/* ---- radius query --------------------------------------------------------------------------- */

typedef struct within_state {
    const vbl_bn_kdtree* t;
    vbl_vec3 q;
    double r2;
    vbl_bn_kdtree_visit_fn visit;
    void* ctx;
} within_state;

/* Squared pruning radius of the subtree over [lo, hi): the query's, or less with per-point radii. */
static double subtree_r2(const within_state* s, size_t lo, size_t hi)
{
    if (!s->t->subtree_radius || hi <= lo) return s->r2;
    double r = s->t->subtree_radius[lo + (hi - lo) / 2] * (1.0 + 1e-9);
    return r * r < s->r2 ? r * r : s->r2;
}

static void within_range(within_state* s, size_t lo, size_t hi)
{
    while (hi > lo) {
        size_t mid = lo + (hi - lo) / 2, pi = s->t->order[mid];
        vbl_vec3 d = vbl_v3_sub(s->q, s->t->points[pi]);
        double dd = vbl_v3_dot(d, d);
        if (dd < s->r2) s->visit(s->ctx, pi, dd);
        if (hi - lo == 1) return;
        double diff = vbl_v3_get(d, s->t->axis[mid]);
        /* left child: keys <= split; right: keys >= split; |diff| bounds the distance to the far side */
        if (diff < 0.0 || diff * diff < subtree_r2(s, lo, mid)) within_range(s, lo, mid);
        if (diff >= 0.0 || diff * diff < subtree_r2(s, mid + 1, hi)) {
            lo = mid + 1;
            continue;
        }
        return;
    }
}

static double set_radii_range(vbl_bn_kdtree* t, const double* radii, size_t lo, size_t hi)
{
    if (hi <= lo) return 0.0;
    size_t mid = lo + (hi - lo) / 2;
    double r = radii[t->order[mid]];
    double a = set_radii_range(t, radii, lo, mid), b = set_radii_range(t, radii, mid + 1, hi);
    if (a > r) r = a;
    if (b > r) r = b;
    t->subtree_radius[mid] = r;
    return r;
}

vbl_result vbl_bn_kdtree_set_radii(vbl_bn_kdtree* tree, const double* radii)
{
    free(tree->subtree_radius);
    tree->subtree_radius = (double*)malloc((tree->count ? tree->count : 1) * sizeof(double));
    if (!tree->subtree_radius)
        return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "blue noise k-d tree: cannot allocate %zu radii", tree->count);
    set_radii_range(tree, radii, 0, tree->count);
    return VBL_SUCCESS;
}

void vbl_bn_kdtree_within(const vbl_bn_kdtree* tree, vbl_vec3 q, double radius, vbl_bn_kdtree_visit_fn visit,
                          void* ctx)
{
    if (tree->count == 0 || !(radius > 0.0)) return;
    within_state s = {tree, q, radius * radius, visit, ctx};
    within_range(&s, 0, tree->count);
}
