/* A deterministic count of work done by the calling thread, in units that density lookups and ray
 * casts do not cover (light-tree and beam-BVH node visits, virtual-light evaluations, lights traced
 * into a pass's store). The hybrid pilot (render/hybrid_pilot.c) adds it to its cost count so that
 * the virtual lights' cost is not undercounted; nothing else reads it. The increment is inline:
 * it sits in the light tree's node importance, a hot path. */
#ifndef VBL_CORE_WORK_COUNT_H
#define VBL_CORE_WORK_COUNT_H

#include <stdint.h>

/* What each kind of work adds (vbl_work_add); the weights are in the cost model's units. */
typedef enum vbl_work_kind {
    VBL_WORK_TREE_NODE = 0,   /* one light-tree node importance (vrl_tree.c) or beam-BVH node (beam_bvh.c) */
    VBL_WORK_LIGHT_EVAL = 1,  /* one virtual light or beam piece evaluated against a camera segment or surface point */
    VBL_WORK_STORE_LIGHT = 2, /* one VRL, beam or VPL traced into a pass's store (trace + tree build) */
    VBL_WORK_KIND_COUNT = 3
} vbl_work_kind;

/* This thread's counts (work_count.c). */
extern _Thread_local uint64_t vbl_thread_work[VBL_WORK_KIND_COUNT];

static inline void vbl_work_add(vbl_work_kind kind, uint64_t n) { vbl_thread_work[kind] += n; }

/* This thread's count of `kind` since it started. */
static inline uint64_t vbl_work_count(vbl_work_kind kind) { return vbl_thread_work[kind]; }

#endif
