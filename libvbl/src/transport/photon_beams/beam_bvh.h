/* Bounding volume hierarchy over beams (photon beams, VRLs/VBLs): segments with a radius, built
 * once per pass, queried with a camera ray segment (Jarosz et al. 2011a,
 * section 8.3).
 *
 * Query contract: vbl_beam_bvh_query returns EXACTLY the beams whose segment lies within the
 * beam's radius of the query segment, i.e. vbl_segment_distance(query, beam) <= radius, each beam
 * once, in increasing index order (the same set a brute-force loop over all beams gives; tested).
 *
 * Long beams are split into sub-beams of about unit aspect ratio (length ~ split_aspect x 2 r,
 * section 8.3), at most VBL_BEAM_BVH_MAX_PIECES per beam, so that beams sharing a vertex (all
 * beams of a point light) or crossing the scene still partition well. The build is a binned SAH
 * with a stable in-place partition: deterministic (same beams -> same tree, same query order)
 * and single-threaded; queries are read-only and thread-safe. */
#ifndef VBL_TRANSPORT_BEAM_BVH_H
#define VBL_TRANSPORT_BEAM_BVH_H

#include <stddef.h>
#include <stdint.h>

#include "core/math.h"
#include "vbl/vbl_core.h"

#ifdef __cplusplus
extern "C" {
#endif

#define VBL_BEAM_BVH_MAX_PIECES 64

typedef struct vbl_beam {
    vbl_vec3 origin, direction; /* direction unit */
    double length, radius;      /* length >= 0, radius >= 0 */
} vbl_beam;

typedef struct vbl_beam_bvh_node {
    double lo[3], hi[3];
    uint32_t first; /* leaf: first piece index; inner: right child index (left child = this + 1) */
    uint32_t count; /* leaf: number of pieces (> 0); inner: 0 */
} vbl_beam_bvh_node;

typedef struct vbl_beam_piece {
    uint32_t beam;
    double t0, t1; /* sub-interval of the beam */
} vbl_beam_piece;

typedef struct vbl_beam_bvh {
    const vbl_beam* beams; /* borrowed: must outlive the BVH */
    size_t beam_count;
    vbl_beam_piece* pieces;
    size_t piece_count;
    vbl_beam_bvh_node* nodes;
    size_t node_count;
} vbl_beam_bvh;

typedef struct vbl_beam_bvh_options {
    double split_aspect; /* sub-beam length / diameter; <= 0: 1 (unit aspect ratio) */
    int leaf_size;       /* max pieces per leaf; <= 0: 4 */
    int max_pieces;      /* per beam; <= 0 or > VBL_BEAM_BVH_MAX_PIECES: VBL_BEAM_BVH_MAX_PIECES */
    int (*stop)(void* user); /* may be NULL; asked every 1024 nodes: non-zero ends the build with
                                VBL_ERROR_INTERRUPTED (cancel, time limit) */
    void* stop_user;
} vbl_beam_bvh_options;

/* Builds over `beams` (borrowed). Beams with non-finite data or negative radius fail with
 * VBL_ERROR_INVALID_ARGUMENT naming the beam; allocation failure gives VBL_ERROR_OUT_OF_MEMORY;
 * options->stop saying stop gives VBL_ERROR_INTERRUPTED.
 * options may be NULL. On failure *bvh is empty (safe to free). */
vbl_result vbl_beam_bvh_build(vbl_beam_bvh* bvh, const vbl_beam* beams, size_t count, const vbl_beam_bvh_options* options);
void vbl_beam_bvh_free(vbl_beam_bvh* bvh);

/* Growable result list (caller owns; zero-initialise, free with vbl_beam_hits_free). */
typedef struct vbl_beam_hits {
    uint32_t* ids;
    size_t count, capacity;
} vbl_beam_hits;
void vbl_beam_hits_free(vbl_beam_hits* hits);

/* Query segment o + t d, t in [0, length] (d unit). Replaces hits->ids with the sorted, unique
 * beam indices within radius. Returns VBL_SUCCESS or VBL_ERROR_OUT_OF_MEMORY. */
vbl_result vbl_beam_bvh_query(const vbl_beam_bvh* bvh, vbl_vec3 o, vbl_vec3 d, double length, vbl_beam_hits* hits);

/* Visitor form for renderers (no allocation): calls fn(user, beam, t0, t1) once for every piece
 * [t0, t1] of a beam (the pieces of a beam partition [0, length]) whose box the query segment
 * meets and whose distance to it is at most the beam's radius (conservatively padded for
 * rounding: a piece may be visited that a brute-force test would just exclude, never the
 * reverse). Order: deterministic (the tree's), not by index. */
typedef void (*vbl_beam_piece_visit_fn)(void* user, uint32_t beam, double t0, double t1);
void vbl_beam_bvh_visit(const vbl_beam_bvh* bvh, vbl_vec3 o, vbl_vec3 d, double length, vbl_beam_piece_visit_fn fn,
                        void* user);

/* Squared distance between segments p0 + s d0 (s in [0, len0]) and p1 + t d1 (t in [0, len1]),
 * unit directions; exact closest-point computation, robust for parallel segments. */
double vbl_segment_distance2(vbl_vec3 p0, vbl_vec3 d0, double len0, vbl_vec3 p1, vbl_vec3 d1, double len1);

#ifdef __cplusplus
}
#endif

#endif
