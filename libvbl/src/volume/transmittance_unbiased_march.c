/* Unbiased ray-marching transmittance (Kettunen, d'Eon, Pantaleoni and Novak 2021, "An Unbiased
 * Ray-Marching Transmittance Estimator"; sec. 3 the power-series expansion around a control,
 * sec. 4 the randomized truncation, sec. 5 the marched factors). Our derivation:
 *
 *   T = exp(-tau) = exp(-tau_c) exp(tau_c - tau) = exp(-tau_c) sum_k (tau_c - tau)^k / k!
 *
 * for any constant tau_c. With X_1, X_2, ... independent unbiased estimates of tau (and of each
 * other and of tau_c), E[prod_{j<=k} (tau_c - X_j)] = (tau_c - tau)^k, so with a random order N
 *
 *   T_hat = exp(-tau_c) [1 + sum_{k=1}^{N} prod_{j<=k} D_j / (k! P(N >= k))],  D_j = tau_c - X_j,
 *
 * is unbiased whenever P(N >= k) > 0 for every k whose term can be non-zero.
 *
 * Blocks (bounded variance by construction). The ray's majorant segments are cut into blocks of
 * bound width sum (max - min) / 2 len <= B (params.block_depth, default 1; a segment wider than B
 * is split), and T = prod_b T_b is estimated by the product of independent per-block series
 * (unbiased: independent factors; the cuts depend on the majorants only). Within a block every
 * factor's |D_j| is at most 2 B plus 1 / rate per sparse piece (below), so the series' terms are
 * bounded by ~exp(2 B) whatever the optical depth; one series over a deep, wide-bound ray (the
 * sigma_t 30 box of test_transport_dense: 30 units of bound width in one segment) had products
 * of D_j ~ e^30 and a heavy tail. Homogeneous segments (min == max) are exact factors. Per block:
 *  - the control tau_c is a marched estimate X_0 (a pilot) independent of the factors, clamped
 *    to the block's deterministic bounds, so exp(-tau_c) <= 1 and T_b's estimate is unbiased
 *    conditionally on it; to first order T_hat = T (1 - e_1), e_1 = X_1 - tau;
 *  - N >= 1; after factor k the series continues with probability q_k = min(1, |D_k| /
 *    (theta (k + 1))), and at most 1/2 from order VBL_UM_ORDER_HALF on (Russian roulette on the
 *    series, a stopping time of the factors drawn: unbiased, N finite almost surely with no
 *    truncation; the former stop at order 1000 was one);
 *  - each X_j walks the block's pieces: a piece of length len, control c = (max + min) / 2 and
 *    radius r = (max - min) / 2 gives X = c len + R, R an estimate of int (sigma_t - c) with
 *    m = rate r len points: m >= 1: ceil(m) (at most max_points) jittered strata; m < 1: one
 *    uniform point with probability m, weight 1 / m. Both unbiased.
 *
 * The adaptive march (params.block_strata, pt.shadow_transmittance = unbiased-march-adaptive)
 * places each march's points over the whole block instead of per piece (vbl_um_march_strata), and
 * pt gives it a lower rate at deep vertices (vbl_unbiased_march_adaptive); params.pilot_min_bound
 * replaces the pilot by the mid-bound control in thin blocks (off by default: measured worse).
 *
 * The running product W of finished factors plays Russian roulette once |W| < rr (params.rr_threshold,
 * default 1e-4; VBL_UNBIASED_MARCH_DEEP_RR at a deep vertex): it survives with |W| / rr, then
 * |W| = rr (ratio tracking's rule on its weight), so lookups stop where T is small even when the
 * minorants are 0.
 *
 * Finite by construction: every sigma_t, D_j and weight is finite (a continued term is the last
 * one times +-theta (k + 1) / k or x2, not a division by a small q), exp(-tau_c) <= 1 and a
 * block returns 0 when it underflows. The estimate can be negative (or above 1) when the
 * factors' signs disagree; pixels stay finite and the mean is unbiased (docs/readme/sampling.md
 * "Shadow-ray transmittance"). */
#include "volume/transmittance_unbiased_march.h"

#include <float.h>
#include <math.h>

/* One piece of a block: [t0, t0 + len] inside one majorant segment, control c, radius r > 0. */
typedef struct vbl_um_piece {
    double t0, len, c, r;
    int cap; /* most points of one march in this piece */
} vbl_um_piece;

/* Most pieces in one block (a block also closes when it is full; any partition fixed by the
 * majorants alone keeps the product unbiased). */
#define VBL_UM_BLOCK_PIECES 32
/* Order after which the continuation probability is at most 1/2: N is finite almost surely with a
 * geometric tail, and no term is cut (the former order-1000 stop was a truncation). */
