/* Balanced 3D k-d tree over a point set for the blue-noise virtual lights
 * (Li et al. 2022, section 3.2): m-nearest queries for eq 2's local density,
 * radius queries for the sample-elimination weights and for photon splitting (section 3.3).
 *
 * Implicit layout: `order` is a permutation of the point indices; the node over order[lo, hi)
 * keeps its splitting point at mid = (lo + hi) / 2, split along the axis of the largest extent
 * of its points. Keys are (coordinate, index), so ties never depend on the input order or on
 * threads: every query result is a deterministic function of the points. */
#ifndef VBL_BLUE_NOISE_KD_TREE_H
#define VBL_BLUE_NOISE_KD_TREE_H

#include <stddef.h>

#include "core/math.h"
#include "vbl/vbl_core.h"

typedef struct vbl_bn_kdtree {
    const vbl_vec3* points; /* not owned */
    size_t count;
    size_t* order;          /* count point indices (into points[]) in tree order */
    unsigned char* axis;    /* split axis of the node whose splitting point sits at order[i] */
    double* subtree_radius; /* NULL, or (vbl_bn_kdtree_set_radii) the largest radius in the subtree of
                               the node whose splitting point sits at order[i] */
} vbl_bn_kdtree;

/* Builds the tree over points[subset[0..count)] (subset NULL: points[0..count)). The points must
 * stay alive and unchanged while the tree is used. Errors: VBL_ERROR_OUT_OF_MEMORY. */
vbl_result vbl_bn_kdtree_build(vbl_bn_kdtree* tree, const vbl_vec3* points, const size_t* subset, size_t count);
void vbl_bn_kdtree_free(vbl_bn_kdtree* tree);

/* The m nearest points to q (excluding index `exclude`; pass (size_t)-1 for none), sorted by
 * (squared distance, index) ascending into idx[] / d2[] (d2 may be NULL). Returns how many were
 * found (min(m, points in the tree minus the excluded one)). */
size_t vbl_bn_kdtree_nearest(const vbl_bn_kdtree* tree, vbl_vec3 q, size_t m, size_t exclude, size_t* idx,
                             double* d2);

/* Calls visit(ctx, index, squared distance) for every point with |p - q| < radius, in a
 * deterministic order (tree order). */
typedef void (*vbl_bn_kdtree_visit_fn)(void* ctx, size_t index, double d2);
void vbl_bn_kdtree_within(const vbl_bn_kdtree* tree, vbl_vec3 q, double radius, vbl_bn_kdtree_visit_fn visit,
                          void* ctx);

/* Gives every point a radius (radii[i] for points[i], finite, >= 0) and stores each subtree's
 * largest. vbl_bn_kdtree_within then also skips a subtree whose split-plane distance from q is
 * at least that subtree's largest radius (times 1 + 1e-9): for sphere queries ("which points'
 * spheres contain q", the caller testing |p - q| against the point's own radius) it visits the
 * same points that pass the caller's test, in the same order, without the max-radius sweep. The
 * caller still passes the overall radius bound. Errors: VBL_ERROR_OUT_OF_MEMORY. */
vbl_result vbl_bn_kdtree_set_radii(vbl_bn_kdtree* tree, const double* radii);

/* Reorders order[0..n) so that order[k] holds the element of rank k by key (points[.][axis],
 * index) with smaller keys before it and larger after it (deterministic quickselect). Shared
 * with the balanced box split of sample_elimination.c. */
void vbl_bn_select(const vbl_vec3* points, size_t* order, size_t n, size_t k, int axis);
/* Axis (0, 1, 2) of the largest extent of points[order[0..n)]. */
int vbl_bn_widest_axis(const vbl_vec3* points, const size_t* order, size_t n);

#endif
