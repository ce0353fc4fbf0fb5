/* Transmittance estimators over an extinction field, all driven by one free-flight loop over the
 * merged majorant segments (pbrt-v4 `SampleT_maj` style): tentative collisions are drawn with rate
 * mu = majorant (or majorant - minorant for residual tracking) segment by segment, and each
 * estimator reacts to them:
 *  - delta tracking (Woodcock): stop with T = 0 at a real collision, probability sigma_t / mu;
 *  - ratio tracking (Novak et al. 2014, eq. 6): T = prod (1 - sigma_t / mu);
 *  - residual ratio tracking (Novak et al. 2014, eq. 11), control = segment minorant sigma_c:
 *    T = exp(-sigma_c len) * prod (1 - (sigma_t - sigma_c) / (mu - sigma_c)); or (residual_mid)
 *    control = the mid-bound c = (max + min) / 2 with rate mu_r = (max - min) / 2, which bounds
 *    |sigma_t - c|, so the factors lie in [0, 2]: T = exp(-c len) prod (1 - (sigma_t - c) / mu_r),
 *    unbiased for any constant c and any mu_r >= |sigma_t - c| (Novak et al. 2014, sec. 5.2, eq. 11
 *    with a two-sided residual). Its relative variance over a segment, exp(int r^2 / mu_r) - 1 with
 *    r = sigma_t - c, at a cost of mu_r len lookups: the work x variance product ~ int r^2, which the
 *    mid-bound cuts 4x against the minorant for sigma_t spread evenly over [min, max], at half
 *    the lookups (docs/readme/sampling.md "Shadow-ray transmittance");
 *  - ray marching (biased): T = exp(-sum sigma_t(t_k) dt), jittered regular steps.
 * Segments whose rate is 0 cost no lookup. Ratio estimators apply Russian roulette once the weight
 * falls below VBL_RR_THRESHOLD (survive with probability w / threshold, weight := threshold):
 * unbiased, and it bounds the work in dense media; vbl_tracking_settings.rr_threshold lowers it
 * (an estimate of T below the threshold is 0 or >= threshold, relative variance ~ threshold / T:
 * the virtual-light estimators, whose camera and connection transmittances multiply, ask for less).
 *
 * Homogeneous segments (majorant == minorant > 0: every trilinear sample in the block, neighbour
 * shell included, is the same value sigma, e.g. the inside of a constant-density box) use the
 * closed form and cost no lookup: transmittance estimators multiply by exp(-sigma len) exactly
 * (delta, ratio and residual alike; ray marching adds sigma len to the optical depth), and
 * free-flight sampling draws the collision analytically, t = t0 - log(1 - u) / sigma, which is
 * exactly delta tracking's law there (with mu = sigma every tentative collision is real). The
 * per-component sigma_t at such a collision is the block value for one medium and one lookup for
 * several. The ratio-tracking cache (a step function) uses ratio tracking with the free
 * majorant 4 sigma there: no lookups, relative variance exp(sigma len / 4) - 1. (For several
 * overlapping media the equality is of the summed bounds, so a component could vary by at most
 * an ulp of the sum: below double precision of T.) */
#include "volume/transmittance.h"

#include <float.h>
#include <math.h>

#include "volume/transmittance_cache.h"
#include "volume/transmittance_unbiased_march.h"

#define VBL_RR_THRESHOLD 0.1
/* Majorant factor of the ratio-tracking cache in homogeneous segments (see vbl_ratio_track_record). */
#define VBL_HOMOGENEOUS_RATIO_K 4.0

enum { VBL_TRACK_CONTINUE = 0, VBL_TRACK_STOP = 1 };

typedef struct vbl_tracker {
    vbl_transmittance_estimator kind; /* DELTA, RATIO or RESIDUAL */
    double weight;
    double t_stop, sigma_stop;
    vbl_rng* rng;
    int sampling; /* 1: free-flight sampling (a real collision must be produced, not a weight) */
    double mu_scale; /* > 1: tentative collisions at this multiple of the majorant (estimates only) */
    vbl_tracking_visit visit; /* free flight only, may be NULL: called at every tentative point */
    void* visit_user;
    double rr;    /* Russian-roulette threshold of the ratio estimators */
    int residual_mid; /* residual tracking's control: 1 the mid-bound, 0 the minorant */
    /* free flight only (vbl_free_flight_sample_pattern): a caller's uniforms (< 0: none left) for
     * the first optical depth and for the real/null decisions, recycled from one decision to
     * the next while u_decide_gain (the remainders' magnification) stays small */
    double u_depth, u_decide, u_decide_gain;
} vbl_tracker;

