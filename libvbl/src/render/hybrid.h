/* render.hybrid: a virtual-light method (vpl, vrl, vbl, beams) combined with pt per transport
 * class (docs/readme/hybrid.md).
 *
 * The transport classes (vbl_transport_class) are disjoint sets of light paths, so a render where
 * pt estimates the classes of a set P and the virtual-light method the others, summed, is an
 * unbiased estimate of the beauty: it is a multiple-importance combination (Veach 1997, sec. 9.1-9.2,
 * eq. 9.3: any weights w_t(path) >= 0 with sum_t w_t = 1 for every path keep the combination
 * unbiased) with weights 0 or 1 that depend only on the path's class. It is NOT the per-path
 * weighting of unified points, beams and paths (Krivanek et al. 2014, sec. 5), which weighs each
 * path by the pdfs of every technique that could have made it.
 *
 * Per camera sample the hybrid estimator runs the method once (with skip_classes = P, so it skips
 * the work of pt's classes, estimator.h) and keeps its classes outside P, then pt_spp pt samples on
 * the same camera ray (from the same pixel stream, after the method's numbers; pt.sampler is
 * independent there), each weighted 1 / pt_spp, and keeps their classes in P. With P = every class
 * the method's pass is skipped; with P empty pt is. */
#ifndef VBL_RENDER_HYBRID_H
#define VBL_RENDER_HYBRID_H

#include "transport/common/estimator.h"

#define VBL_HYBRID_ALL_CLASSES ((1u << VBL_CLASS_COUNT) - 1u)

/* The pilot's measurements per class (auto mode; zeros otherwise). */
typedef struct vbl_hybrid_pilot_stats {
    double pt_variance[VBL_CLASS_COUNT]; /* variance of one pt sample (sum over pilot pixels) */
    double vl_variance[VBL_CLASS_COUNT]; /* variance of one method pass (spp samples), same units */
    double pt_cost, vl_cost;             /* cost units (density lookups, VBL_HYBRID_RAY_COST per ray
                                            cast, VBL_HYBRID_SAMPLE_COST per camera sample, the
                                            work counts below) per pt sample / per method pass of
                                            one pixel, the method's store included */
} vbl_hybrid_pilot_stats;

/* What a hybrid render does (fixed for the whole render, for every pass range). */
typedef struct vbl_hybrid_plan {
    const vbl_estimator* base; /* the virtual-light method */
    unsigned pt_classes;       /* bit c: pt renders class c */
    int pt_spp;                /* pt samples per method camera sample */
    int automatic;             /* 1: chosen by the pilot */
    vbl_hybrid_pilot_stats pilot;
} vbl_hybrid_plan;

/* The estimator of a hybrid render; its pass_begin reads ctx->hybrid. */
extern const vbl_estimator vbl_estimator_hybrid;

/* The plan of options.hybrid for `base` (VBL_HYBRID_CLASSES: the options; VBL_HYBRID_AUTO: the
 * pilot, vbl_hybrid_pilot). Fails for method pt or a method without a virtual-light estimator. */
vbl_result vbl_hybrid_plan_make(const vbl_render_context* ctx, const vbl_estimator* base, vbl_hybrid_plan* out);

/* The auto pilot (render/hybrid_pilot.c): VBL_HYBRID_PILOT_PASSES passes of `base` and of pt over
 * a grid of at most VBL_HYBRID_PILOT_GRID^2 pixels, seeds (options.seed ^ VBL_RNG_DOMAIN_HYBRID,
 * pilot pass, pixel) and pilot passes 0 .. P-1 whatever options.first_pass is, so the decision
 * depends only on (scene, options) and never on threads or a split's pass range. Per class, the
 * variances are the grid's sums of per-pixel sample variances (absolute, in units of the grid's
 * squared mean beauty), and vbl_hybrid_assign picks the owners. pt_spp: the optimal split
 * n_pt / n_method = sqrt(B C_vl / (A c_pt)) of a fixed cost between two independent estimators of
 * sums A (method) and B (pt), rounded, in [1, VBL_HYBRID_MAX_PT_SPP]. Cost is counted, not timed,
 * so the decision is deterministic: density lookups, VBL_HYBRID_RAY_COST per Embree ray cast
 * (vbl_surfaces_ray_count), VBL_HYBRID_SAMPLE_COST per camera sample, and the virtual lights' own
 * work (core/work_count.h): VBL_HYBRID_TREE_NODE_COST per light-tree node visited,
 * VBL_HYBRID_LIGHT_EVAL_COST per virtual light evaluated, and VBL_HYBRID_STORE_LIGHT_COST per light
 * traced into a pass's store, spread over the image's pixels. The weights are in units of about
 * 0.08 us, fitted to CPU time per pass of pt and vrl on the race scenes (bench/results/
 * hybrid_s8.txt); within 2x of the measured vrl / pt cost ratio on each. */
#define VBL_HYBRID_PILOT_PASSES 4
#define VBL_HYBRID_PILOT_GRID 8
#define VBL_HYBRID_MAX_PT_SPP 256
#define VBL_HYBRID_RAY_COST 16.0
#define VBL_HYBRID_SAMPLE_COST 32.0
#define VBL_HYBRID_TREE_NODE_COST 0.8
#define VBL_HYBRID_LIGHT_EVAL_COST 12.0
#define VBL_HYBRID_STORE_LIGHT_COST 150.0
#define VBL_HYBRID_DISCREPANCY_Z 3.0
#define VBL_RNG_DOMAIN_HYBRID 0x4859425249445049ull /* "HYBRIDPI" */
vbl_result vbl_hybrid_pilot(const vbl_render_context* ctx, const vbl_estimator* base, vbl_hybrid_plan* plan);

/* The assignment of the pilot's measurements (pt_classes; bit c: pt owns class c). Per class c:
 * - an estimator with no energy on the grid (energy[c] = sum |mean|) where the other has some does
 *   not get the class (nothing of its variance was seen);
 * - where the two grid totals (sums of the means, in the variances' units) differ by more than
 *   VBL_HYBRID_DISCREPANCY_Z standard errors, the lower one has missed light in samples the pilot
 *   did not draw (a heavy tail), and its variance is raised to what the gap implies (st is updated);
 * - the other classes are assigned so that the sum of the classes' variances at a fixed cost, with
 *   the optimal split of that cost (pt_spp), is least: (sqrt(A C_vl) + sqrt(B c_pt))^2 over all
 *   assignments, A the method's classes' variance per pass, B pt's per sample; an estimator that
 *   owns no class costs nothing. So a class goes to pt only if pt's samples pay for themselves
 *   next to the method's pass, which runs anyway while the method owns anything.
 * Classes without energy in either go to pt when pt owns any class. */
unsigned vbl_hybrid_assign(vbl_hybrid_pilot_stats* st, const double* vl_total, const double* pt_total,
                           const double* vl_energy, const double* pt_energy, int passes, double pt_samples);

/* One hybrid camera sample's value: the method's classes outside pt_classes plus pt_sum / pt_count
 * in pt_classes (pt_count 0: nothing from pt). Every class comes from exactly one of the two. */
void vbl_hybrid_combine(const vbl_sample_value* method, const vbl_sample_value* pt_sum, int pt_count,
                        unsigned pt_classes, vbl_sample_value* out);

/* "pt: surface_direct,volume_from_volume; pt_spp 2 (auto)" into out[size] (the EXR's vbl:hybrid). */
void vbl_hybrid_describe(unsigned pt_classes, int pt_spp, int automatic, char* out, size_t size);

#endif
