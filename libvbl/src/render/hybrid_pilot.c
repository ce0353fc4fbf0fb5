/* The auto pilot of render.hybrid (hybrid.h, vbl_hybrid_pilot): per class, the variance x cost of
 * the virtual-light method and of pt on a small pixel grid, and the assignment (vbl_hybrid_assign). */
#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "core/work_count.h"
#include "render/hybrid.h"
#include "transport/path_tracing/pt.h"

/* One pilot pixel's sums over the pilot passes. */
typedef struct vbl_pilot_pixel {
    int px, py;
    double vl_sum[VBL_CLASS_COUNT], vl_sq[VBL_CLASS_COUNT]; /* over passes, of the pass mean (luminance-free: R+G+B) */
    double pt_sum[VBL_CLASS_COUNT], pt_sq[VBL_CLASS_COUNT]; /* over single pt samples */
    double vl_cost, pt_cost; /* cost units (vbl_pilot_cost) over the pilot passes / pt samples */
} vbl_pilot_pixel;

static double vbl_pilot_value(vbl_vec3 v) { return v.x + v.y + v.z; }

/* The camera sample of pixel (px, py) from rng, as the render driver makes it (render.c). */
static void vbl_pilot_camera_sample(const vbl_render_context* ctx, int px, int py, uint32_t index, vbl_rng* rng,
                                    vbl_camera_sample* cs)
{
    memset(cs, 0, sizeof *cs);
    cs->px = px;
    cs->py = py;
    cs->pixel_index = (uint64_t)py * (uint64_t)ctx->scene->camera.width + (uint64_t)px;
    cs->sample_index = index;
    cs->sx = px + vbl_rng_uniform(rng);
    cs->sy = py + vbl_rng_uniform(rng);
    vbl_camera_sample_ray(ctx->scene, cs);
}

/* The pilot's cost count of this thread: density lookups, VBL_HYBRID_RAY_COST per ray cast and the
 * virtual lights' own work (core/work_count.h), weighted (hybrid.h). */
static double vbl_pilot_cost(const vbl_thread_state* ts)
{
    return (double)vbl_extinction_cursor_lookups(&ts->cursor) + VBL_HYBRID_RAY_COST * (double)vbl_surfaces_ray_count() +
           VBL_HYBRID_TREE_NODE_COST * (double)vbl_work_count(VBL_WORK_TREE_NODE) +
           VBL_HYBRID_LIGHT_EVAL_COST * (double)vbl_work_count(VBL_WORK_LIGHT_EVAL);
}

unsigned vbl_hybrid_assign(vbl_hybrid_pilot_stats* st, const double* vl_total, const double* pt_total,
                           const double* vl_energy, const double* pt_energy, int passes, double pt_samples)
{
    const int P = passes;
    const double n_pt = pt_samples;
    /* Both estimators are unbiased, so their grid totals differ only by noise. Where they differ
     * by more than VBL_HYBRID_DISCREPANCY_Z standard errors (as estimated), the lower one has
     * missed light that lies in samples the pilot did not draw (a heavy tail: a rare large sample
     * of a non-negative estimator is what a small sample lacks), so its variance estimate is too
     * low: it is raised to the variance of its total that the gap implies,
     * Var(total) >= d^2 - Var(other total), times its number of pilot passes (vl) or samples (pt). */
    for (int c = 0; c < VBL_CLASS_COUNT; ++c) {
        const double var_v = st->vl_variance[c] / P, var_p = st->pt_variance[c] / n_pt; /* of the totals */
        const double d = vl_total[c] - pt_total[c];
        if (!(d * d > VBL_HYBRID_DISCREPANCY_Z * VBL_HYBRID_DISCREPANCY_Z * (var_v + var_p))) continue;
        if (d > 0.0) st->pt_variance[c] = fmax(st->pt_variance[c], (d * d - var_v) * n_pt);
        else st->vl_variance[c] = fmax(st->vl_variance[c], (d * d - var_p) * P);
    }
    /* classes an estimator must or cannot own: one that found no light where the other did has
     * shown none of its variance there (its light lies in samples the pilot did not draw) */
    unsigned forced_pt = 0, forced_vl = 0, empty = 0;
    for (int c = 0; c < VBL_CLASS_COUNT; ++c) {
        const int v = vl_energy[c] > 0.0, p = pt_energy[c] > 0.0;
        if (!v && p) forced_pt |= 1u << c;
        else if (v && !p) forced_vl |= 1u << c;
        else if (!v && !p) empty |= 1u << c;
    }
    /* every assignment of the other classes: the smallest total variance at a fixed cost with the
     * optimal split of that cost between the two (A / n_vl + B / n_pt at n_vl C_vl + n_pt c_pt = T
     * is least at (sqrt(A C_vl) + sqrt(B c_pt))^2 / T); an estimator that owns no class costs
     * nothing (the method's pass is skipped when pt owns every class) */
    unsigned best = 0;
    double best_score = INFINITY;
    for (unsigned mask = 0; mask <= VBL_HYBRID_ALL_CLASSES; ++mask) {
        if ((mask & forced_pt) != forced_pt || (mask & forced_vl) || (mask & empty)) continue;
        double A = 0.0, B = 0.0;
        for (int c = 0; c < VBL_CLASS_COUNT; ++c) {
            if (mask & (1u << c)) B += st->pt_variance[c];
            else A += st->vl_variance[c];
        }
        const unsigned owned_vl = VBL_HYBRID_ALL_CLASSES & ~mask & ~empty;
        const double a = owned_vl ? sqrt(A * st->vl_cost) : 0.0, b = mask ? sqrt(B * st->pt_cost) : 0.0;
        const double score = (a + b) * (a + b);
        if (score < best_score) { /* strict: of equal scores the first (fewest pt classes) */
            best_score = score;
            best = mask;
        }
    }
    unsigned mask = best;
    if (mask) /* classes without energy in the pilot cost pt nothing more */
        mask |= empty;
    return mask;
}

