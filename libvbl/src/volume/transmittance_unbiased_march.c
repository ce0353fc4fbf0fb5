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
 * is unbiased whenever P(N >= k) > 0 for every k whose term can be non-zero. Here:
 *  - the control tau_c is itself a marched estimate X_0 (a pilot), independent of the factors, so
 *    T_hat is unbiased conditionally on it (the paper's use of a first estimate as the expansion
 *    point). tau_c may be any function of X_0: it is clamped to the deterministic bounds
 *    [sum minorant len, sum majorant len] of the true tau, which keeps exp(-tau_c) <= 1;
 *  - to first order T_hat = T (1 - e_1 + O(e^2)) with e_j = X_j - tau: the variance is the first
 *    factor's, the pilot's error enters only at second order;
 *  - N >= 1 always; after factor k the series continues with probability
 *    q_k = min(1, |D_k| / (theta (k + 1))) (a stopping time of the factors drawn so far: the
 *    estimator is Russian roulette on the series, P(N >= k + 1 | X_1..X_k) = prod q_i, still
 *    unbiased). The next term is the current one times D_{k+1} / (k + 1), so q follows its expected
 *    size: rare second factors where the march is accurate, more where it is not; q_k = 0 only when
 *    D_k = 0, where every later term is 0 too;
 *  - each X_j walks the merged majorant segments once: over a segment of length len with bounds
 *    [min, max], control c = (max + min) / 2 and radius r = (max - min) / 2, X = c len + R with
 *    R an estimate of int (sigma_t - c): m = rate r len expected points; m >= 1: n = ceil(m)
 *    (at most max_points) strata of length len / n with one jittered point each (stratified
 *    sampling), R = len / n sum (sigma_t(t_i) - c); m < 1: with probability m one uniform point,
 *    R = len / m (sigma_t(t) - c), else R = 0. Both are unbiased; homogeneous (min == max) and
 *    empty segments are exact and cost no lookup. The lookups follow the residual r len as ratio
 *    tracking's follow mu len, but the points are stratified, not Poisson.
 *
 * In dense media the first walk plays Russian roulette on the whole estimate once the majorants'
 * bound on T falls below 1e-4 (as ratio tracking does on its weight below 0.1), so lookups stop where
 * T is small; a survivor carries 1 / p, which keeps (bound on T) / p at 1e-4, so tc / p <= 1.
 *
 * Finite by construction: every sigma_t, D_j and weight is finite (a continued term is the last
 * one times +-theta (k + 1) / k, not a division by a small q), exp(-tau_c) <= exp(-sum min len)
 * and it returns 0 when that underflows (T below double precision). The estimate can be
 * negative (or above 1) when the factors' signs disagree; pixels stay finite and the mean is
 * unbiased (docs/readme/sampling.md "Shadow-ray transmittance"). */
#include "volume/transmittance_unbiased_march.h"

#include <float.h>
#include <math.h>

/* Walks [t0, t1] once; returns sum c len (exact part, identical for every walk) and fills the
 * residual estimates R[i] of `n` independent marches at rates[i]; *bound receives sum r len.
 * With `roulette` not NULL (the first walk), once the upper bound exp(-sum min len) of T so far
 * times *roulette falls below VBL_RR_MARCH the whole estimate survives with probability
 * p = bound x *roulette / VBL_RR_MARCH and *roulette /= p (unbiased: p depends on the majorants
 * only); it returns -1 when the estimate was killed (T_hat = 0) or T is below double precision. */
