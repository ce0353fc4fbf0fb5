/* Per-camera-ray selection of virtual ray lights from a light tree (stochastic lightcuts:
 * Yuksel 2019, "Stochastic Lightcuts", section 3; Estevez and Kulla 2018, "Importance Sampling
 * of Many Lights with Adaptive Tree Splitting", section 4: a binary tree over the lights whose
 * internal nodes carry bounds, traversed from the root by choosing a child with probability
 * proportional to a conservative importance; the light reached is used with weight 1 / pdf).
 *
 * Tree: built once per pass over the VRLs that can contribute (power > 0, length > 0 and
 * bounce + 2 <= max_bounces), top-down, splitting at the median of the segment midpoints along
 * the widest axis, one VRL per leaf. A node stores the bounding sphere of its segments, its
 * mass = sum over its VRLs of sum_rgb(Phi) x density (the mean sigma_s along the VRL: eq 7's
 * sigma_s(v) factor; a VRL through thin medium scatters little) and the longest VRL length l_max
 * below it.
 *
 * Importance of a node for a camera segment c + u d, u in [0, len]:
 *   I = mass T_c(max(0, u* - r)) G(l_max, len, h),   h = max(h_lb, floor),
 *   G(l, L, h) = min(l, h) min(L, h) / h^2 x (1 + log(min(l, L) / h) if min(l, L) > h),
 *   h_lb = max(0, dist(segment, sphere centre) - r),
 * with r the sphere radius and u* the segment point closest to the centre; at a leaf h is the
 * exact distance between the camera segment and the VRL and r the VRL's length. h_lb is a lower
 * bound of the distance from the segment to every VRL below the node and G falls with h and
 * grows with l, so the geometric factor bounds each child's from above. G follows the VRL
 * integrand of eq 7 (VRL paper, with the geometry of eqs 10-13): int int 1 / w^2 du dv over two
 * segments of lengths l and L at distance h is ~ l L / h^2 when both are shorter than h,
 * ~ pi l / h when only the camera segment is longer, and ~ (2 pi / sin theta) log(min(l, L) / h)
 * when both are longer (crossing). T_c is the camera ray's cached transmittance
 * (optional, floored at min_transmittance), taken at the front of the node's projection onto the
 * segment: it is non-increasing, so that bounds it over the node. The connection's transmittance
 * is left out: a midpoint-rule guess of it at 4 sigma_t points (an earlier version) moved the
 * probability of the VRLs that carry a dense cloud's pixels towards 0 (the fringe seen through a
 * guess across the core) and made the selection's tail worse, at twice the cost per camera sample.
 * The traversal looks VBL_VRL_TREE_LOOKAHEAD levels ahead where the camera segment passes close
 * to a node (within its radius of the sphere): a child's importance is then the sum of its
 * descendants' (an estimate, not a bound, of the sum over its pieces), which follows the
 * integrand much better there than one distance bound for a node the segment crosses.
 * floor > 0 and the transmittance floor keep every light's
 * probability positive (unbiased for any floors); floor is a small fraction of the media's
 * bounding radius. The caller passes the camera segment restricted to where its cached
 * transmittance is not negligible (vbl_vrl_tree_visible_length), which only moves probability,
 * never to zero.
 *
 * The pdf of a leaf is the product of the branch probabilities along its path; vbl_vrl_tree_pdf
 * recomputes it from the leaf upwards (tests). Draws are independent and with replacement. */
#ifndef VBL_TRANSPORT_VRL_TREE_H
#define VBL_TRANSPORT_VRL_TREE_H

#include <stddef.h>

#include "core/error.h"
#include "core/math.h"
#include "core/rng.h"

struct vbl_vrl;
struct vbl_transmittance_cache;

typedef struct vbl_vrl_tree_node {
    vbl_vec3 center;
    double radius;
    double mass;     /* sum of its pieces' masses */
    double length;   /* the longest of its pieces */
    int left, right; /* children; leaf: left = -1, right = the piece's index */
    int parent;      /* -1 at the root */
} vbl_vrl_tree_node;

/* The tree's lights are pieces [v0, v1] of the VRLs (a VRL longer than the piece length is split
 * into equal pieces; the estimate of a VRL is the sum of its pieces' estimates, so selecting
 * pieces is as unbiased as selecting VRLs, and small pieces give tight node bounds). */
typedef struct vbl_vrl_tree_piece {
    int vrl;          /* index in the store */
    double v0, v1;    /* 0 <= v0 < v1 <= length */
} vbl_vrl_tree_piece;