vbl_result vbl_hybrid_pilot(const vbl_render_context* ctx, const vbl_estimator* base, vbl_hybrid_plan* plan)
{
    const vbl_scene* scene = ctx->scene;
    const int W = scene->camera.width, H = scene->camera.height;
    const int gx = W < VBL_HYBRID_PILOT_GRID ? W : VBL_HYBRID_PILOT_GRID;
    const int gy = H < VBL_HYBRID_PILOT_GRID ? H : VBL_HYBRID_PILOT_GRID;
    const int count = gx * gy, spp = ctx->options.spp, P = VBL_HYBRID_PILOT_PASSES;
    vbl_pilot_pixel* px = calloc((size_t)count, sizeof *px);
    if (!px) return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory (hybrid pilot)", scene->path);
    for (int j = 0; j < gy; ++j)
        for (int i = 0; i < gx; ++i) {
            px[j * gx + i].px = (int)((i + 0.5) * W / gx);
            px[j * gx + i].py = (int)((j + 0.5) * H / gy);
        }
    vbl_render_context pc = *ctx; /* the pilot's own seeds and passes; no time limit */
    pc.options.seed = ctx->options.seed ^ VBL_RNG_DOMAIN_HYBRID;
    pc.options.pt.sampler = VBL_PT_SAMPLER_INDEPENDENT;
    pc.deadline = 0.0;
    pc.skip_classes = 0;
    pc.hybrid = NULL;
    vbl_result r = VBL_SUCCESS;
    uint64_t store_lights = 0; /* lights traced into the pilot passes' stores (core/work_count.h) */
    volatile int stop = 0; /* a cancel seen by any thread (the pilot has no time limit of its own) */
    for (int p = 0; p < P && !r; ++p) {
        pc.pass = (uint32_t)p;
        void* store = NULL;
        const uint64_t w0 = vbl_work_count(VBL_WORK_STORE_LIGHT);
        if ((r = base->pass_begin(&pc, &store))) break;
        store_lights += vbl_work_count(VBL_WORK_STORE_LIGHT) - w0;
#pragma omp parallel num_threads(ctx->threads)
        {
            vbl_thread_state ts;
            memset(&ts, 0, sizeof ts);
            vbl_extinction_cursor_init(&ts.cursor, pc.extinction);
            if (scene->has_emission) vbl_emission_cursor_init(&ts.emission, scene);
#pragma omp for schedule(dynamic, 1)
            for (int k = 0; k < count; ++k) {
                if (stop || vbl_render_stop_requested(&pc)) { /* cancel (SIGINT): skip the rest */
                    stop = 1;
                    continue;
                }
                vbl_pilot_pixel* q = &px[k];
                const uint64_t pixel = (uint64_t)q->py * (uint64_t)W + (uint64_t)q->px;
                vbl_camera_sample cs;
                double mean[VBL_CLASS_COUNT] = {0};
                vbl_rng rng = vbl_rng_make(pc.options.seed, (uint64_t)p, pixel);
                double l0 = vbl_pilot_cost(&ts);
                for (int s = 0; s < spp; ++s) {
                    vbl_sample_value v;
                    memset(&v, 0, sizeof v);
                    vbl_pilot_camera_sample(&pc, q->px, q->py, (uint32_t)(p * spp + s), &rng, &cs);
                    base->camera_sample(&pc, store, &ts, &cs, &rng, &v);
                    for (int c = 0; c < VBL_CLASS_COUNT; ++c) mean[c] += vbl_pilot_value(v.L[c]) / spp;
                }
                double l1 = vbl_pilot_cost(&ts);
                q->vl_cost += l1 - l0;
                for (int c = 0; c < VBL_CLASS_COUNT; ++c) {
                    q->vl_sum[c] += mean[c];
                    q->vl_sq[c] += mean[c] * mean[c];
                }
                vbl_rng prng = vbl_rng_make(pc.options.seed ^ VBL_RNG_DOMAIN_LIGHT, (uint64_t)p, pixel);
                for (int s = 0; s < spp; ++s) {
                    vbl_sample_value v;
                    memset(&v, 0, sizeof v);
                    vbl_pilot_camera_sample(&pc, q->px, q->py, (uint32_t)(p * spp + s), &prng, &cs);
                    vbl_pt_camera_sample(&pc, NULL, &ts, &cs, &prng, &v);
                    for (int c = 0; c < VBL_CLASS_COUNT; ++c) {
                        double x = vbl_pilot_value(v.L[c]);
                        q->pt_sum[c] += x;
                        q->pt_sq[c] += x * x;
                    }
                }
                q->pt_cost += vbl_pilot_cost(&ts) - l1;
            }
        }
        if (base->pass_end) base->pass_end(&pc, store);
        if (stop || vbl_render_stop_requested(&pc) || (pc.stop_latch && *pc.stop_latch))
            r = vbl_error(VBL_ERROR_INTERRUPTED, "%s: render stopped during the hybrid pilot", scene->path);
    }
    if (r) {
        free(px);
        return r;
    }
    /* Per class, the sum over the grid of each pixel's variance, in units of the grid's squared mean
     * beauty. Absolute, not per-pixel relative, variances: the error that counts is the image's
     * (rMAE sums absolute errors over pixels), and the plain sum of sample variances is an unbiased
     * estimate of the sum of variances even where an estimator's variance lies in rare large
     * samples that miss most pixels (a per-pixel sigma or relative variance is then biased low
     * where no rare sample fell). */
    const double n_pt = (double)P * spp;
    double grid_mean = 0.0;
    for (int k = 0; k < count; ++k)
        for (int c = 0; c < VBL_CLASS_COUNT; ++c) grid_mean += 0.5 * (px[k].vl_sum[c] / P + px[k].pt_sum[c] / n_pt);
    grid_mean /= count;
    const double norm = grid_mean * grid_mean + 1e-300;
    vbl_hybrid_pilot_stats* st = &plan->pilot;
    memset(st, 0, sizeof *st);
    double vl_energy[VBL_CLASS_COUNT] = {0}, pt_energy[VBL_CLASS_COUNT] = {0};
    double vl_total[VBL_CLASS_COUNT] = {0}, pt_total[VBL_CLASS_COUNT] = {0}; /* grid sums of the means */
    double vl_cost = 0, pt_cost = 0;
    for (int k = 0; k < count; ++k) { /* in pixel order: the same sums at any thread count */
        const vbl_pilot_pixel* q = &px[k];
        for (int c = 0; c < VBL_CLASS_COUNT; ++c) {
            double mv = q->vl_sum[c] / P, mp = q->pt_sum[c] / n_pt;
            double vv = fmax(0.0, (q->vl_sq[c] - P * mv * mv) / (P - 1));
            double vp = fmax(0.0, (q->pt_sq[c] - n_pt * mp * mp) / (n_pt - 1));
            st->vl_variance[c] += vv / norm;
            st->pt_variance[c] += vp / norm;
            vl_energy[c] += fabs(mv);
            pt_energy[c] += fabs(mp);
            vl_total[c] += mv / sqrt(norm); /* in the variances' units; finite on a black grid */
            pt_total[c] += mp / sqrt(norm);
        }
        vl_cost += q->vl_cost;
        pt_cost += q->pt_cost;
    }
    free(px);
    /* a pass's store (light tracing, tree build) is shared by every pixel of the image */
    st->vl_cost = vl_cost / ((double)P * count) + VBL_HYBRID_SAMPLE_COST * spp +
                  VBL_HYBRID_STORE_LIGHT_COST * (double)store_lights / ((double)P * W * H);
    st->pt_cost = pt_cost / (n_pt * count) + VBL_HYBRID_SAMPLE_COST;
    const unsigned mask = vbl_hybrid_assign(st, vl_total, pt_total, vl_energy, pt_energy, P, n_pt);
    double A = 0.0, B = 0.0;
    for (int c = 0; c < VBL_CLASS_COUNT; ++c) {
        if (mask & (1u << c)) B += st->pt_variance[c];
        else A += st->vl_variance[c];
    }
    int pt_spp = 1;
    if (mask && mask != VBL_HYBRID_ALL_CLASSES && A > 0.0 && B > 0.0) {
        double ratio = sqrt(B * st->vl_cost / (A * st->pt_cost)) / spp; /* pt samples per method sample */
        pt_spp = ratio < 1.0 ? 1 : (ratio > VBL_HYBRID_MAX_PT_SPP ? VBL_HYBRID_MAX_PT_SPP : (int)floor(ratio + 0.5));
    }
    plan->pt_classes = mask;
    plan->pt_spp = pt_spp;
    return VBL_SUCCESS;
}