#define VBL_RR_MARCH 1e-4
static double vbl_um_walk(const vbl_extinction* ext, vbl_extinction_cursor* cursor, vbl_vec3 origin,
                          vbl_vec3 direction, double t0, double t1, int use_global, const double* rates, int n,
                          int max_points, vbl_rng* rng, double* R, double* bound, double* roulette)
{
    vbl_extinction_iter iter;
    vbl_majorant_segment seg;
    double exact = 0.0, radius_depth = 0.0;
    for (int i = 0; i < n; ++i) R[i] = 0.0;
    vbl_extinction_iter_init(&iter, ext, origin, direction, t0, t1, use_global);
    while (vbl_extinction_iter_next(&iter, &seg)) {
        const double len = seg.t1 - seg.t0;
        if (!(seg.majorant > 0.0) || !(len > 0.0)) continue;
        const double c = 0.5 * (seg.majorant + seg.minorant);
        const double r = 0.5 * (seg.majorant - seg.minorant);
        exact += c * len;
        radius_depth += r * len;
        if (roulette) {
            const double upper = exp(-(exact - radius_depth)) * *roulette;
            if (!(upper > 0.0)) return -1.0; /* T below double precision */
            if (upper < VBL_RR_MARCH) {
                const double keep = upper / VBL_RR_MARCH;
                if (!(vbl_rng_uniform(rng) < keep)) return -1.0;
                *roulette /= keep;
            }
        }
        if (!(r > 0.0)) continue; /* homogeneous: exact */
        for (int i = 0; i < n; ++i) {
            const double m = rates[i] * r * len;
            if (m < 1.0) {
                if (!(vbl_rng_uniform(rng) < m)) continue;
                double t = seg.t0 + vbl_rng_uniform(rng) * len;
                if (!(t < seg.t1)) t = seg.t0; /* rounding */
                R[i] += len / m * (vbl_extinction_eval(ext, cursor, vbl_v3_madd(origin, direction, t), NULL) - c);
                continue;
            }
            int k = m < (double)max_points ? (int)ceil(m) : max_points;
            const double h = len / (double)k;
            double s = 0.0;
            for (int j = 0; j < k; ++j) {
                double t = seg.t0 + ((double)j + vbl_rng_uniform(rng)) * h;
                if (!(t < seg.t1)) t = seg.t0 + (double)j * h;
                s += vbl_extinction_eval(ext, cursor, vbl_v3_madd(origin, direction, t), NULL) - c;
            }
            R[i] += h * s;
        }
    }
    *bound = radius_depth;
    return exact;
}

vbl_unbiased_march_params vbl_unbiased_march_defaults(double scale)
{
    const double k = scale > 1.0 ? scale : 1.0;
    vbl_unbiased_march_params p = {VBL_UNBIASED_MARCH_RATE * k, VBL_UNBIASED_MARCH_RATE * k,
                                   VBL_UNBIASED_MARCH_MAX_POINTS, 1.0};
    return p;
}

double vbl_transmittance_unbiased_march(const vbl_extinction* ext, vbl_extinction_cursor* cursor, vbl_vec3 origin,
                                        vbl_vec3 direction, double t0, double t1, int use_global_majorant,
                                        const vbl_unbiased_march_params* params, vbl_rng* rng)
{
    if (!(t1 > t0)) return 1.0;
    const vbl_unbiased_march_params p = *params;
    const int max_points = p.max_points >= 1 ? p.max_points : 1;
    const double theta = p.theta > 0.0 ? p.theta : 1.0;
    /* walk 1: the pilot X_0 and the first factor X_1 together (one DDA walk) */
    double rates[2] = {p.pilot_rate > 0.0 ? p.pilot_rate : VBL_UNBIASED_MARCH_RATE,
                       p.rate > 0.0 ? p.rate : VBL_UNBIASED_MARCH_RATE};
    double R[2], bound, roulette = 1.0;
    const double exact = vbl_um_walk(ext, cursor, origin, direction, t0, t1, use_global_majorant, rates, 2, max_points,
                                     rng, R, &bound, &roulette);
    if (exact < 0.0) return 0.0;
    /* tau_c = exact + rc, rc = R_0 clamped to the true tau's bounds [-bound, bound] around exact */
    double rc = R[0];
    if (rc < -bound) rc = -bound;
    if (rc > bound) rc = bound;
    const double tc = exp(-(exact - bound)) * exp(-(rc + bound)); /* both factors <= 1 */
    if (!(tc > 0.0)) return 0.0; /* T below double precision */
    double d = rc - R[1]; /* D_1 = tau_c - X_1 (the exact parts cancel) */
    double term = d;      /* prod D_j / (k! P(N >= k)) at k = 1 */
    double sum = 1.0 + term;
    for (int k = 1; k < 1000; ++k) {
        if (d == 0.0) break;
        const double q = fabs(d) / (theta * (double)(k + 1));
        double w; /* term / min(1, q) without dividing by a small q */
        if (q < 1.0) {
            if (!(vbl_rng_uniform(rng) < q)) break;
            w = term / fabs(d) * theta * (double)(k + 1); /* |term / d| is the previous term's size / k */
        } else {
            w = term;
        }
        double Rk, b;
        vbl_um_walk(ext, cursor, origin, direction, t0, t1, use_global_majorant, &rates[1], 1, max_points, rng, &Rk, &b,
                    NULL);
        d = rc - Rk;
        term = w * d / (double)(k + 1);
        sum += term;
    }
    return tc * roulette * sum;
}