/* A piece's weight in the mass (multiplies sum_rgb(Phi)); must be > 0 for the piece to count. */
typedef double (*vbl_vrl_tree_weight_fn)(void* user, const struct vbl_vrl* vrl, double v0, double v1);

typedef struct vbl_vrl_tree {
    vbl_vrl_tree_node* nodes;
    int node_count;
    vbl_vrl_tree_piece* pieces;
    int* leaf_of;      /* per piece: its leaf node, -1 if not in the tree */
    int piece_count;
    int light_count;   /* pieces in the tree */
    double floor;      /* distance floor, world units */
    const struct vbl_vrl* vrls; /* the store's VRLs (not owned; must outlive the tree) */
} vbl_vrl_tree;

typedef struct vbl_vrl_tree_query {
    vbl_vec3 origin, direction; /* unit direction */
    double length;              /* >= 0 */
    /* optional (NULL: T = 1): the camera ray's cached transmittance, evaluated at
     * cache_offset + s for the segment point origin + s direction, floored at min_transmittance > 0 */
    const struct vbl_transmittance_cache* cache;
    double cache_offset, min_transmittance;
} vbl_vrl_tree_query;

#define VBL_VRL_TREE_LOOKAHEAD 2 /* levels of look-ahead near the camera segment (measured: 2) */

/* Builds the tree over the pieces (at most piece_length long; <= 0: whole VRLs) of vrls[0 ..
 * count-1] that have power > 0, length > 0 and bounce + 2 <= max_bounces (max_bounces < 0:
 * unlimited). floor > 0 (world units). weight (may be NULL: 1) multiplies a piece's power in
 * its mass (the estimators pass the mean sigma_s along the piece, vbl_vrl_select_tree_build);
 * pieces of weight <= 0 are left out. An empty tree is valid: light_count = 0. */
vbl_result vbl_vrl_tree_build(vbl_vrl_tree* tree, const struct vbl_vrl* vrls, size_t count, int max_bounces,
                              double floor, double piece_length, vbl_vrl_tree_weight_fn weight, void* user);
/* A stop hook: fn(user) non-zero asks the build to stop. */
typedef struct vbl_vrl_tree_stop_hook {
    int (*fn)(void* user);
    void* user;
} vbl_vrl_tree_stop_hook;
/* The same with a stop hook (may be NULL), asked at every node over 1024 pieces: non-zero ends the
 * build with VBL_ERROR_INTERRUPTED and an empty tree (cancel, time limit). */
vbl_result vbl_vrl_tree_build_stoppable(vbl_vrl_tree* tree, const struct vbl_vrl* vrls, size_t count, int max_bounces,
                                        double floor, double piece_length, vbl_vrl_tree_weight_fn weight, void* user,
                                        const vbl_vrl_tree_stop_hook* stop);
void vbl_vrl_tree_free(vbl_vrl_tree* tree);

/* One draw: the chosen piece's index (tree->pieces) and its selection probability (*pdf > 0),
 * or -1 for an empty tree. xi in [0, 1). */
int vbl_vrl_tree_sample(const vbl_vrl_tree* tree, const vbl_vrl_tree_query* q, double xi, double* pdf);
/* K stratified draws ((k + xi0) / K, one uniform xi0 from rng; each draw's marginal is still the
 * tree pdf): visit(piece, 1 / (den K pdf), user) per draw, stopping at the first failed draw.
 * The per-camera-sample selection of vrl and vbl (stochastic lightcuts, Yuksel 2019): unbiased. */
typedef void (*vbl_vrl_tree_visit_fn)(const vbl_vrl_tree_piece* piece, double weight, void* user);
void vbl_vrl_tree_select(const vbl_vrl_tree* tree, const vbl_vrl_tree_query* q, int K, double den,
                         vbl_rng* rng, vbl_vrl_tree_visit_fn visit, void* user);
/* Probability that vbl_vrl_tree_sample returns piece `index` (0 if it is not in the tree). */
double vbl_vrl_tree_pdf(const vbl_vrl_tree* tree, const vbl_vrl_tree_query* q, int index);

/* The part of the camera segment [u0, u1] worth selecting for: u from u0 to the first cached
 * point where the cache's transmittance estimate falls below `cut` (u1 if it never does).
 * Returns that length (>= 0). */
double vbl_vrl_tree_visible_length(const struct vbl_transmittance_cache* cache, double u0, double u1, double cut);

#endif