/* Past this magnification of the recycled decision uniform (2^20 of its 53 bits used up), the
 * stream takes over. */
#define VBL_DECIDE_GAIN_MAX 1048576.0

/* The uniform of delta tracking's real/null decision with probability p of real: the caller's
 * while it has one, then the stream. After a null decision the remainder (u - p) / (1 - p) is
 * uniform on [0, 1) again and independent of everything before given the null outcome, so the
 * next decision takes it: one stratified uniform decides which tentative collision is the real
 * one (larger u, a later collision). */
static inline int vbl_tracker_real(vbl_tracker* tr, double p)
{
    if (!(tr->u_decide >= 0.0)) return vbl_rng_uniform(tr->rng) < p;
    const double u = tr->u_decide;
    tr->u_decide = -1.0;
    if (u < p) return 1;
    if (p < 1.0) {
        double r = p > 0.0 ? (u - p) / (1.0 - p) : u;
        tr->u_decide_gain /= 1.0 - (p > 0.0 ? p : 0.0);
        if (r >= 0.0 && r < 1.0 && tr->u_decide_gain < VBL_DECIDE_GAIN_MAX) tr->u_decide = r;
    }
    return 0;
}

/* The caller's uniform for the next optical depth, if the flight needs one and has it. */
static inline void vbl_tracker_depth(vbl_tracker* tr, double* tau)
{
    if (!(*tau >= 0.0) && tr->u_depth >= 0.0) {
        *tau = -log1p(-tr->u_depth);
        tr->u_depth = -1.0;
    }
}

/* The roulette threshold of a settings value (0: VBL_RR_THRESHOLD). */
static inline double vbl_rr_of(double rr) { return rr > 0.0 && rr <= 1.0 ? rr : VBL_RR_THRESHOLD; }

/* A segment of constant, known extinction (see above). */
static inline int vbl_segment_homogeneous(const vbl_majorant_segment* seg)
{
    return seg->majorant > 0.0 && seg->majorant == seg->minorant;
}

/* Russian roulette of the ratio estimators on a small weight (shared by the closed form). */
static int vbl_tracker_roulette(vbl_tracker* tr)
{
    if (tr->weight <= 0.0) {
        tr->weight = 0.0;
        return VBL_TRACK_STOP;
    }
    if (tr->kind != VBL_TRANSMITTANCE_DELTA_TRACKING && tr->weight < tr->rr) {
        double survive = tr->weight / tr->rr;
        if (vbl_rng_uniform(tr->rng) >= survive) {
            tr->weight = 0.0;
            return VBL_TRACK_STOP;
        }
        tr->weight = tr->rr;
    }
    return VBL_TRACK_CONTINUE;
}

/* Reacts to a tentative collision at t with sigma_t, sampled with rate mu over control sigma_c. */
static int vbl_tracker_event(vbl_tracker* tr, double sigma_t, double mu, double sigma_c)
{
    double p = (sigma_t - sigma_c) / mu; /* in [0, 1] for true bounds, [-1, 1] for the mid-bound control */
    if (tr->kind == VBL_TRANSMITTANCE_DELTA_TRACKING) {
        if (vbl_tracker_real(tr, p)) {
            tr->weight = 0.0;
            return VBL_TRACK_STOP;
        }
        return VBL_TRACK_CONTINUE;
    }
    double f = 1.0 - p;
    if (f < 0.0) f = 0.0; /* sigma_t above a true bound only by float rounding of the lerp */
    tr->weight *= f;
    if (tr->weight <= 0.0) {
        tr->weight = 0.0;
        return VBL_TRACK_STOP;
    }
    if (tr->weight < tr->rr) {
        double survive = tr->weight / tr->rr;
        if (vbl_rng_uniform(tr->rng) >= survive) {
            tr->weight = 0.0;
            return VBL_TRACK_STOP;
        }
        tr->weight = tr->rr;
    }
    return VBL_TRACK_CONTINUE;
}

