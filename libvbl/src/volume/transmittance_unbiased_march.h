/* Unbiased ray-marching transmittance (Kettunen, d'Eon, Pantaleoni and Novak 2021, "An Unbiased
 * Ray-Marching Transmittance Estimator", secs. 3-5): T = exp(-tau) expanded as a power series
 * around a control optical depth tau_c, each factor an independent stratified (jittered) marched
 * estimate of tau, the series cut by Russian roulette, one series per block of bounded bound
 * width (bounded variance at any depth). Unbiased, finite, and it may be negative
 * (documented in docs/readme/sampling.md "Shadow-ray transmittance"). */
#ifndef VBL_VOLUME_TRANSMITTANCE_UNBIASED_MARCH_H
#define VBL_VOLUME_TRANSMITTANCE_UNBIASED_MARCH_H

#include "core/rng.h"
#include "volume/extinction.h"

/* Points per unit of a segment's residual optical depth (majorant - minorant) / 2 x length: the
 * march's density (default of vbl_unbiased_march_params.rate; measured in
 * bench/results/shadow_tx_issue14.txt). */
#define VBL_UNBIASED_MARCH_RATE 4.0
/* Most points of one marched estimate in one majorant segment (bounds the work in dense media;
 * the estimate stays unbiased, only its variance grows). */
#define VBL_UNBIASED_MARCH_MAX_POINTS 32
/* Most bound width sum (majorant - minorant) / 2 x length of one block (one power series): the
 * series' terms stay below ~exp(2 x this) at any optical depth (transmittance_unbiased_march.c). */
#define VBL_UNBIASED_MARCH_BLOCK_DEPTH 1.0
/* The running estimate's roulette threshold (params.rr_threshold = 0): low, so that a camera
 * vertex's light through a thick medium keeps its precision. */
#define VBL_UNBIASED_MARCH_RR 1e-4

/* Most blocks of one ray whose first factor march takes a given offset (params.offsets). */
#define VBL_UNBIASED_MARCH_OFFSETS 2

typedef struct vbl_unbiased_march_params {
    double rate;       /* > 0: points per unit residual optical depth of the factors' marches */
    double pilot_rate; /* > 0: the same for the control's (pilot) march */
    int max_points;    /* >= 1: per segment and estimate */
    double theta;      /* > 0: roulette scale: after factor k continue with min(1, |D_k| / (theta (k + 1))) */
    double block_depth; /* > 0: most bound width of one block (VBL_UNBIASED_MARCH_BLOCK_DEPTH) */
    /* Adaptive march (session 6; 0 in older initializers: the classic march above). A block whose
     * bound width sum (max - min) / 2 x len is below pilot_min_bound takes the deterministic
     * mid-bound control (no pilot march); block_strata 1 stratifies a march's points over the whole
     * block in the residual-depth coordinate (ceil(rate x bound) points per block, importance
     * sampled by the pieces' radii) instead of ceil(rate r len) per piece. */
    double pilot_min_bound;
    int block_strata;
    /* (0, 1]: Russian roulette on the running estimate W once |W| falls below this (survive with
     * |W| / rr_threshold, carry W = +-rr_threshold); 0 (older initializers): VBL_UNBIASED_MARCH_RR */
    double rr_threshold;
    /* offset_count > 0: the first factor march (D_1, the term that carries the estimate's noise
     * to first order) of the ray's first offset_count blocks places its block strata
     * systematically at (j + offsets[b]) h for block b instead of one jittered number per stratum
     * (block_strata marches only; the sparse case m < 1 keeps its point where offsets[b] < m, at
     * offsets[b] / m). With the offsets independent and uniform in [0, 1) the estimate stays
     * unbiased (the blocks' factors stay independent, as their product needs); drawn from a
     * low-discrepancy sequence over a pixel's samples (pt.sobol_shadow_march), the nearly equal
     * shadow rays of one pixel stratify each other's marches. 0 (older initializers): jittered. */
    int offset_count;
    double offsets[VBL_UNBIASED_MARCH_OFFSETS];
} vbl_unbiased_march_params;

/* The defaults (rate = pilot_rate = VBL_UNBIASED_MARCH_RATE x `scale` for scale > 1, else x 1). */
vbl_unbiased_march_params vbl_unbiased_march_defaults(double scale);

/* Adaptive march: block-wide strata, and at a deep vertex (`deep` 1: the shadow ray of a path
 * vertex after the first scattering event) the rate VBL_UNBIASED_MARCH_DEEP_RATE instead of
 * VBL_UNBIASED_MARCH_RATE (measured in bench/results/umarch_s6.txt). VBL_UNBIASED_MARCH_PILOT_MIN
 * is its pilot_min_bound: 0, a pilot in every block (skipping it below a bound width of 0.1-0.5
 * saved lookups but raised the smoky room's volume_from_volume error 1.2x: the mid-bound is a
 * poor control where the majorant bounds are loose). */
#define VBL_UNBIASED_MARCH_PILOT_MIN 0.0
#define VBL_UNBIASED_MARCH_DEEP_RATE 2.0
/* ... and at a deep vertex the roulette threshold VBL_UNBIASED_MARCH_DEEP_RR instead of
 * VBL_UNBIASED_MARCH_RR: a deep vertex's shadow ray through a thick medium no longer marches to
 * the medium's exit once its estimate is below 0.05 (session 10, bench/results/pt_deep_rr_s10.txt:
 * the dense cloud's error at equal CPU 0.90x, the pass 1.2x cheaper; thin media unchanged). */
#define VBL_UNBIASED_MARCH_DEEP_RR 0.05
vbl_unbiased_march_params vbl_unbiased_march_adaptive(double scale, int deep);

/* One estimate of T(t0, t1) along origin + t direction; `direction` must be unit
 * (vbl_unit_ray). Deterministic per rng stream; counts its lookups in the cursor. */
double vbl_transmittance_unbiased_march(const vbl_extinction* ext, vbl_extinction_cursor* cursor, vbl_vec3 origin,
                                        vbl_vec3 direction, double t0, double t1, int use_global_majorant,
                                        const vbl_unbiased_march_params* params, vbl_rng* rng);

#endif
