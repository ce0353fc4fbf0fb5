/* BVH over beams for camera-ray queries, Jarosz et al. 2011a, section 8.3. */
#include "transport/photon_beams/beam_bvh.h"

#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "core/work_count.h"

#define BVH_BINS 16
#define BVH_MAX_DEPTH 48

/* ---- geometry ---- */

static double point_segment_distance2(vbl_vec3 p, vbl_vec3 a, vbl_vec3 d, double len)
{
    double t = vbl_clamp(vbl_v3_dot(vbl_v3_sub(p, a), d), 0.0, len);
    vbl_vec3 q = vbl_v3_sub(p, vbl_v3_madd(a, d, t));
    return vbl_v3_dot(q, q);
}

double vbl_segment_distance2(vbl_vec3 p0, vbl_vec3 d0, double len0, vbl_vec3 p1, vbl_vec3 d1, double len1)
{
    len0 = fmax(len0, 0.0);
    len1 = fmax(len1, 0.0);
    /* The minimum of |p0 + s d0 - p1 - t d1|^2 over the rectangle lies at the interior critical
     * point (lines' closest points) or on the rectangle's boundary, i.e. at an endpoint of one
     * segment against the other segment. */
    vbl_vec3 e0 = vbl_v3_madd(p0, d0, len0), e1 = vbl_v3_madd(p1, d1, len1);
    double best = point_segment_distance2(p0, p1, d1, len1);
    best = fmin(best, point_segment_distance2(e0, p1, d1, len1));
    best = fmin(best, point_segment_distance2(p1, p0, d0, len0));
    best = fmin(best, point_segment_distance2(e1, p0, d0, len0));
    vbl_vec3 r = vbl_v3_sub(p0, p1);
    double b = vbl_v3_dot(d0, d1), c = vbl_v3_dot(d0, r), f = vbl_v3_dot(d1, r);
    vbl_vec3 x = vbl_v3_cross(d0, d1);
    double denom = vbl_v3_dot(x, x); /* 1 - b^2 without cancellation */
    if (denom > 1e-24) {
        double s = (b * f - c) / denom, t = (f - b * c) / denom;
        if (s > 0.0 && s < len0 && t > 0.0 && t < len1) {
            double dn = vbl_v3_dot(r, x);
            best = fmin(best, dn * dn / denom); /* line-line distance^2 */
        }
    }
    return best;
}

/* ---- build ---- */

typedef struct box { double lo[3], hi[3]; } box;

static void box_empty(box* b)
{
    for (int k = 0; k < 3; ++k) {
        b->lo[k] = INFINITY;
        b->hi[k] = -INFINITY;
    }
}
static void box_grow(box* b, const box* o)
{
    for (int k = 0; k < 3; ++k) {
        b->lo[k] = fmin(b->lo[k], o->lo[k]);
        b->hi[k] = fmax(b->hi[k], o->hi[k]);
    }
}
static double box_area(const box* b)
{
    double e[3];
    for (int k = 0; k < 3; ++k) e[k] = b->hi[k] > b->lo[k] ? b->hi[k] - b->lo[k] : 0.0;
    return e[0] * e[1] + e[1] * e[2] + e[2] * e[0];
}

typedef struct piece_info { box bounds; double centroid[3]; } piece_info;

static void piece_bounds(const vbl_beam* bm, const vbl_beam_piece* pc, piece_info* out)
{
    vbl_vec3 a = vbl_v3_madd(bm->origin, bm->direction, pc->t0);
    vbl_vec3 b = vbl_v3_madd(bm->origin, bm->direction, pc->t1);
    double pa[3] = {a.x, a.y, a.z}, pb[3] = {b.x, b.y, b.z};
    for (int k = 0; k < 3; ++k) {
        /* Conservative padding for rounding in the piece endpoints and the query's slab test. */
        double pad = bm->radius + 1e-9 * (fabs(pa[k]) + fabs(pb[k]) + bm->radius + bm->length) + 1e-300;
        out->bounds.lo[k] = fmin(pa[k], pb[k]) - pad;
        out->bounds.hi[k] = fmax(pa[k], pb[k]) + pad;
        out->centroid[k] = 0.5 * (pa[k] + pb[k]);
    }
}

typedef struct task { size_t start, end; size_t patch; int depth; } task;

static int beam_ok(const vbl_beam* b)
{
    return isfinite(b->origin.x) && isfinite(b->origin.y) && isfinite(b->origin.z) && isfinite(b->direction.x) &&
           isfinite(b->direction.y) && isfinite(b->direction.z) && isfinite(b->length) && isfinite(b->radius) &&
           b->length >= 0.0 && b->radius >= 0.0;
}

