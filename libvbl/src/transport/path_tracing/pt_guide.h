/* Adjoint-driven Russian roulette and splitting for pt (option pt.guided_rr; Vorba and Krivanek
 * 2016, "Adjoint-Driven Russian Roulette and Splitting in Light Transport Simulation", sec. 4-5).
 *
 * The cache: a cells^3 grid over the media's bounds of the mean incident radiance at a point (all
 * transport classes summed, RGB, averaged over uniform directions), and an 8x8-block estimate of
 * the pixels' luminance I. Both come from a deterministic pre-pass of unguided pt paths: cell c
 * traces options.pt.guide_paths paths from uniform points of the cell in uniform directions, block
 * b 2 * guide_paths camera paths through uniform points of the block, path k of item i drawing
 * from vbl_rng_make(seed ^ VBL_RNG_DOMAIN_GUIDE, i, k): the cache depends only on (scene, seed,
 * options), never on threads or on which passes a split render runs. Its cost is
 * cells^3 * guide_paths + ceil(w/8) * ceil(h/8) * 2 * guide_paths pt paths (16^3 * 8 = 32768 plus
 * 4096 at 128x128 with the defaults), before the first pass.
 *
 * The decision (at each scattering vertex x after the direction is sampled, path throughput beta,
 * pixel block estimate I): r = Y(beta * L(x)) / I, the expected contribution of the continuation
 * relative to the pixel (the paper's path weight over the weight-window centre, eq. 8 - 9). The
 * window is [2/(1+s), 2s/(1+s)], s = 5 (sec. 5.1): below it the path survives with probability
 * q = max(r, 0.05) and beta /= q; above it it splits into n = min(round(r), cap) copies of beta/n;
 * inside it continues unchanged. Both only reweight, so the estimate stays unbiased for any
 * cache; where the cache knows nothing (outside the grid, a cell or block whose estimate is 0) pt
 * keeps its throughput roulette. */
#ifndef VBL_TRANSPORT_PT_GUIDE_H
#define VBL_TRANSPORT_PT_GUIDE_H

#include "transport/common/estimator.h"

#define VBL_RNG_DOMAIN_GUIDE 0x4755494445525221ull /* the pre-pass: (seed ^ this, item, path) */
#define VBL_PT_GUIDE_BLOCK 8                       /* pixels per side of a pixel-estimate block */
#define VBL_PT_GUIDE_MAX_SPLIT 8                   /* copies at one vertex at most */

typedef struct vbl_pt_guide {
    int cells;               /* per axis */
    vbl_vec3 lo, hi, inv_cell;
    float* radiance;         /* cells^3 RGB: mean incident radiance */
    int blocks_x, blocks_y;
    double* pixel;           /* blocks_x * blocks_y: luminance of the pixels' estimate */
    uint64_t prepass_paths;  /* paths the pre-pass traced */
} vbl_pt_guide;

/* Builds the cache with ctx's scene and options (pt.guide_cells, pt.guide_paths, seed, threads);
 * VBL_ERROR_OUT_OF_MEMORY if it cannot be allocated. *out is NULL on failure. */
vbl_result vbl_pt_guide_build(const vbl_render_context* ctx, vbl_pt_guide** out);
void vbl_pt_guide_free(vbl_pt_guide* guide);

/* Cached mean incident radiance at x (0 outside the grid) and the pixel (px, py)'s estimate. */
vbl_vec3 vbl_pt_guide_radiance(const vbl_pt_guide* g, vbl_vec3 x);
double vbl_pt_guide_pixel(const vbl_pt_guide* g, int px, int py);

/* The roulette/splitting decision for throughput *beta at x in pixel (px, py), at most
 * max_copies copies (>= 1): returns -1 where the cache knows nothing (*beta unchanged; the caller's
 * own roulette applies), 0 to end the path, else the number of copies n, with *beta reweighted
 * (1/q after surviving, 1/n for each of n copies). */
int vbl_pt_guide_decide(const vbl_pt_guide* g, vbl_vec3 x, int px, int py, int max_copies, vbl_rng* rng,
                        vbl_vec3* beta);

#endif