#define VBL_UM_ORDER_HALF 64
/* A marched estimate R of int (sigma_t - c) over the block's pieces at `rate` points per unit of
 * residual depth r len: m = rate r len; m >= 1: ceil(m) (at most max_points) jittered strata;
 * m < 1: one uniform point with probability m, weight 1 / m. Both unbiased; |R| <= sum r len
 * for the strata, <= 1 / rate per sparse piece. */
static double vbl_um_march(const vbl_extinction* ext, vbl_extinction_cursor* cursor, vbl_vec3 origin,
                           vbl_vec3 direction, const vbl_um_piece* pc, int n, double rate, vbl_rng* rng)
{
    double R = 0.0;
    for (int i = 0; i < n; ++i) {
        const double len = pc[i].len, c = pc[i].c, t0 = pc[i].t0;
        const double m = rate * pc[i].r * len;
        if (m < 1.0) {
            if (!(vbl_rng_uniform(rng) < m)) continue;
            double t = t0 + vbl_rng_uniform(rng) * len;
            if (!(t < t0 + len)) t = t0; /* rounding */
            R += len / m * (vbl_extinction_eval(ext, cursor, vbl_v3_madd(origin, direction, t), NULL) - c);
            continue;
        }
        const int k = m < (double)pc[i].cap ? (int)ceil(m) : pc[i].cap;
        const double h = len / (double)k;
        double s = 0.0;
        for (int j = 0; j < k; ++j) {
            double t = t0 + ((double)j + vbl_rng_uniform(rng)) * h;
            if (!(t < t0 + len)) t = t0 + (double)j * h;
            s += vbl_extinction_eval(ext, cursor, vbl_v3_madd(origin, direction, t), NULL) - c;
        }
        R += h * s;
    }
    return R;
}

/* The adaptive march (params.block_strata): R over the whole block with its points stratified in
 * the residual-depth coordinate u = int r dt in [0, W], W = sum r len the block's bound width (an
 * importance density r / W along t, constant per piece): m = rate W; m >= 1: K = ceil(m) (at most
 * `cap`) strata of width W / K, one jittered u each, R = (W / K) sum (sigma_t - c) / r at its t;
 * m < 1: one uniform u with probability m, R = (1 / rate) (sigma_t - c) / r. Unbiased (the density
 * integrates each piece's (sigma_t - c) / r x r dt), |R| <= W, resp. <= 1 / rate; the points
 * follow the block's total residual depth, so many thin pieces share strata instead of each
 * rounding its count up (a thin block costs rate W lookups on average, a full one ceil(rate W)). */
static double vbl_um_march_strata(const vbl_extinction* ext, vbl_extinction_cursor* cursor, vbl_vec3 origin,
                                  vbl_vec3 direction, const vbl_um_piece* pc, int n, double W, double rate,
                                  double offset, vbl_rng* rng)
{
    const double m = rate * W;
    int K = 1;
    double h = W; /* the stratum width in u */
    if (m < 1.0) {
        if (offset >= 0.0) { /* the point with probability m, uniform given it: offset / m */
            if (!(offset < m)) return 0.0;
            offset /= m;
        } else if (!(vbl_rng_uniform(rng) < m)) {
            return 0.0;
        }
    } else {
        K = m < (double)pc[0].cap ? (int)ceil(m) : pc[0].cap;
        h = W / (double)K;
    }
    double s = 0.0, U = 0.0; /* U: u at the start of piece i */
    int i = 0;
    for (int j = 0; j < K; ++j) { /* offset >= 0: systematic strata (params.offsets) */
        const double u = ((double)j + (offset >= 0.0 ? offset : vbl_rng_uniform(rng))) * h;
        while (i + 1 < n && u >= U + pc[i].r * pc[i].len) {
            U += pc[i].r * pc[i].len;
            ++i;
        }
        double t = pc[i].t0 + (u - U) / pc[i].r;
        if (!(t < pc[i].t0 + pc[i].len)) t = pc[i].t0; /* rounding */
        s += (vbl_extinction_eval(ext, cursor, vbl_v3_madd(origin, direction, t), NULL) - pc[i].c) / pc[i].r;
    }
    return m < 1.0 ? s / rate : h * s;
}

/* One marched estimate X of the block's residual; offset >= 0 (block strata only): systematic. */
static double vbl_um_x(const vbl_extinction* ext, vbl_extinction_cursor* cursor, vbl_vec3 origin,
                       vbl_vec3 direction, const vbl_um_piece* pc, int n, double bound, double rate, int strata,
                       double offset, vbl_rng* rng)
{
    return strata ? vbl_um_march_strata(ext, cursor, origin, direction, pc, n, bound, rate, offset, rng)
                  : vbl_um_march(ext, cursor, origin, direction, pc, n, rate, rng);
}