/* Weight above which the mid-bound's late control is folded in (vbl_track). */
#define VBL_LATE_CONTROL_FOLD 1e100

/* The shared free-flight loop. Returns VBL_TRACK_STOP if the tracker stopped, else CONTINUE. */
static int vbl_track(const vbl_extinction* ext, vbl_extinction_cursor* cursor, vbl_vec3 origin, vbl_vec3 direction,
                     double t0, double t1, int use_global, vbl_tracker* tr, double* per_component)
{
    vbl_extinction_iter iter;
    vbl_majorant_segment seg;
    const int residual = tr->kind == VBL_TRANSMITTANCE_RESIDUAL_RATIO_TRACKING;
    double tau = -1.0; /* carried optical depth to the next tentative collision (vbl_exp_carry_step) */
    vbl_extinction_iter_init(&iter, ext, origin, direction, t0, t1, use_global);
    while (vbl_extinction_iter_next(&iter, &seg)) {
        if (vbl_segment_homogeneous(&seg)) {
            const double sigma = seg.majorant;
            if (tr->sampling) { /* analytic exponential free flight */
                double t = seg.t0;
                vbl_tracker_depth(tr, &tau);
                if (!vbl_exp_carry_step(&tau, &t, seg.t1, sigma, tr->rng)) continue;
                tr->t_stop = t;
                tr->sigma_stop = sigma;
                tr->weight = 0.0;
                if (per_component) {
                    if (ext->count == 1) per_component[0] = sigma;
                    else vbl_extinction_eval(ext, cursor, vbl_v3_madd(origin, direction, t), per_component);
                }
                /* the analytic flight draws only the real collision: its own majorant is sigma */
                if (tr->visit) tr->visit(tr->visit_user, vbl_v3_madd(origin, direction, t), sigma, per_component);
                return VBL_TRACK_STOP;
            }
            tr->weight *= exp(-sigma * (seg.t1 - seg.t0));
            if (vbl_tracker_roulette(tr) == VBL_TRACK_STOP) return VBL_TRACK_STOP;
            continue;
        }
        double sigma_c = residual ? seg.minorant : 0.0;
        double mu = seg.majorant - sigma_c;
        if (residual && tr->residual_mid) {
            sigma_c = 0.5 * (seg.majorant + seg.minorant);
            mu = fmax(seg.majorant - sigma_c, sigma_c - seg.minorant); /* = (max - min) / 2 up to rounding */
        }
        if (tr->mu_scale > 1.0) mu *= tr->mu_scale;
        /* The control's exp(-sigma_c len): the minorant's at the segment start (its factors are
         * <= 1); the mid-bound's at the segment end, after the factors (some > 1) it may
         * compensate, so the roulette does not act on a weight the segment will raise again. */
        const int control_late = residual && tr->residual_mid;
        if (residual && sigma_c > 0.0 && !control_late) {
            tr->weight *= exp(-sigma_c * (seg.t1 - seg.t0));
            if (!(tr->weight > 0.0)) { /* underflow: T is 0 to double precision */
                tr->weight = 0.0;
                return VBL_TRACK_STOP;
            }
        }
        if (!(mu > 0.0)) {
            if (control_late && sigma_c > 0.0) { /* exactly known: the closed form alone */
                tr->weight *= exp(-sigma_c * (seg.t1 - seg.t0));
                if (vbl_tracker_roulette(tr) == VBL_TRACK_STOP) return VBL_TRACK_STOP;
            }
            continue; /* empty (or exactly known) segment: no lookups */
        }
        double t = seg.t0, t_control = seg.t0; /* the late control covers [t_control, t1] */
        for (;;) {
            /* a pattern's uniform for the next depth (free flight): the same law as the step's own */
            vbl_tracker_depth(tr, &tau);
            if (!vbl_exp_carry_step(&tau, &t, seg.t1, mu, tr->rng)) break;
            double sigma_t = vbl_extinction_eval(ext, cursor, vbl_v3_madd(origin, direction, t), per_component);
            if (tr->visit) tr->visit(tr->visit_user, vbl_v3_madd(origin, direction, t), mu, per_component);
            if (vbl_tracker_event(tr, sigma_t, mu, sigma_c) == VBL_TRACK_STOP) {
                tr->t_stop = t;
                tr->sigma_stop = sigma_t;
                return VBL_TRACK_STOP;
            }
            /* The mid-bound's factors (up to 2 each) can overflow over thousands of events in a
             * dense segment before the late control exp(-sigma_c len) compensates (inf x 0 = NaN):
             * fold the control of [t_control, t] in first. The same product, regrouped. */
            if (control_late && tr->weight > VBL_LATE_CONTROL_FOLD) {
                tr->weight *= exp(-sigma_c * (t - t_control));
                t_control = t;
                if (vbl_tracker_roulette(tr) == VBL_TRACK_STOP) return VBL_TRACK_STOP;
            }
        }
        if (control_late && sigma_c > 0.0) {
            tr->weight *= exp(-sigma_c * (seg.t1 - t_control));
            if (vbl_tracker_roulette(tr) == VBL_TRACK_STOP) return VBL_TRACK_STOP;
        }
    }
    return VBL_TRACK_CONTINUE;
}

