/* Light tree over a pass's VRLs and its stochastic traversal (vrl_tree.h). */
#include "transport/virtual_lights/vrl_tree.h"

#include <stdlib.h>

#include "core/rng.h"
#include "core/work_count.h"
#include "transport/common/photon_trace.h"
#include "volume/transmittance_cache.h"

typedef struct vbl_tree_item {
    vbl_vec3 lo, hi, mid; /* segment bounds and midpoint */
    double mass, length;
    int index;
} vbl_tree_item;

static _Thread_local int vbl_tree_axis; /* the qsort comparator's axis */

static double vbl_axis(vbl_vec3 v, int a) { return a == 0 ? v.x : (a == 1 ? v.y : v.z); }

static int vbl_tree_item_cmp(const void* pa, const void* pb)
{
    const vbl_tree_item *a = pa, *b = pb;
    double x = vbl_axis(a->mid, vbl_tree_axis), y = vbl_axis(b->mid, vbl_tree_axis);
    if (x < y) return -1;
    if (x > y) return 1;
    return a->index - b->index; /* total order: the tree does not depend on qsort's stability */
}

/* The build's stop hook (cancel, time limit): asked at every node over 1024 pieces. */
typedef struct vbl_tree_stop {
    int (*stop)(void* user);
    void* user;
    int stopped;
} vbl_tree_stop;

/* Builds the subtree over items[0 .. n-1] into tree->nodes, returns its node index (-1 once
 * stopped: the caller discards the tree). */
static int vbl_tree_build_range(vbl_vrl_tree* tree, vbl_tree_item* items, int n, int parent, vbl_tree_stop* st)
{
    if (st->stopped || (n > 1024 && st->stop && (st->stopped = st->stop(st->user) != 0))) return -1;
    const int id = tree->node_count++;
    vbl_vrl_tree_node* node = &tree->nodes[id];
    node->parent = parent;
    vbl_vec3 lo = items[0].lo, hi = items[0].hi, mlo = items[0].mid, mhi = items[0].mid;
    double mass = 0.0, length = 0.0;
    for (int i = 0; i < n; ++i) {
        length = fmax(length, items[i].length);
        lo = vbl_v3(fmin(lo.x, items[i].lo.x), fmin(lo.y, items[i].lo.y), fmin(lo.z, items[i].lo.z));
        hi = vbl_v3(fmax(hi.x, items[i].hi.x), fmax(hi.y, items[i].hi.y), fmax(hi.z, items[i].hi.z));
        mlo = vbl_v3(fmin(mlo.x, items[i].mid.x), fmin(mlo.y, items[i].mid.y), fmin(mlo.z, items[i].mid.z));
        mhi = vbl_v3(fmax(mhi.x, items[i].mid.x), fmax(mhi.y, items[i].mid.y), fmax(mhi.z, items[i].mid.z));
        mass += items[i].mass;
    }
    node->center = vbl_v3_scale(vbl_v3_add(lo, hi), 0.5);
    node->radius = 0.5 * vbl_v3_length(vbl_v3_sub(hi, lo));
    node->mass = mass;
    node->length = length;
    if (n == 1) {
        node->left = -1;
        node->right = items[0].index;
        tree->leaf_of[items[0].index] = id;
        return id;
    }
    vbl_vec3 ext = vbl_v3_sub(mhi, mlo);
    vbl_tree_axis = ext.x >= ext.y && ext.x >= ext.z ? 0 : (ext.y >= ext.z ? 1 : 2);
    qsort(items, (size_t)n, sizeof *items, vbl_tree_item_cmp);
    const int half = n / 2;
    int l = vbl_tree_build_range(tree, items, half, id, st);
    int r = vbl_tree_build_range(tree, items + half, n - half, id, st);
    tree->nodes[id].left = l;
    tree->nodes[id].right = r;
    return id;
}