/* The block's estimate of exp(-tau_b): tau_b = exact + int (sigma_t - c) with |int| <= bound
 * (Kettunen et al. 2021, sec. 3 eq. for the power series around tau_c; sec. 4 the random order). */
static double vbl_um_block(const vbl_extinction* ext, vbl_extinction_cursor* cursor, vbl_vec3 origin,
                           vbl_vec3 direction, const vbl_um_piece* pc, int n, double exact, double bound,
                           const vbl_unbiased_march_params* p, double offset, vbl_rng* rng)
{
    const double rate = p->rate > 0.0 ? p->rate : VBL_UNBIASED_MARCH_RATE;
    const double pilot_rate = p->pilot_rate > 0.0 ? p->pilot_rate : VBL_UNBIASED_MARCH_RATE;
    const double theta = p->theta > 0.0 ? p->theta : 1.0;
    const int strata = p->block_strata;
    /* the control tau_c = exact + rc, rc the pilot clamped to the true residual's bounds; below
     * pilot_min_bound the mid-bound itself (rc = 0: any control independent of the factors keeps
     * the series unbiased; |tau - tau_c| <= bound, so the series' roulette terms stay O(bound^3)) */
    double rc = 0.0;
    if (!(bound < p->pilot_min_bound)) {
        rc = vbl_um_x(ext, cursor, origin, direction, pc, n, bound, pilot_rate, strata, -1.0, rng);
        if (rc < -bound) rc = -bound;
        if (rc > bound) rc = bound;
    }
    const double tc = exp(-(exact - bound)) * exp(-(rc + bound)); /* both factors <= 1 */
    if (!(tc > 0.0)) return 0.0;                                  /* below double precision */
    double d = rc - vbl_um_x(ext, cursor, origin, direction, pc, n, bound, rate, strata, offset, rng); /* D_1 */
    double term = d; /* prod D_j / (k! P(N >= k)) at k = 1 */
    double sum = 1.0 + term;
    for (int k = 1; d != 0.0; ++k) {
        double q = fabs(d) / (theta * (double)(k + 1));
        const int half = k >= VBL_UM_ORDER_HALF && q > 0.5;
        if (half) q = 0.5;
        double w; /* term / min(1, q) without dividing by a small q */
        if (q < 1.0) {
            if (!(vbl_rng_uniform(rng) < q)) break;
            w = half ? 2.0 * term : term / fabs(d) * theta * (double)(k + 1);
        } else {
            w = term;
        }
        d = rc - vbl_um_x(ext, cursor, origin, direction, pc, n, bound, rate, strata, -1.0, rng);
        term = w * d / (double)(k + 1);
        sum += term;
    }
    return tc * sum;
}

vbl_unbiased_march_params vbl_unbiased_march_defaults(double scale)
{
    const double k = scale > 1.0 ? scale : 1.0;
    vbl_unbiased_march_params p = {VBL_UNBIASED_MARCH_RATE * k,
                                   VBL_UNBIASED_MARCH_RATE * k,
                                   VBL_UNBIASED_MARCH_MAX_POINTS,
                                   1.0,
                                   VBL_UNBIASED_MARCH_BLOCK_DEPTH,
                                   0.0,
                                   0,
                                   0.0,
                                   0,
                                   {0.0, 0.0}};
    return p;
}

vbl_unbiased_march_params vbl_unbiased_march_adaptive(double scale, int deep)
{
    vbl_unbiased_march_params p = vbl_unbiased_march_defaults(scale);
    if (deep) {
        p.rate = p.pilot_rate = VBL_UNBIASED_MARCH_DEEP_RATE;
        p.rr_threshold = VBL_UNBIASED_MARCH_DEEP_RR;
    }
    p.pilot_min_bound = VBL_UNBIASED_MARCH_PILOT_MIN;
    p.block_strata = 1;
    return p;
}

/* Multiplies the running estimate by a finished factor and plays roulette on it once |W| falls
 * below rr: survives with p = |W| / rr and carries W / p (unbiased: the decision depends on
 * factors already drawn only). Returns 0 when the estimate ends at 0. */
static int vbl_um_times(double* W, double f, double rr, vbl_rng* rng)
{
    *W *= f;
    if (*W == 0.0) return 0;
    const double a = fabs(*W);
    if (a < rr) {
        const double keep = a / rr;
        if (!(vbl_rng_uniform(rng) < keep)) {
            *W = 0.0;
            return 0;
        }
        *W = *W < 0.0 ? -rr : rr;
    }
    return 1;
}