/* Step (ray parameter) of about one voxel along the ray for the finest component. */
static double vbl_adaptive_march_step(const vbl_extinction* ext, vbl_vec3 direction)
{
    double step = INFINITY;
    for (int c = 0; c < ext->count; ++c) {
        const vbl_medium_component* m = &ext->components[c];
        vbl_vec3 d = vbl_affine_vector(&m->volume->world_to_index, vbl_affine_vector(&m->scene_to_volume, direction));
        double len = vbl_v3_length(d); /* voxels per unit t */
        if (len > 0.0 && 1.0 / len < step) step = 1.0 / len;
    }
    return step;
}

/* Ray marching: points t0 + (k + u) h, u ~ U[0,1) shared by the whole ray, evaluated only inside
 * segments with a non-zero majorant; E[h sum sigma] = optical depth (only exp() adds bias). */
static double vbl_ray_march(const vbl_extinction* ext, vbl_extinction_cursor* cursor, vbl_vec3 origin,
                            vbl_vec3 direction, double t0, double t1, const vbl_tracking_settings* s, vbl_rng* rng)
{
    double h = s->march_step > 0.0 ? s->march_step : vbl_adaptive_march_step(ext, direction);
    if (!(h > 0.0) || !isfinite(h)) return 1.0;
    if (h < (t1 - t0) * 1e-7) h = (t1 - t0) * 1e-7; /* at most 1e7 steps per ray (documented) */
    double u = vbl_rng_uniform(rng);
    double tau = 0.0;
    vbl_extinction_iter iter;
    vbl_majorant_segment seg;
    vbl_extinction_iter_init(&iter, ext, origin, direction, t0, t1, s->use_global_majorant);
    while (vbl_extinction_iter_next(&iter, &seg)) {
        if (!(seg.majorant > 0.0)) continue;
        if (vbl_segment_homogeneous(&seg)) { /* exact optical depth, no lookups */
            tau += seg.majorant * (seg.t1 - seg.t0);
            continue;
        }
        double k = ceil((seg.t0 - t0) / h - u);
        if (k < 0.0) k = 0.0;
        for (;; k += 1.0) {
            double t = t0 + (k + u) * h;
            if (t < seg.t0) continue; /* rounding at the segment start */
            if (t >= seg.t1) break;
            tau += h * vbl_extinction_eval(ext, cursor, vbl_v3_madd(origin, direction, t), NULL);
        }
    }
    return exp(-tau);
}

/* The estimators work with a unit direction, so optical depth is per world unit along the ray
 * whatever the caller's parameterization: t' = t |d|. Returns 0 for a zero/non-finite direction
 * (no distance is travelled: T = 1). */
int vbl_unit_ray(vbl_vec3* direction, double* t0, double* t1, double* len)
{
    double l = vbl_v3_length(*direction);
    if (!(l > 0.0) || !isfinite(l)) return 0;
    *direction = vbl_v3_scale(*direction, 1.0 / l);
    *t0 *= l;
    *t1 *= l;
    *len = l;
    return 1;
}