vbl_result vbl_vrl_tree_build(vbl_vrl_tree* tree, const vbl_vrl* vrls, size_t count, int max_bounces, double floor,
                              double piece_length, vbl_vrl_tree_weight_fn weight, void* user)
{
    return vbl_vrl_tree_build_stoppable(tree, vrls, count, max_bounces, floor, piece_length, weight, user, NULL);
}

vbl_result vbl_vrl_tree_build_stoppable(vbl_vrl_tree* tree, const vbl_vrl* vrls, size_t count, int max_bounces,
                                        double floor, double piece_length, vbl_vrl_tree_weight_fn weight, void* user,
                                        const vbl_vrl_tree_stop_hook* stop)
{
    *tree = (vbl_vrl_tree){0};
    tree->floor = floor;
    /* count the pieces */
    size_t total = 0;
    for (size_t j = 0; j < count; ++j) {
        const vbl_vrl* l = &vrls[j];
        if (max_bounces >= 0 && l->bounce + 2 > max_bounces) continue;
        if (!(l->length > 0.0) || !isfinite(l->length)) continue;
        double k = piece_length > 0.0 ? ceil(l->length / piece_length) : 1.0;
        total += (size_t)fmin(fmax(k, 1.0), 1e6);
    }
    if (total == 0) return VBL_SUCCESS;
    if (total > 0x3FFFFFFF) return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vrl tree: %zu pieces is too many", total);
    tree->pieces = malloc(total * sizeof *tree->pieces);
    tree->leaf_of = malloc(total * sizeof *tree->leaf_of);
    vbl_tree_item* items = malloc(total * sizeof *items);
    if (!tree->pieces || !tree->leaf_of || !items) {
        free(items);
        vbl_vrl_tree_free(tree);
        return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "vrl tree: out of memory (%zu pieces)", total);
    }
    int np = 0, n = 0;
    for (size_t j = 0; j < count; ++j) {
        const vbl_vrl* l = &vrls[j];
        if (max_bounces >= 0 && l->bounce + 2 > max_bounces) continue;
        if (!(l->length > 0.0) || !isfinite(l->length)) continue;
        double power = l->power.x + l->power.y + l->power.z;
        int k = (int)fmin(fmax(piece_length > 0.0 ? ceil(l->length / piece_length) : 1.0, 1.0), 1e6);
        for (int i = 0; i < k; ++i) {
            double v0 = l->length * i / k, v1 = i + 1 == k ? l->length : l->length * (i + 1) / k;
            double p = power * (weight ? weight(user, l, v0, v1) : 1.0);
            const int id = np++;
            tree->pieces[id] = (vbl_vrl_tree_piece){(int)j, v0, v1};
            tree->leaf_of[id] = -1;
            if (!(p > 0.0) || !isfinite(p)) continue;
            vbl_vec3 a = vbl_v3_madd(l->origin, l->direction, v0), b = vbl_v3_madd(l->origin, l->direction, v1);
            items[n].lo = vbl_v3(fmin(a.x, b.x), fmin(a.y, b.y), fmin(a.z, b.z));
            items[n].hi = vbl_v3(fmax(a.x, b.x), fmax(a.y, b.y), fmax(a.z, b.z));
            items[n].mid = vbl_v3_scale(vbl_v3_add(a, b), 0.5);
            items[n].mass = p;
            items[n].length = v1 - v0;
            items[n].index = id;
            ++n;
        }
    }
    tree->piece_count = np;
    tree->light_count = n;
    tree->vrls = vrls;
    if (n > 0) {
        tree->nodes = malloc((size_t)(2 * n - 1) * sizeof *tree->nodes);
        if (!tree->nodes) {
            free(items);
            vbl_vrl_tree_free(tree);
            return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "vrl tree: out of memory (%d nodes)", 2 * n - 1);
        }
        vbl_tree_stop st = {stop ? stop->fn : NULL, stop ? stop->user : NULL, 0};
        vbl_tree_build_range(tree, items, n, -1, &st);
        if (st.stopped) {
            free(items);
            vbl_vrl_tree_free(tree);
            return vbl_error(VBL_ERROR_INTERRUPTED, "vrl tree: build stopped (cancel or time limit)");
        }
    }
    free(items);
    return VBL_SUCCESS;
}

