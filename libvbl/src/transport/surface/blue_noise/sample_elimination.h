/* Adaptive, parallel weighted sample elimination (Li et al. 2022, section 3.2, eqs. 1-2,
 * after Yuksel 2015): selects N of M candidate virtual-light positions forming a blue-noise set
 * that keeps the candidates' density variation.
 *
 *  - r_max per sample (eq 2): d_i = distance to the m-th nearest other sample, A_i = pi d_i^2,
 *        r_i = sqrt(M A_i / (2 sqrt(3) N m)).
 *    Uniform elimination instead uses eq 1 with a given area A: r = sqrt(A / (2 sqrt(3) N)).
 *  - Weights (Yuksel 2015): w_ij = (1 - d_ij / (2 r_ij))^beta for d_ij < 2 r_ij, beta = 8, with
 *    the symmetric pair radius r_ij = (r_i + r_j) / 2 (our choice for per-sample radii). The
 *    sample with the largest sum of weights (ties: the lower index) is eliminated and its
 *    neighbours' sums are reduced, through a max-heap, until N remain.
 *  - Parallel scheme: the candidates are split recursively into two halves of (nearly) equal
 *    count along the widest axis (a balanced k-d tree of boxes), 3 binary levels per 8-way
 *    level. Each leaf box eliminates `partial` (0.8) of its excess over its share N M_b / M,
 *    then each 8-box parent does the same on the survivors, and the root eliminates exactly
 *    down to N in one thread. Boxes of one level are disjoint and each box's elimination is
 *    sequential, so the result does not depend on the thread count.
 * VSL radius = alpha r_max (alpha = 2 by default, VBL_BN_VSL_ALPHA_DEFAULT). */
#ifndef VBL_BLUE_NOISE_SAMPLE_ELIMINATION_H
#define VBL_BLUE_NOISE_SAMPLE_ELIMINATION_H

#include <stddef.h>

#include "core/math.h"
#include "vbl/vbl_core.h"

#define VBL_BN_VSL_ALPHA_DEFAULT 2.0

typedef struct vbl_bn_elimination_options {
    size_t size;
    size_t neighbors;       /* m of eq 2 (clamped to M - 1) */
    double weight_exponent; /* beta of the weight (1 - d / 2r)^beta */
    double partial;         /* fraction of a box's excess eliminated before its parent, in [0, 1] */
    size_t leaf_size;       /* smallest leaf box of the parallel scheme; 0: sequential (one box) */
    double uniform_area;    /* > 0: uniform elimination, eq 1 with this area; 0: adaptive (eq 2) */
    int (*stop)(void* user); /* may be NULL; asked every few hundred samples: non-zero ends the step
                                with VBL_ERROR_INTERRUPTED (cancel, time limit; issue #18) */
    void* stop_user;
} vbl_bn_elimination_options;

#define VBL_BN_ELIMINATION_DEFAULT {sizeof(vbl_bn_elimination_options), 32, 8.0, 0.8, 4096, 0.0, NULL, NULL}

typedef struct vbl_bn_elimination_stats {
    int levels;          /* 8-way levels below the root (0: sequential) */
    size_t leaf_boxes;   /* 8^levels */
    size_t eliminated_before_root; /* by the leaf and intermediate boxes (in parallel) */
} vbl_bn_elimination_stats;

/* Eq 2 (or eq 1 when uniform_area > 0) for every sample: r_max[0..M). Samples whose m-th
 * neighbour coincides with them (d_i = 0) get the smallest positive r of the set (0 if none). */
vbl_result vbl_bn_compute_rmax(const vbl_vec3* points, size_t M, size_t N, const vbl_bn_elimination_options* options,
                               double* r_max);

/* Keeps exactly N of the M points: kept[0..N) ascending indices; kept_r_max (may be NULL) their
 * r_max; stats may be NULL. options NULL: defaults. Errors: VBL_ERROR_INVALID_ARGUMENT (N
 * outside [1, M], a non-finite point, bad option), VBL_ERROR_OUT_OF_MEMORY. */
vbl_result vbl_bn_eliminate(const vbl_vec3* points, size_t M, size_t N, const vbl_bn_elimination_options* options,
                            size_t* kept, double* kept_r_max, vbl_bn_elimination_stats* stats);

/* The same with r_max[0..M) given (e.g. from vbl_bn_compute_rmax, computed once for several N or
 * kept for eq 8); r_max values must be finite and >= 0. */
vbl_result vbl_bn_eliminate_with_rmax(const vbl_vec3* points, size_t M, size_t N, const double* r_max,
                                      const vbl_bn_elimination_options* options, size_t* kept, double* kept_r_max,
                                      vbl_bn_elimination_stats* stats);

#endif