void vbl_beam_bvh_free(vbl_beam_bvh* bvh)
{
    free(bvh->pieces);
    free(bvh->nodes);
    memset(bvh, 0, sizeof *bvh);
}

vbl_result vbl_beam_bvh_build(vbl_beam_bvh* bvh, const vbl_beam* beams, size_t count, const vbl_beam_bvh_options* options)
{
    memset(bvh, 0, sizeof *bvh);
    double aspect = options && options->split_aspect > 0.0 ? options->split_aspect : 1.0;
    size_t leaf_size = options && options->leaf_size > 0 ? (size_t)options->leaf_size : 4;
    int max_pieces = options && options->max_pieces > 0 && options->max_pieces <= VBL_BEAM_BVH_MAX_PIECES
                         ? options->max_pieces
                         : VBL_BEAM_BVH_MAX_PIECES;
    if (count > UINT32_MAX / VBL_BEAM_BVH_MAX_PIECES)
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "beam_bvh: %zu beams exceed the index range", count);
    size_t total = 0;
    for (size_t i = 0; i < count; ++i) {
        if (!beam_ok(&beams[i]))
            return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "beam_bvh: beam %zu has a non-finite or negative length/radius",
                             i);
        double diameter = 2.0 * beams[i].radius;
        double n = diameter > 0.0 ? ceil(beams[i].length / (aspect * diameter)) : 1.0;
        total += (size_t)vbl_clamp(n, 1.0, (double)max_pieces);
    }
    bvh->beams = beams;
    bvh->beam_count = count;
    if (total == 0) return VBL_SUCCESS;
    bvh->pieces = (vbl_beam_piece*)malloc(total * sizeof *bvh->pieces);
    bvh->nodes = (vbl_beam_bvh_node*)malloc((2 * total) * sizeof *bvh->nodes);
    piece_info* info = (piece_info*)malloc(total * sizeof *info);
    task* stack = (task*)malloc((2 * total + 1) * sizeof *stack);
    if (!bvh->pieces || !bvh->nodes || !info || !stack) {
        free(info);
        free(stack);
        vbl_beam_bvh_free(bvh);
        return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "beam_bvh: out of memory for %zu beam pieces", total);
    }
    size_t k = 0;
    for (size_t i = 0; i < count; ++i) {
        double diameter = 2.0 * beams[i].radius;
        double nd = diameter > 0.0 ? ceil(beams[i].length / (aspect * diameter)) : 1.0;
        int n = (int)vbl_clamp(nd, 1.0, (double)max_pieces);
        for (int j = 0; j < n; ++j, ++k) {
            bvh->pieces[k].beam = (uint32_t)i;
            bvh->pieces[k].t0 = beams[i].length * j / n;
            bvh->pieces[k].t1 = j + 1 == n ? beams[i].length : beams[i].length * (j + 1) / n;
            piece_bounds(&beams[i], &bvh->pieces[k], &info[k]);
        }
    }
    bvh->piece_count = total;

    size_t top = 0, nodes = 0;
    stack[top++] = (task){0, total, (size_t)-1, 0};
    while (top > 0) {
        if ((nodes & 1023) == 1023 && options && options->stop && options->stop(options->stop_user)) {
            free(info);
            free(stack);
            vbl_beam_bvh_free(bvh);
            return vbl_error(VBL_ERROR_INTERRUPTED, "beam_bvh: build stopped (cancel or time limit)");
        }
        task t = stack[--top];
        size_t id = nodes++;
        if (t.patch != (size_t)-1) bvh->nodes[t.patch].first = (uint32_t)id;
        vbl_beam_bvh_node* node = &bvh->nodes[id];
        box nb, cb;
        box_empty(&nb);
        box_empty(&cb);
        for (size_t i = t.start; i < t.end; ++i) {
            box_grow(&nb, &info[i].bounds);
            box c = {{info[i].centroid[0], info[i].centroid[1], info[i].centroid[2]},
                     {info[i].centroid[0], info[i].centroid[1], info[i].centroid[2]}};
            box_grow(&cb, &c);
        }
        memcpy(node->lo, nb.lo, sizeof nb.lo);
        memcpy(node->hi, nb.hi, sizeof nb.hi);
        size_t n = t.end - t.start;
        size_t mid = t.start;
        int split = n > leaf_size && t.depth < BVH_MAX_DEPTH;
        if (split) {
            int axis = 0;
            double ext[3];
            for (int a = 0; a < 3; ++a) ext[a] = cb.hi[a] - cb.lo[a];
            if (ext[1] > ext[axis]) axis = 1;
            if (ext[2] > ext[axis]) axis = 2;
            if (ext[axis] > 0.0) {
                /* Binned SAH (16 bins) along the widest centroid axis. */
                box bins[BVH_BINS];
                size_t cnt[BVH_BINS] = {0};
                for (int b = 0; b < BVH_BINS; ++b) box_empty(&bins[b]);
                double scale = BVH_BINS / ext[axis];
                for (size_t i = t.start; i < t.end; ++i) {
                    int b = (int)((info[i].centroid[axis] - cb.lo[axis]) * scale);
                    b = b < 0 ? 0 : (b >= BVH_BINS ? BVH_BINS - 1 : b);
                    cnt[b]++;
                    box_grow(&bins[b], &info[i].bounds);
                }
                double right_area[BVH_BINS];
                size_t right_cnt[BVH_BINS];
                box acc;
                box_empty(&acc);
                size_t rc = 0;
                for (int b = BVH_BINS - 1; b > 0; --b) {
                    box_grow(&acc, &bins[b]);
                    rc += cnt[b];
                    right_area[b] = box_area(&acc);
                    right_cnt[b] = rc;
                }
                box_empty(&acc);
                size_t lc = 0;
                double best = INFINITY;
                int best_b = -1;
                for (int b = 1; b < BVH_BINS; ++b) {
                    box_grow(&acc, &bins[b - 1]);
                    lc += cnt[b - 1];
                    if (lc == 0 || right_cnt[b] == 0) continue;
                    double cost = box_area(&acc) * (double)lc + right_area[b] * (double)right_cnt[b];
                    if (cost < best) {
                        best = cost;
                        best_b = b;
                    }
                }
                if (best_b > 0) {
                    size_t i = t.start, j = t.end;
                    while (i < j) { /* in-place partition: bin < best_b to the left */
                        int b = (int)((info[i].centroid[axis] - cb.lo[axis]) * scale);
                        b = b < 0 ? 0 : (b >= BVH_BINS ? BVH_BINS - 1 : b);
                        if (b < best_b) {
                            ++i;
                        } else {
                            --j;
                            vbl_beam_piece tp = bvh->pieces[i];
                            bvh->pieces[i] = bvh->pieces[j];
                            bvh->pieces[j] = tp;
                            piece_info ti = info[i];
                            info[i] = info[j];
                            info[j] = ti;
                        }
                    }
                    mid = i;
                }
            }
            if (mid <= t.start || mid >= t.end) mid = t.start + n / 2; /* coincident centroids: halve */
        }
        if (!split) {
            node->first = (uint32_t)t.start;
            node->count = (uint32_t)n;
        } else {
            node->count = 0;
            node->first = 0; /* patched when the right child is created */
            stack[top++] = (task){mid, t.end, id, t.depth + 1};
            stack[top++] = (task){t.start, mid, (size_t)-1, t.depth + 1}; /* left child = id + 1 */
        }
    }
    bvh->node_count = nodes;
    free(info);
    free(stack);
    return VBL_SUCCESS;
}