void vbl_vrl_tree_free(vbl_vrl_tree* tree)
{
    free(tree->nodes);
    free(tree->leaf_of);
    free(tree->pieces);
    *tree = (vbl_vrl_tree){0};
}

/* Distance from point p to the segment q->origin + u q->direction, u in [0, length]. */
static double vbl_point_segment_distance(const vbl_vrl_tree_query* q, vbl_vec3 p, double* u_closest)
{
    vbl_vec3 r = vbl_v3_sub(p, q->origin);
    double u = vbl_clamp(vbl_v3_dot(r, q->direction), 0.0, q->length);
    *u_closest = u;
    return vbl_v3_length(vbl_v3_sub(r, vbl_v3_scale(q->direction, u)));
}

/* Closest points of segment q and segment b + t e (t in [0, lb], unit e): distance, and the
 * parameter on q in *s (clamped line-line solution, as vbl_segment_distance). */
static double vbl_segment_closest(const vbl_vrl_tree_query* q, vbl_vec3 b, vbl_vec3 e, double lb, double* s_out)
{
    vbl_vec3 r = vbl_v3_sub(q->origin, b);
    double ab = vbl_v3_dot(q->direction, e), c = vbl_v3_dot(q->direction, r), f = vbl_v3_dot(e, r);
    double denom = 1.0 - ab * ab;
    double s = denom > 1e-12 ? vbl_clamp((ab * f - c) / denom, 0.0, q->length) : 0.0;
    double t = ab * s + f;
    if (t < 0.0) {
        t = 0.0;
        s = vbl_clamp(-c, 0.0, q->length);
    } else if (t > lb) {
        t = lb;
        s = vbl_clamp(ab * lb - c, 0.0, q->length);
    }
    *s_out = s;
    return vbl_v3_length(vbl_v3_sub(vbl_v3_madd(q->origin, q->direction, s), vbl_v3_madd(b, e, t)));
}

/* The geometric factor ~ int int 1 / w^2 of two segments of lengths l and L at distance h >= floor
 * (see the header): falls with h, grows with l and L. */
static double vbl_geometry_factor(double l, double L, double h)
{
    double g = fmin(l, h) * fmin(L, h) / (h * h);
    double m = fmin(l, L);
    return m > h ? g * (1.0 + log(m / h)) : g;
}

static double vbl_node_importance(const vbl_vrl_tree* tree, const vbl_vrl_tree_query* q, int id)
{
    const vbl_vrl_tree_node* n = &tree->nodes[id];
    double s, h, front;
    vbl_work_add(VBL_WORK_TREE_NODE, 1);
    if (n->left < 0) { /* leaf: the piece itself */
        const vbl_vrl_tree_piece* pc0 = &tree->pieces[n->right];
        const vbl_vrl* l = &tree->vrls[pc0->vrl];
        vbl_vec3 a = vbl_v3_madd(l->origin, l->direction, pc0->v0);
        double len = pc0->v1 - pc0->v0;
        h = vbl_segment_closest(q, a, l->direction, len, &s);
        front = s - len;
    } else { /* the bounding sphere: h_lb */
        h = vbl_point_segment_distance(q, n->center, &s) - n->radius;
        front = s - n->radius;
    }
    h = fmax(h, tree->floor);
    double t = 1.0; /* T_c is non-increasing: its value at the front of the node's projection bounds it */
    if (q->cache)
        t = fmax(vbl_transmittance_cache_eval(q->cache, q->cache_offset + fmax(0.0, front)), q->min_transmittance);
    return n->mass * t * vbl_geometry_factor(n->length, fmax(q->length, tree->floor), h);
}

/* A node's importance with look-ahead: where the camera segment passes within the node's radius
 * of its sphere (the distance bound says little there), the sum of its children's, down to
 * `depth` levels; elsewhere its own. The sum over a node's descendants is a sharper estimate of
 * the sum of its pieces' contributions than the node's single bound (measured: docs/readme/vrl.md). */