/* Block b's systematic offset for its D_1 (params.offsets), or -1: jittered. */
static double vbl_um_offset(const vbl_unbiased_march_params* p, int b)
{
    if (b >= p->offset_count || b >= VBL_UNBIASED_MARCH_OFFSETS) return -1.0;
    return p->offsets[b] >= 0.0 && p->offsets[b] < 1.0 ? p->offsets[b] : -1.0;
}

double vbl_transmittance_unbiased_march(const vbl_extinction* ext, vbl_extinction_cursor* cursor, vbl_vec3 origin,
                                        vbl_vec3 direction, double t0, double t1, int use_global_majorant,
                                        const vbl_unbiased_march_params* params, vbl_rng* rng)
{
    if (!(t1 > t0)) return 1.0;
    const double B = params->block_depth > 0.0 ? params->block_depth : VBL_UNBIASED_MARCH_BLOCK_DEPTH;
    const int max_points = params->max_points >= 1 ? params->max_points : 1;
    const double rr = params->rr_threshold > 0.0 ? fmin(params->rr_threshold, 1.0) : VBL_UNBIASED_MARCH_RR;
    const double rate = fmax(params->rate, params->pilot_rate) > 0.0 ? fmax(params->rate, params->pilot_rate)
                                                                       : VBL_UNBIASED_MARCH_RATE;
    const double per_block = ceil(fmin(rate * B, (double)max_points)); /* points of a full block */
    const int wide = (int)fmax(1.0, floor((double)max_points / per_block));
    const int wide_cap = (int)fmax(1.0, floor((double)max_points / (double)wide));
    vbl_um_piece pc[VBL_UM_BLOCK_PIECES];
    int n = 0;
    double exact = 0.0, bound = 0.0, W = 1.0;
    /* params->offsets: block b < offset_count takes offsets[b] for its D_1 (independent numbers
     * per block: the blocks' factors stay independent, which the product needs) */
    int block = 0;
    vbl_extinction_iter iter;
    vbl_majorant_segment seg;
    vbl_extinction_iter_init(&iter, ext, origin, direction, t0, t1, use_global_majorant);
    while (vbl_extinction_iter_next(&iter, &seg)) {
        const double len = seg.t1 - seg.t0;
        if (!(seg.majorant > 0.0) || !(len > 0.0)) continue;
        const double c = 0.5 * (seg.majorant + seg.minorant);
        const double r = 0.5 * (seg.majorant - seg.minorant);
        if (!(r > 0.0)) { /* homogeneous: an exact factor, no lookup */
            if (!vbl_um_times(&W, exp(-c * len), rr, rng)) return 0.0;
            continue;
        }
        /* a segment wider than `wide` x B: its own `wide` blocks of max_points / wide points each
         * (the work per segment stays at most max_points per march, as without blocks) */
        if (r * len > (double)wide * B) {
            if (n > 0) {
                const double off = vbl_um_offset(params, block++);
                const double f = vbl_um_block(ext, cursor, origin, direction, pc, n, exact, bound, params, off, rng);
                if (!vbl_um_times(&W, f, rr, rng)) return 0.0;
                n = 0;
                exact = bound = 0.0;
            }
            const double l = len / (double)wide;
            for (int i = 0; i < wide; ++i) {
                const vbl_um_piece one = {seg.t0 + (double)i * l, l, c, r, wide_cap};
                const double off = vbl_um_offset(params, block++);
                const double f = vbl_um_block(ext, cursor, origin, direction, &one, 1, c * l, r * l, params, off, rng);
                if (!vbl_um_times(&W, f, rr, rng)) return 0.0;
            }
            continue;
        }
        /* else pieces so that every block's bound width sum r len is at most B */
        double t = seg.t0, left = len;
        while (left > 0.0) {
            const double room = B - bound;
            const int fills = r * left >= room;
            const double l = fills ? room / r : left;
            pc[n++] = (vbl_um_piece){t, l, c, r, max_points};
            exact += c * l;
            bound += r * l;
            t += l;
            left = fills ? left - l : 0.0;
            if (fills || n == VBL_UM_BLOCK_PIECES) {
                const double off = vbl_um_offset(params, block++);
                const double f = vbl_um_block(ext, cursor, origin, direction, pc, n, exact, bound, params, off, rng);
                if (!vbl_um_times(&W, f, rr, rng)) return 0.0;
                n = 0;
                exact = bound = 0.0;
            }
        }
    }
    if (n > 0) {
        const double off = vbl_um_offset(params, block);
        const double f = vbl_um_block(ext, cursor, origin, direction, pc, n, exact, bound, params, off, rng);
        if (!vbl_um_times(&W, f, rr, rng)) return 0.0;
    }
    return W;
}