/* ---- query ---- */

void vbl_beam_hits_free(vbl_beam_hits* hits)
{
    free(hits->ids);
    hits->ids = NULL;
    hits->count = hits->capacity = 0;
}

static int push_hit(vbl_beam_hits* h, uint32_t id)
{
    if (h->count == h->capacity) {
        size_t cap = h->capacity ? 2 * h->capacity : 64;
        uint32_t* p = (uint32_t*)realloc(h->ids, cap * sizeof *p);
        if (!p) return 0;
        h->ids = p;
        h->capacity = cap;
    }
    h->ids[h->count++] = id;
    return 1;
}

static int cmp_u32(const void* a, const void* b)
{
    uint32_t x = *(const uint32_t*)a, y = *(const uint32_t*)b;
    return x < y ? -1 : (x > y);
}

/* Does the segment o + t d, t in [0, len], meet the box? Slab test without 0 * inf. */
static int segment_hits_box(const double o[3], const double d[3], double len, const double lo[3], const double hi[3])
{
    double t0 = 0.0, t1 = len;
    for (int k = 0; k < 3; ++k) {
        if (d[k] == 0.0) {
            if (o[k] < lo[k] || o[k] > hi[k]) return 0;
            continue;
        }
        double inv = 1.0 / d[k];
        double a = (lo[k] - o[k]) * inv, b = (hi[k] - o[k]) * inv;
        if (a > b) {
            double t = a;
            a = b;
            b = t;
        }
        t0 = fmax(t0, a);
        t1 = fmin(t1, b);
        if (t0 > t1) return 0;
    }
    return 1;
}