static double vbl_lookahead_importance(const vbl_vrl_tree* tree, const vbl_vrl_tree_query* q, int id, int depth)
{
    const vbl_vrl_tree_node* n = &tree->nodes[id];
    if (depth <= 0 || n->left < 0) return vbl_node_importance(tree, q, id);
    double s, h = vbl_point_segment_distance(q, n->center, &s) - n->radius;
    if (h > n->radius) return vbl_node_importance(tree, q, id);
    return vbl_lookahead_importance(tree, q, n->left, depth - 1) + vbl_lookahead_importance(tree, q, n->right, depth - 1);
}

/* Probability of taking child `c` of internal node `id`. */
static double vbl_branch_probability(const vbl_vrl_tree* tree, const vbl_vrl_tree_query* q, int id, int c)
{
    const vbl_vrl_tree_node* n = &tree->nodes[id];
    double il = vbl_lookahead_importance(tree, q, n->left, VBL_VRL_TREE_LOOKAHEAD);
    double ir = vbl_lookahead_importance(tree, q, n->right, VBL_VRL_TREE_LOOKAHEAD);
    double sum = il + ir;
    if (!(sum > 0.0) || !isfinite(sum)) return 0.5; /* cannot happen with mass > 0, floor > 0 */
    return (c == n->left ? il : ir) / sum;
}

int vbl_vrl_tree_sample(const vbl_vrl_tree* tree, const vbl_vrl_tree_query* q, double xi, double* pdf)
{
    *pdf = 0.0;
    if (tree->light_count == 0) return -1;
    int id = 0;
    double p = 1.0;
    while (tree->nodes[id].left >= 0) {
        const vbl_vrl_tree_node* n = &tree->nodes[id];
        double pl = vbl_branch_probability(tree, q, id, n->left);
        /* pl is in (0, 1) (both importances > 0); xi is rescaled into [0, 1) for the next level */
        if (xi < pl) {
            xi /= pl;
            p *= pl;
            id = n->left;
        } else {
            xi = (xi - pl) / (1.0 - pl);
            p *= 1.0 - pl;
            id = n->right;
        }
        if (!(xi < 1.0)) xi = 0x1.fffffffffffffp-1;
        if (!(xi >= 0.0)) xi = 0.0;
    }
    *pdf = p;
    return tree->nodes[id].right;
}

double vbl_vrl_tree_pdf(const vbl_vrl_tree* tree, const vbl_vrl_tree_query* q, int index)
{
    if (index < 0 || index >= tree->piece_count || tree->leaf_of[index] < 0) return 0.0;
    int id = tree->leaf_of[index];
    double p = 1.0;
    while (tree->nodes[id].parent >= 0) {
        int parent = tree->nodes[id].parent;
        double pl = vbl_branch_probability(tree, q, parent, tree->nodes[parent].left);
        p *= id == tree->nodes[parent].left ? pl : 1.0 - pl;
        id = parent;
    }
    return p;
}

double vbl_vrl_tree_visible_length(const vbl_transmittance_cache* cache, double u0, double u1, double cut)
{
    for (int i = 0; i < cache->count; ++i)
        if (cache->value[i] < cut) return fmax(0.0, fmin(cache->t[i], u1) - u0);
    return fmax(0.0, u1 - u0);
}

void vbl_vrl_tree_select(const vbl_vrl_tree* tree, const vbl_vrl_tree_query* q, int K, double den, vbl_rng* rng,
                         vbl_vrl_tree_visit_fn visit, void* user)
{
    const double xi0 = vbl_rng_uniform(rng);
    for (int k = 0; k < K; ++k) {
        double pdf, xi = (k + xi0) / K;
        int j = vbl_vrl_tree_sample(tree, q, xi < 1.0 ? xi : 0x1.fffffffffffffp-1, &pdf);
        if (j < 0 || !(pdf > 0.0)) break;
        visit(&tree->pieces[j], 1.0 / (den * K * pdf), user);
    }
}