double vbl_transmittance_estimate(const vbl_extinction* ext, vbl_extinction_cursor* cursor, vbl_vec3 origin,
                                  vbl_vec3 direction, double t0, double t1, const vbl_tracking_settings* settings,
                                  vbl_rng* rng)
{
    double len;
    if (!(t1 > t0) || !vbl_unit_ray(&direction, &t0, &t1, &len)) return 1.0;
    if (settings->unbiased_march) {
        vbl_unbiased_march_params p =
            settings->unbiased_march >= 2
                ? vbl_unbiased_march_adaptive(settings->majorant_scale, settings->unbiased_march == 3)
                : vbl_unbiased_march_defaults(settings->majorant_scale);
        p.offset_count = settings->march_offsets;
        for (int b = 0; b < VBL_UNBIASED_MARCH_OFFSETS; ++b) p.offsets[b] = settings->march_offset[b];
        return vbl_transmittance_unbiased_march(ext, cursor, origin, direction, t0, t1, settings->use_global_majorant,
                                                &p, rng);
    }
    switch (settings->estimator) {
    case VBL_TRANSMITTANCE_RAY_MARCHING:
        return vbl_ray_march(ext, cursor, origin, direction, t0, t1, settings, rng);
    case VBL_TRANSMITTANCE_CACHED_DELTA:
    case VBL_TRANSMITTANCE_CACHED_RATIO: {
        vbl_transmittance_cache cache;
        vbl_transmittance_cache_build_rr(&cache, settings->estimator, ext, cursor, origin, direction, t0, t1, 0,
                                         settings->use_global_majorant, settings->rr_threshold, rng);
        return vbl_transmittance_cache_eval(&cache, t1);
    }
    case VBL_TRANSMITTANCE_DELTA_TRACKING:
    case VBL_TRANSMITTANCE_RATIO_TRACKING:
    case VBL_TRANSMITTANCE_RESIDUAL_RATIO_TRACKING:
    default: {
        vbl_tracker tr = {settings->estimator, 1.0, 0.0, 0.0, rng, 0, settings->majorant_scale, NULL, NULL,
                          vbl_rr_of(settings->rr_threshold), settings->residual_mid, -1.0, -1.0, 1.0};
        if (tr.kind > VBL_TRANSMITTANCE_RESIDUAL_RATIO_TRACKING) tr.kind = VBL_TRANSMITTANCE_RATIO_TRACKING;
        vbl_track(ext, cursor, origin, direction, t0, t1, settings->use_global_majorant, &tr, NULL);
        return tr.weight;
    }
    }
}

int vbl_free_flight_sample_pattern(const vbl_extinction* ext, vbl_extinction_cursor* cursor, vbl_vec3 origin,
                                   vbl_vec3 direction, double t0, double t1, int use_global_majorant, vbl_rng* rng,
                                   const double* u, double* t_collision, double* sigma_t_at,
                                   double* per_component, vbl_tracking_visit visit, void* visit_user)
{
    double len;
    if (!(t1 > t0) || !vbl_unit_ray(&direction, &t0, &t1, &len)) return 0;
    vbl_tracker tr = {VBL_TRANSMITTANCE_DELTA_TRACKING, 1.0, 0.0, 0.0, rng, 1, 1.0, visit, visit_user, VBL_RR_THRESHOLD,
                      0, u ? u[0] : -1.0, u ? u[1] : -1.0, 1.0};
    if (vbl_track(ext, cursor, origin, direction, t0, t1, use_global_majorant, &tr, per_component) != VBL_TRACK_STOP)
        return 0;
    if (t_collision) *t_collision = fmin(tr.t_stop / len, t1 / len);
    if (sigma_t_at) *sigma_t_at = tr.sigma_stop;
    return 1;
}

int vbl_free_flight_sample(const vbl_extinction* ext, vbl_extinction_cursor* cursor, vbl_vec3 origin,
                           vbl_vec3 direction, double t0, double t1, int use_global_majorant, vbl_rng* rng,
                           double* t_collision, double* sigma_t_at, double* per_component)
{
    return vbl_free_flight_sample_pattern(ext, cursor, origin, direction, t0, t1, use_global_majorant, rng, NULL,
                                          t_collision, sigma_t_at, per_component, NULL, NULL);
}