vbl_result vbl_beam_bvh_query(const vbl_beam_bvh* bvh, vbl_vec3 o, vbl_vec3 d, double length, vbl_beam_hits* hits)
{
    hits->count = 0;
    if (bvh->node_count == 0 || !(length >= 0.0)) return VBL_SUCCESS;
    double oo[3] = {o.x, o.y, o.z}, dd[3] = {d.x, d.y, d.z};
    uint32_t stack[BVH_MAX_DEPTH + 8];
    int top = 0;
    stack[top++] = 0;
    uint64_t visited = 0; /* nodes, for the cost model (core/work_count.h) */
    while (top > 0) {
        const vbl_beam_bvh_node* n = &bvh->nodes[stack[--top]];
        ++visited;
        if (!segment_hits_box(oo, dd, length, n->lo, n->hi)) continue;
        if (n->count == 0) {
            stack[top++] = n->first;                                /* right */
            stack[top++] = (uint32_t)(n - bvh->nodes) + 1u;          /* left, visited first */
            continue;
        }
        for (uint32_t i = n->first; i < n->first + n->count; ++i) {
            uint32_t id = bvh->pieces[i].beam;
            const vbl_beam* b = &bvh->beams[id];
            const vbl_beam_piece* pc = &bvh->pieces[i];
            if (hits->count > 0 && hits->ids[hits->count - 1] == id) continue; /* adjacent piece, already in */
            /* Cheap conservative prefilter on the piece, then the whole beam is the arbiter (the
             * same test as a brute-force loop, so rounding cannot make the sets differ). */
            double pad = b->radius + 1e-7 * (b->radius + b->length + vbl_v3_length(b->origin) + length) + 1e-300;
            if (vbl_segment_distance2(o, d, length, vbl_v3_madd(b->origin, b->direction, pc->t0), b->direction,
                                      pc->t1 - pc->t0) > pad * pad)
                continue;
            if (vbl_segment_distance2(o, d, length, b->origin, b->direction, b->length) <= b->radius * b->radius)
                if (!push_hit(hits, id)) return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "beam_bvh: out of memory for hits");
        }
    }
    if (hits->count > 1) {
        qsort(hits->ids, hits->count, sizeof *hits->ids, cmp_u32);
        size_t w = 1;
        for (size_t i = 1; i < hits->count; ++i)
            if (hits->ids[i] != hits->ids[w - 1]) hits->ids[w++] = hits->ids[i];
        hits->count = w;
    }
    vbl_work_add(VBL_WORK_TREE_NODE, visited);
    return VBL_SUCCESS;
}

void vbl_beam_bvh_visit(const vbl_beam_bvh* bvh, vbl_vec3 o, vbl_vec3 d, double length, vbl_beam_piece_visit_fn fn,
                        void* user)
{
    if (bvh->node_count == 0 || !(length >= 0.0)) return;
    double oo[3] = {o.x, o.y, o.z}, dd[3] = {d.x, d.y, d.z};
    uint32_t stack[BVH_MAX_DEPTH + 8];
    int top = 0;
    stack[top++] = 0;
    uint64_t visited = 0; /* nodes, for the cost model (core/work_count.h) */
    while (top > 0) {
        const vbl_beam_bvh_node* n = &bvh->nodes[stack[--top]];
        ++visited;
        if (!segment_hits_box(oo, dd, length, n->lo, n->hi)) continue;
        if (n->count == 0) {
            stack[top++] = n->first;
            stack[top++] = (uint32_t)(n - bvh->nodes) + 1u;
            continue;
        }
        for (uint32_t i = n->first; i < n->first + n->count; ++i) {
            const vbl_beam_piece* pc = &bvh->pieces[i];
            const vbl_beam* b = &bvh->beams[pc->beam];
            double pad = b->radius + 1e-7 * (b->radius + b->length + vbl_v3_length(b->origin) + length) + 1e-300;
            if (vbl_segment_distance2(o, d, length, vbl_v3_madd(b->origin, b->direction, pc->t0), b->direction,
                                      pc->t1 - pc->t0) > pad * pad)
                continue;
            fn(user, pc->beam, pc->t0, pc->t1);
        }
    }
    vbl_work_add(VBL_WORK_TREE_NODE, visited);
}