int vbl_free_flight_sample_visit(const vbl_extinction* ext, vbl_extinction_cursor* cursor, vbl_vec3 origin,
                                 vbl_vec3 direction, double t0, double t1, int use_global_majorant, vbl_rng* rng,
                                 double* t_collision, double* sigma_t_at, double* per_component,
                                 vbl_tracking_visit visit, void* visit_user)
{
    return vbl_free_flight_sample_pattern(ext, cursor, origin, direction, t0, t1, use_global_majorant, rng, NULL,
                                          t_collision, sigma_t_at, per_component, visit, visit_user);
}

/* Internal (transmittance_cache.c): one ratio-tracking pass that reports every tentative point;
 * the ray must have a unit direction (vbl_unit_ray). */
int vbl_ratio_track_record(const vbl_extinction* ext, vbl_extinction_cursor* cursor, vbl_vec3 origin,
                           vbl_vec3 direction, double t0, double t1, int use_global, double rr_threshold, vbl_rng* rng,
                           void (*record)(void* user, double t, double weight), void* user, int max_records)
{
    vbl_extinction_iter iter;
    vbl_majorant_segment seg;
    vbl_tracker tr = {VBL_TRANSMITTANCE_RATIO_TRACKING, 1.0, 0.0, 0.0, rng, 0, 1.0, NULL, NULL, vbl_rr_of(rr_threshold), 0,
                      -1.0, -1.0, 1.0};
    int records = 0;
    double t_last = t0, tau = -1.0; /* carried optical depth (vbl_exp_carry_step) */
    vbl_extinction_iter_init(&iter, ext, origin, direction, t0, t1, use_global);
    while (vbl_extinction_iter_next(&iter, &seg)) {
        double mu = seg.majorant;
        if (!(mu > 0.0)) continue;
        if (vbl_segment_homogeneous(&seg)) {
            /* Known sigma: ratio tracking with a free, larger majorant mu' = k sigma (no lookups):
             * each tentative point multiplies by 1 - 1/k, unbiased (E = exp(-sigma len)) with
             * relative variance exp(sigma len / k) - 1 instead of exp(sigma len) - 1 for the
             * tight majorant (a 0/1 step). A step function cannot hold exp(-sigma t) itself. */
            const double mu_free = VBL_HOMOGENEOUS_RATIO_K * mu;
            double t = seg.t0;
            while (vbl_exp_carry_step(&tau, &t, seg.t1, mu_free, rng)) {
                if (records == max_records) {
                    double d;
                    if (vbl_free_flight_sample(ext, cursor, origin, direction, t_last, t1, use_global, rng, &d, NULL,
                                               NULL))
                        record(user, d, 0.0);
                    return records + 1;
                }
                int stop = vbl_tracker_event(&tr, mu, mu_free, 0.0);
                record(user, t, tr.weight);
                records++;
                t_last = t;
                if (stop == VBL_TRACK_STOP) return records;
            }
            continue;
        }
        double t = seg.t0;
        while (vbl_exp_carry_step(&tau, &t, seg.t1, mu, rng)) {
            if (records == max_records) {
                /* Out of room: the rest of the ray is covered by one delta-tracking distance d
                 * drawn afresh from the last recorded point (the Poisson process after it is
                 * independent of the stored product; the point just drawn is discarded), so
                 * T(t) ~ w_last * 1[d > t] stays unbiased for every t. */
                double d;
                if (vbl_free_flight_sample(ext, cursor, origin, direction, t_last, t1, use_global, rng, &d, NULL, NULL))
                    record(user, d, 0.0);
                return records + 1;
            }
            double sigma_t = vbl_extinction_eval(ext, cursor, vbl_v3_madd(origin, direction, t), NULL);
            int stop = vbl_tracker_event(&tr, sigma_t, mu, 0.0);
            record(user, t, tr.weight);
            records++;
            t_last = t;
            if (stop == VBL_TRACK_STOP) return records;
        }
    }
    return records;
}
