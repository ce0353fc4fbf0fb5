/* VBL media-to-media (Novak et al. 2012 (VBL), section 3.2, eq. 10): the two-stage sampler
 * (chi-square of stage 1, stage 2 and the joint against the returned pdf; normalisation; the
 * closed-form stage-1 marginal), the VSL kernel (limits w >> R, R -> 0, w -> 0, g = +-0.999,
 * unbiased over its jitter) and the estimator (unbiased; lower variance than VRLs at equal count). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <cmocka.h>

#include "chi2.h"
#include "core/rng.h"
#include "quad.h"
#include "sampling/cauchy.h"
#include "sampling/phase_hg.h"
#include "sampling/beam_light_pair.h"
#include "sampling/vrl_pair.h"

typedef struct geom {
    const char* name;
    vbl_vec3 c_o, c_d;
    double u0, u1;
    vbl_vec3 l_o, l_d;
    double v0, v1;
} geom;

static geom make(const char* name, vbl_vec3 lo, vbl_vec3 ld, double v0, double v1)
{
    geom g = {name, vbl_v3(0, 0, 0), vbl_v3(1, 0, 0), 0.2, 3.0, lo, vbl_v3_normalize(ld), v0, v1};
    return g;
}

#define NGEOM 6
static geom geoms(int i)
{
    switch (i) {
    case 0: return make("skew", vbl_v3(1, 0.5, -1), vbl_v3(0.3, 0.2, 1), 0.0, 2.5);
    case 1: return make("near parallel", vbl_v3(0.5, 0.05, 0), vbl_v3(1, 1e-6, 0), -0.5, 2.0);
    case 2: return make("parallel", vbl_v3(0.5, 0.04, 0.01), vbl_v3(1, 0, 0), -0.5, 2.0);
    case 3: return make("crossing", vbl_v3(1.5, -1, 0), vbl_v3(0, 1, 0), 0.0, 2.0);
    case 4: return make("near crossing", vbl_v3(1.5, -1, 1e-4), vbl_v3(0.2, 1, 0), 0.0, 2.0);
    default: return make("far short", vbl_v3(-4, 6, 2), vbl_v3(0.1, 0.3, 1), 0.0, 0.3);
    }
}

static const double kR[] = {0.0, 0.02, 0.3};
static const double kGPairs[][2] = {{0.0, 0.0}, {0.9, 0.9}, {-0.5, 0.8}, {0.999, -0.999}};
#define NR 3
#define NGP 4

static int init_pair(vbl_beam_light_pair* p, const geom* g, double gc, double gl, double r)
{
    return vbl_beam_light_pair_init(p, g->c_o, g->c_d, g->u0, g->u1, g->l_o, g->l_d, g->v0, g->v1, gc, gl, r);
}

/* ---- quadrature of the pdf (angle substitution mirrors the sampler's documented mapping) ---- */
typedef struct qctx { const vbl_beam_light_pair* p; double v, ua, ub; } qctx;
typedef struct phictx { const vbl_beam_light_pair* p; double v, up, d; } phictx;
static double cond_phi(double phi, void* c)
{
    phictx* k = (phictx*)c;
    double t = tan(phi);
    return vbl_beam_light_pair_conditional_pdf(k->p, k->v, k->up + k->d * t) * k->d * (1.0 + t * t);
}
static double cond_mass(const vbl_beam_light_pair* p, double v, double a, double b, double abs_tol, double rel_tol)
{
    vbl_vec3 rel = vbl_v3_sub(vbl_v3_madd(p->l_o, p->l_d, v), p->c_o);
    phictx k = {p, v, vbl_v3_dot(rel, p->c_d), vbl_v3_length(vbl_v3_cross(rel, p->c_d))};
    k.d = fmax(hypot(k.d, p->radius), VBL_SAMPLING_H_FLOOR_REL * fmax(fabs(p->u0 - k.up), fabs(p->u1 - k.up)));
    return vbl_quad_adaptive(cond_phi, &k, atan2(a - k.up, k.d), atan2(b - k.up, k.d), abs_tol, rel_tol);
}
static double marg_times_cell(double v, void* c)
{
    qctx* q = (qctx*)c;
    double pv = vbl_beam_light_pair_marginal_pdf(q->p, v);
    return pv > 0.0 ? pv * cond_mass(q->p, v, q->ua, q->ub, 1e-7, 1e-5) : 0.0;
}
static double joint_cell(qctx* q, double va, double vb, int panels)
{
    double m = 0.0;
    for (int k = 0; k < panels; ++k)
        m += vbl_quad_gl16(marg_times_cell, q, va + (vb - va) * k / panels, va + (vb - va) * (k + 1) / panels);
    return m;
}
static double marg(double v, void* c) { return vbl_beam_light_pair_marginal_pdf(((qctx*)c)->p, v); }

static void test_vbl_pair_normalisation(void** state)
{
    (void)state;
    for (int i = 0; i < NGEOM; ++i) {
        geom g = geoms(i);
        for (int r = 0; r < NR; ++r)
            for (int k = 0; k < NGP; ++k) {
                vbl_beam_light_pair p;
                assert_true(init_pair(&p, &g, kGPairs[k][0], kGPairs[k][1], kR[r]));
                qctx q = {&p, 0.0, p.u0, p.u1};
                double mv = vbl_quad_adaptive(marg, &q, p.v0, p.v1, 1e-12, 1e-10);
                if (fabs(mv - 1.0) > 1e-7) printf("marginal mass %s R=%g: %.12f\n", g.name, kR[r], mv);
                assert_true(fabs(mv - 1.0) < 1e-7);
                for (int j = 0; j <= 1; ++j) {
                    double v = p.v0 + (p.v1 - p.v0) * (0.1 + 0.8 * j);
                    double mu = cond_mass(&p, v, p.u0, p.u1, 1e-10, 1e-9);
                    if (fabs(mu - 1.0) > 1e-7) printf("conditional mass %s R=%g v=%g: %.12f\n", g.name, kR[r], v, mu);
                    assert_true(fabs(mu - 1.0) < 1e-7);
                }
            }
    }
}

/* Stage 1 in closed form: pdf(v) proportional to integral_R du / (w(u,v)^2 + R^2) = pi / sqrt(h^2 + R^2).
 * Checked against a brute-force integral over a long stretch of the camera line plus its
 * analytic tails (ratios between v values, since the pdf is normalised over the segment). */
typedef struct soft { vbl_vec3 c_o, c_d, x; double r; } soft;
static double soft_integrand(double u, void* c)
{
    soft* s = (soft*)c;
    vbl_vec3 dv = vbl_v3_sub(vbl_v3_madd(s->c_o, s->c_d, u), s->x);
    return 1.0 / (vbl_v3_dot(dv, dv) + s->r * s->r);
}
static void test_vbl_pair_stage1_closed_form(void** state)
{
    (void)state;
    for (int i = 0; i < NGEOM; ++i) {
        geom g = geoms(i);
        for (int r = 1; r < NR; ++r) {
            vbl_beam_light_pair p;
            init_pair(&p, &g, 0.5, 0.5, kR[r]);
            double ratio0 = 0.0;
            for (int j = 0; j <= 4; ++j) {
                double v = p.v0 + (p.v1 - p.v0) * j / 4.0;
                soft s = {g.c_o, g.c_d, vbl_v3_madd(g.l_o, g.l_d, v), kR[r]};
                vbl_vec3 rel = vbl_v3_sub(s.x, g.c_o);
                double up = vbl_v3_dot(rel, g.c_d), h = vbl_v3_length(vbl_v3_cross(rel, g.c_d));
                double a = hypot(h, kR[r]), x = 200.0;
                double integral = 0.0;
                for (int k = -40; k < 40; ++k)
                    integral += vbl_quad_adaptive(soft_integrand, &s, up + x * k / 40.0, up + x * (k + 1) / 40.0, 1e-15, 1e-12);
                integral += 2.0 * (0.5 * VBL_PI - atan(x / a)) / a; /* tails beyond +-x */
                double ratio = vbl_beam_light_pair_marginal_pdf(&p, v) / integral;
                assert_true(fabs(integral - VBL_PI / a) < 1e-8 * VBL_PI / a);
                if (j == 0) ratio0 = ratio;
                assert_true(fabs(ratio - ratio0) < 1e-8 * ratio0);
            }
        }
    }
}

static void test_vbl_pair_marginal_chi2(void** state)
{
    (void)state;
    int ok = 1, tests = NGEOM * NR;
    for (int i = 0; i < NGEOM; ++i) {
        geom g = geoms(i);
        for (int r = 0; r < NR; ++r) {
            vbl_beam_light_pair p;
            init_pair(&p, &g, 0.9, 0.5, kR[r]);
            enum { NB = 16, NSM = 15000 };
            double obs[NB] = {0}, expct[NB];
            vbl_rng rng = vbl_rng_make(4242, (uint64_t)i, (uint64_t)r);
            for (int s = 0; s < NSM; ++s) {
                vbl_beam_light_pair_sample smp;
                vbl_beam_light_pair_draw(&p, vbl_rng_uniform(&rng), vbl_rng_uniform(&rng), &smp);
                int b = (int)((smp.v - p.v0) / (p.v1 - p.v0) * NB);
                obs[b < 0 ? 0 : (b >= NB ? NB - 1 : b)] += 1.0;
            }
            qctx q = {&p, 0.0, 0.0, 0.0};
            for (int b = 0; b < NB; ++b)
                expct[b] = NSM * vbl_quad_adaptive(marg, &q, p.v0 + (p.v1 - p.v0) * b / NB, p.v0 + (p.v1 - p.v0) * (b + 1) / NB,
                                                   1e-12, 1e-10);
            char label[96];
            snprintf(label, sizeof label, "vbl marginal v %s R=%g", g.name, kR[r]);
            ok &= vbl_chi2_check(label, obs, expct, NB, 0.01, tests);
        }
    }
    assert_true(ok);
}

/* Stage 2 alone: xi1 fixed, u drawn from the conditional at that v. */
static void test_vbl_pair_conditional_chi2(void** state)
{
    (void)state;
    const double xi1s[] = {0.07, 0.61};
    enum { NB = 16, NSC = 6000 };
    int ok = 1, tests = NGEOM * NR * NGP;
    for (int i = 0; i < NGEOM; ++i) {
        geom g = geoms(i);
        for (int r = 0; r < NR; ++r)
            for (int k = 0; k < NGP; ++k) {
                vbl_beam_light_pair p;
                init_pair(&p, &g, kGPairs[k][0], kGPairs[k][1], kR[r]);
                for (int j = (i + r + k) % 2; j < 2; j += 2) { /* one stage-1 value per configuration, alternating */
                    vbl_beam_light_pair_sample smp;
                    double ue[NB + 1], obs[NB] = {0}, expct[NB];
                    for (int b = 0; b <= NB; ++b) {
                        vbl_beam_light_pair_draw(&p, xi1s[j], (double)b / NB, &smp);
                        ue[b] = smp.u;
                    }
                    ue[0] = p.u0;
                    ue[NB] = p.u1;
                    double v = smp.v;
                    vbl_rng rng = vbl_rng_make(2024, (uint64_t)(i * 100 + r * 10 + k), (uint64_t)j);
                    long bad = 0;
                    for (int s = 0; s < NSC; ++s) {
                        if (!vbl_beam_light_pair_draw(&p, xi1s[j], vbl_rng_uniform(&rng), &smp)) {
                            ++bad;
                            continue;
                        }
                        double q = vbl_beam_light_pair_density(&p, smp.u, smp.v);
                        bad += smp.v != v || !(fabs(smp.pdf - q) <= 1e-9 * q) || !(smp.u >= p.u0 && smp.u <= p.u1);
                        int b = 0;
                        while (b + 1 < NB && smp.u >= ue[b + 1]) ++b;
                        obs[b] += 1.0;
                    }
                    for (int b = 0; b < NB; ++b) expct[b] = NSC * cond_mass(&p, v, ue[b], ue[b + 1], 1e-10, 1e-8);
                    char label[128];
                    snprintf(label, sizeof label, "vbl|v %s R=%g g=(%g,%g) xi1=%g", g.name, kR[r], kGPairs[k][0],
                             kGPairs[k][1], xi1s[j]);
                    ok &= vbl_chi2_check(label, obs, expct, NB, 0.01, tests) && bad == 0;
                }
            }
    }
    assert_true(ok);
}

#define NU 8
#define NV 8
static int chi2_joint(const geom* g, double gc, double gl, double r, uint64_t seed, int tests, long ns)
{
    vbl_beam_light_pair p;
    if (!init_pair(&p, g, gc, gl, r)) return 0;
    double ve[NV + 1], ue[NU + 1];
    for (int i = 0; i <= NV; ++i) ve[i] = p.v0 + vbl_sinh_marginal_sample_t(&p.marginal, (double)i / NV, NULL);
    ve[0] = p.v0;
    ve[NV] = p.v1;
    for (int i = 0; i <= NU; ++i) ue[i] = p.u0 + (p.u1 - p.u0) * i / NU;
    double obs[NU * NV] = {0}, expct[NU * NV];
    vbl_rng rng = vbl_rng_make(seed, 5, 0);
    long bad = 0;
    for (long s = 0; s < ns; ++s) {
        vbl_beam_light_pair_sample smp;
        if (!vbl_beam_light_pair_draw(&p, vbl_rng_uniform(&rng), vbl_rng_uniform(&rng), &smp)) {
            ++bad;
            continue;
        }
        double q = vbl_beam_light_pair_density(&p, smp.u, smp.v);
        if (!isfinite(smp.pdf) || !(fabs(smp.pdf - q) <= 1e-9 * q)) ++bad;
        int vi = 0, ui = 0;
        while (vi + 1 < NV && smp.v >= ve[vi + 1]) ++vi;
        while (ui + 1 < NU && smp.u >= ue[ui + 1]) ++ui;
        obs[vi * NU + ui] += 1.0;
    }
    double total = 0.0;
    for (int vi = 0; vi < NV; ++vi)
        for (int ui = 0; ui < NU; ++ui) {
            qctx q = {&p, 0.0, ue[ui], ue[ui + 1]};
            double m = joint_cell(&q, ve[vi], ve[vi + 1], 2);
            expct[vi * NU + ui] = ns * m;
            total += m;
        }
    char label[128];
    snprintf(label, sizeof label, "vbl joint %s R=%g g=(%g,%g)", g->name, r, gc, gl);
    int ok = vbl_chi2_check(label, obs, expct, NU * NV, 0.01, tests);
    printf("     mass %.9f, bad samples %ld\n", total, bad);
    return ok && bad == 0 && fabs(total - 1.0) < 1e-4;
}

static void test_vbl_pair_joint_chi2(void** state)
{
    (void)state;
    int ok = 1;
    geom g0 = geoms(0), g4 = geoms(4);
    ok &= chi2_joint(&g0, 0.9, 0.9, 0.3, 100, 2, 40000);
    ok &= chi2_joint(&g4, 0.999, -0.999, 0.02, 201, 2, 40000);
    assert_true(ok);
}

/* The chi-square can fail: samples at R = 0.3 judged against the pdf of R = 0.02. */
static void test_vbl_pair_chi2_detects_wrong_pdf(void** state)
{
    (void)state;
    geom g = geoms(4);
    vbl_beam_light_pair drawn, judged;
    init_pair(&drawn, &g, 0.9, 0.9, 0.3);
    init_pair(&judged, &g, 0.9, 0.9, 0.02);
    enum { NB = 16, NSM = 40000 };
    double obs[NB] = {0}, expct[NB];
    vbl_rng rng = vbl_rng_make(77, 0, 0);
    for (int s = 0; s < NSM; ++s) {
        vbl_beam_light_pair_sample smp;
        vbl_beam_light_pair_draw(&drawn, vbl_rng_uniform(&rng), vbl_rng_uniform(&rng), &smp);
        int b = (int)((smp.v - g.v0) / (g.v1 - g.v0) * NB);
        obs[b < 0 ? 0 : (b >= NB ? NB - 1 : b)] += 1.0;
    }
    qctx q = {&judged, 0.0, 0.0, 0.0};
    for (int b = 0; b < NB; ++b)
        expct[b] = NSM * vbl_quad_adaptive(marg, &q, g.v0 + (g.v1 - g.v0) * b / NB, g.v0 + (g.v1 - g.v0) * (b + 1) / NB, 1e-12, 1e-10);
    assert_false(vbl_chi2_check("vbl R=0.3 vs pdf R=0.02 (must fail)", obs, expct, NB, 0.01, 1));
}

static void test_vsl_kernel_pair_extremes(void** state)
{
    (void)state;
    const double xs[] = {0.0, 1e-300, 1e-9, 0.5, 1.0 - 1e-9, nextafter(1.0, 0.0), 1.0};
    const double gs[][2] = {{0.999, 0.999}, {-0.999, -0.999}, {0.999, -0.999}, {0.0, 0.999}, {0.0, 0.0}};
    const double rs[] = {0.0, 1e-12, 1e-3, 1.0, 1e6};
    for (int i = 0; i < NGEOM; ++i) {
        geom g = geoms(i);
        for (size_t r = 0; r < sizeof rs / sizeof rs[0]; ++r)
            for (int k = 0; k < 5; ++k) {
                vbl_beam_light_pair p;
                assert_true(init_pair(&p, &g, gs[k][0], gs[k][1], rs[r]));
                for (size_t a = 0; a < sizeof xs / sizeof xs[0]; ++a)
                    for (size_t b = 0; b < sizeof xs / sizeof xs[0]; ++b) {
                        vbl_beam_light_pair_sample s;
                        assert_int_equal(vbl_beam_light_pair_draw(&p, xs[a], xs[b], &s), 1);
                        assert_true(isfinite(s.u) && isfinite(s.v) && isfinite(s.pdf) && s.pdf > 0.0);
                        assert_true(s.u >= g.u0 && s.u <= g.u1 && s.v >= g.v0 && s.v <= g.v1);
                        double k2 = vbl_vsl_kernel(vbl_v3_madd(g.c_o, g.c_d, s.u), g.c_d, gs[k][0],
                                                   vbl_v3_madd(g.l_o, g.l_d, s.v), g.l_d, gs[k][1], rs[r], 8, xs[a], xs[b]);
                        assert_true(isfinite(k2) && k2 >= 0.0);
                        assert_true(isfinite(k2 / s.pdf));
                    }
            }
    }
    /* VRL starting exactly on the camera ray; zero-length segments have no support. */
    geom g = geoms(0);
    vbl_beam_light_pair p;
    vbl_beam_light_pair_sample s;
    assert_true(vbl_beam_light_pair_init(&p, g.c_o, g.c_d, g.u0, g.u1, vbl_v3(1, 0, 0), vbl_v3(0, 0, 1), 0.0, 1.0, 0.7, 0.7, 0.01));
    for (size_t a = 0; a < sizeof xs / sizeof xs[0]; ++a) {
        assert_int_equal(vbl_beam_light_pair_draw(&p, xs[a], xs[a], &s), 1);
        assert_true(isfinite(s.pdf) && s.pdf > 0.0);
    }
    assert_false(vbl_beam_light_pair_init(&p, g.c_o, g.c_d, 1.0, 1.0, g.l_o, g.l_d, g.v0, g.v1, 0.5, 0.5, 0.1));
    assert_int_equal(vbl_beam_light_pair_draw(&p, 0.3, 0.3, &s), 0);
    assert_true(s.pdf == 0.0 && vbl_beam_light_pair_density(&p, 1.0, 1.0) == 0.0);
    assert_false(vbl_beam_light_pair_init(&p, g.c_o, g.c_d, g.u0, g.u1, g.l_o, g.l_d, g.v0, g.v1, 0.5, 0.5, NAN));
}

/* ---- kernel ---- */
static double ff_over_w2(vbl_vec3 xc, vbl_vec3 cd, double gc, vbl_vec3 xl, vbl_vec3 ld, double gl)
{
    vbl_vec3 d = vbl_v3_sub(xc, xl);
    double w2 = vbl_v3_dot(d, d);
    vbl_vec3 om = vbl_v3_scale(d, 1.0 / sqrt(w2));
    return vbl_hg_eval(gl, vbl_v3_dot(ld, om)) * vbl_hg_eval(gc, -vbl_v3_dot(cd, om)) / w2;
}

/* w >> R: K_R -> f_l f_c / w^2; R == 0: exactly the VRL integrand. */
static void test_vsl_kernel_far_limit(void** state)
{
    (void)state;
    const double gs[][2] = {{0.0, 0.0}, {0.9, 0.9}, {-0.5, 0.8}, {0.95, -0.9}};
    vbl_vec3 cd = vbl_v3_normalize(vbl_v3(1, 0.2, -0.1)), ld = vbl_v3_normalize(vbl_v3(0.3, -1, 0.4));
    vbl_vec3 xl = vbl_v3(0.1, 0.2, 0.3);
    vbl_vec3 dirs[3] = {vbl_v3_normalize(vbl_v3(1, 1, 0)), vbl_v3_normalize(vbl_v3(-0.2, 0.5, 1)),
                        vbl_v3_normalize(vbl_v3(0.3, -1, 0.4))};
    for (int k = 0; k < 4; ++k)
        for (int j = 0; j < 3; ++j) {
            vbl_vec3 xc = vbl_v3_madd(xl, dirs[j], 2.0);
            double ref = ff_over_w2(xc, cd, gs[k][0], xl, ld, gs[k][1]);
            assert_true(fabs(vbl_vsl_kernel(xc, cd, gs[k][0], xl, ld, gs[k][1], 0.0, 16, 0.5, 0.5) - ref) <= 1e-14 * ref);
            double prev = INFINITY;
            for (double r = 0.2; r >= 0.2e-3; r *= 0.1) {
                double kv = vbl_vsl_kernel(xc, cd, gs[k][0], xl, ld, gs[k][1], r, 32, 0.5, 0.5);
                double err = fabs(kv - ref) / ref;
                printf("far limit g=(%g,%g) dir %d R/w=%g: K=%.8g ff/w^2=%.8g rel err %.3g\n", gs[k][0], gs[k][1], j,
                       r / 2.0, kv, ref, err);
                assert_true(err <= fmax(prev * 0.5, 1e-9)); /* shrinks with R / w */
                prev = err;
            }
            assert_true(prev < 1e-5);
        }
}

/* w -> 0 and g -> +-1: finite, non-negative and below the bound 2 max(f_l f_c) / R^2. */
static void test_vsl_kernel_bounded(void** state)
{
    (void)state;
    const double gs[] = {0.999, -0.999, 0.9, 0.0, -0.3};
    const double rs[] = {1e-12, 1e-4, 0.1, 10.0, 1e8};
    const double ws[] = {0.0, 1e-300, 1e-13, 1e-5, 0.05, 1.0};
    vbl_vec3 cd = vbl_v3(1, 0, 0), xl = vbl_v3(0, 0, 0);
    vbl_vec3 lds[2] = {vbl_v3(1, 0, 0), vbl_v3_normalize(vbl_v3(0.3, 0.9, -0.1))};
    vbl_vec3 off = vbl_v3_normalize(vbl_v3(0.2, 1, 0.5));
    for (size_t a = 0; a < 5; ++a)
        for (size_t b = 0; b < 5; ++b)
            for (size_t r = 0; r < sizeof rs / sizeof rs[0]; ++r)
                for (size_t w = 0; w < sizeof ws / sizeof ws[0]; ++w)
                    for (int l = 0; l < 2; ++l) {
                        double fmax_l = vbl_hg_eval(gs[a], gs[a] >= 0 ? 1.0 : -1.0);
                        double fmax_c = vbl_hg_eval(gs[b], gs[b] >= 0 ? 1.0 : -1.0);
                        double bound = 2.0 * fmax_l * fmax_c / (rs[r] * rs[r]);
                        double kv = vbl_vsl_kernel(vbl_v3_madd(xl, off, ws[w]), cd, gs[b], xl, lds[l], gs[a], rs[r], 16,
                                                   0.3, 0.7);
                        if (!(isfinite(kv) && kv >= 0.0 && kv <= bound * (1.0 + 1e-9)))
                            printf("kernel g=(%g,%g) R=%g w=%g: %g (bound %g)\n", gs[b], gs[a], rs[r], ws[w], kv, bound);
                        assert_true(isfinite(kv) && kv >= 0.0 && kv <= bound * (1.0 + 1e-9));
                    }
}

/* The kernel's quadrature is unbiased over its jitter: mean of random-jitter evaluations vs a
 * dense deterministic quadrature, for cones from thin to the full hemisphere. */
static void test_vsl_kernel_unbiased_over_jitter(void** state)
{
    (void)state;
    const double gs[][2] = {{0.9, 0.9}, {-0.5, 0.95}, {0.999, 0.0}, {0.0, 0.0}};
    const double wr[] = {0.3, 0.9, 1.5, 5.0};
    vbl_vec3 cd = vbl_v3_normalize(vbl_v3(1, 0.1, 0)), ld = vbl_v3_normalize(vbl_v3(0.8, 0.5, 0.2)), xl = vbl_v3(0, 0, 0);
    vbl_vec3 off = vbl_v3_normalize(vbl_v3(0.7, 0.6, 0.1));
    int ok = 1;
    for (int k = 0; k < 4; ++k)
        for (int j = 0; j < 4; ++j) {
            double r = 0.1;
            vbl_vec3 xc = vbl_v3_madd(xl, off, wr[j] * r);
            /* dense reference: average of many deterministic lattices */
            double ref = 0.0;
            for (int q = 0; q < 16; ++q)
                ref += vbl_vsl_kernel(xc, cd, gs[k][0], xl, ld, gs[k][1], r, 4096, (q + 0.5) / 16.0, (q * 7 % 16 + 0.5) / 16.0);
            ref /= 16.0;
            vbl_rng rng = vbl_rng_make(99, (uint64_t)k, (uint64_t)j);
            vbl_mean_acc acc = {0, 0, 0};
            for (int s = 0; s < 4000; ++s)
                vbl_mean_add(&acc, vbl_vsl_kernel(xc, cd, gs[k][0], xl, ld, gs[k][1], r, 16, vbl_rng_uniform(&rng),
                                                  vbl_rng_uniform(&rng)));
            char label[96];
            snprintf(label, sizeof label, "kernel jitter mean g=(%g,%g) w/R=%g", gs[k][0], gs[k][1], wr[j]);
            ok &= vbl_mean_check(label, &acc, ref, 4.5, 2e-4 * ref);
        }
    assert_true(ok);
}

/* R -> 0: the kernel integrated along the camera segment converges to the VRL integral. */
typedef struct kctx { vbl_vec3 c_o, c_d, xl, ld; double gc, gl, r; } kctx;
/* Composite 16-point Gauss-Legendre: the fixed-jitter kernel has tiny jumps (lobe samples crossing
 * the cone boundary), which an adaptive rule would chase to its depth limit. */
static double composite(vbl_quad_fn f, void* c, double a, double b, int panels)
{
    double m = 0.0;
    for (int k = 0; k < panels; ++k) m += vbl_quad_gl16(f, c, a + (b - a) * k / panels, a + (b - a) * (k + 1) / panels);
    return m;
}
static double kernel_u(double u, void* c)
{
    kctx* k = (kctx*)c;
    return vbl_vsl_kernel(vbl_v3_madd(k->c_o, k->c_d, u), k->c_d, k->gc, k->xl, k->ld, k->gl, k->r, 24, 0.5, 0.5);
}
static void test_vsl_kernel_r_to_zero(void** state)
{
    (void)state;
    const double gs[][2] = {{0.0, 0.0}, {0.7, 0.8}, {-0.4, 0.9}};
    for (int k = 0; k < 3; ++k) {
        kctx c = {vbl_v3(0, 0, 0), vbl_v3(1, 0, 0), vbl_v3(1.2, 0.15, 0.05), vbl_v3_normalize(vbl_v3(0.2, 1, 0.3)), gs[k][0],
                  gs[k][1], 0.0};
        double ref = vbl_quad_adaptive(kernel_u, &c, 0.0, 3.0, 1e-12, 1e-10); /* R = 0: VRL */
        double prev = INFINITY;
        for (double r = 0.1; r > 1e-3; r *= 0.5) {
            c.r = r;
            double v = composite(kernel_u, &c, 0.0, 3.0, 96);
            double err = fabs(v - ref) / ref;
            printf("R->0 g=(%g,%g) R=%.4g: integral %.8g vs VRL %.8g, rel err %.3g\n", gs[k][0], gs[k][1], r, v, ref, err);
            assert_true(err < prev);
            prev = err;
        }
        assert_true(prev < 1e-3);
    }
}

/* ---- estimator ---- */
typedef struct ectx { const vbl_beam_light_pair* p; double v; int n; } ectx;
static double pair_kernel(const vbl_beam_light_pair* p, double u, double v, int n)
{
    return vbl_vsl_kernel(vbl_v3_madd(p->c_o, p->c_d, u), p->c_d, p->g_camera, vbl_v3_madd(p->l_o, p->l_d, v), p->l_d,
                          p->g_light, p->radius, n, 0.5, 0.5);
}
static double ek_u(double u, void* c)
{
    ectx* e = (ectx*)c;
    return pair_kernel(e->p, u, e->v, e->n);
}
static double ek_v(double v, void* c)
{
    ectx e = *(ectx*)c;
    e.v = v;
    return composite(ek_u, &e, e.p->u0, e.p->u1, 32);
}

/* E[K(u, v) / pdf(u, v)] equals the double integral of K (eq 10 with sigma = T = V = Phi = 1). */
static void test_vbl_pair_unbiased(void** state)
{
    (void)state;
    const int geo[] = {0, 1, 4};
    const double gs[][2] = {{0.0, 0.0}, {0.9, 0.9}, {-0.5, 0.9}};
    int ok = 1;
    for (int i = 0; i < 3; ++i) {
        geom g = geoms(geo[i]);
        for (int k = 0; k < 3; ++k) {
            vbl_beam_light_pair p;
            init_pair(&p, &g, gs[k][0], gs[k][1], 0.1);
            ectx e = {&p, 0.0, 8};
            double ref = composite(ek_v, &e, p.v0, p.v1, 16);
            vbl_rng rng = vbl_rng_make(31337, (uint64_t)i, (uint64_t)k);
            vbl_mean_acc acc = {0, 0, 0};
            for (int s = 0; s < 20000; ++s) {
                vbl_beam_light_pair_sample smp;
                double est = 0.0;
                if (vbl_beam_light_pair_draw(&p, vbl_rng_uniform(&rng), vbl_rng_uniform(&rng), &smp))
                    est = pair_kernel(&p, smp.u, smp.v, 8) / smp.pdf;
                vbl_mean_add(&acc, est);
            }
            char label[96];
            snprintf(label, sizeof label, "eq10 %s g=(%g,%g) R=0.1", g.name, gs[k][0], gs[k][1]);
            ok &= vbl_mean_check(label, &acc, ref, 4.0, 1e-5 * ref);
            printf("     relative stderr %.3g\n", vbl_mean_stderr(&acc) / ref);
        }
    }
    assert_true(ok);
}

/* Equal VRL count, g = 0.9, VRLs passing close to the camera ray: per-VRL estimates of VBLs
 * (fixed R) have lower variance than those of VRLs, and their means agree within the blur. */
static void test_vbl_lower_variance_than_vrl(void** state)
{
    (void)state;
    const double r = 0.05, g = 0.9;
    vbl_vec3 c_o = vbl_v3(0, 0, 0), c_d = vbl_v3(1, 0, 0);
    vbl_rng rng = vbl_rng_make(555, 0, 0);
    vbl_mean_acc vrl = {0, 0, 0}, vbl = {0, 0, 0};
    for (int s = 0; s < 20000; ++s) {
        /* VRL of length 1 through a random point within 0.1 of the camera ray, random direction */
        double a = 2.0 * VBL_PI * vbl_rng_uniform(&rng), rad = 0.1 * sqrt(vbl_rng_uniform(&rng));
        vbl_vec3 mid = vbl_v3(0.5 + 2.0 * vbl_rng_uniform(&rng), rad * cos(a), rad * sin(a));
        double z = 1.0 - 2.0 * vbl_rng_uniform(&rng), ph = 2.0 * VBL_PI * vbl_rng_uniform(&rng);
        vbl_vec3 ld = vbl_v3(sqrt(fmax(0.0, 1 - z * z)) * cos(ph), sqrt(fmax(0.0, 1 - z * z)) * sin(ph), z);
        vbl_vec3 lo = vbl_v3_madd(mid, ld, -0.5);
        double x1 = vbl_rng_uniform(&rng), x2 = vbl_rng_uniform(&rng);
        vbl_vrl_pair pr;
        vbl_vrl_pair_sample sr;
        double er = 0.0, eb = 0.0;
        const vbl_segment camera = vbl_segment_make(c_o, c_d, 0.0, 3.0), light = vbl_segment_make(lo, ld, 0.0, 1.0);
        vbl_vrl_pair_init(&pr, &camera, &light, g, g);
        if (vbl_vrl_pair_draw(&pr, x1, x2, &sr)) er = vbl_vrl_pair_phase_geometry(&pr, sr.u, sr.v) / sr.pdf;
        vbl_beam_light_pair pb;
        vbl_beam_light_pair_sample sb;
        vbl_beam_light_pair_init(&pb, c_o, c_d, 0.0, 3.0, lo, ld, 0.0, 1.0, g, g, r);
        if (vbl_beam_light_pair_draw(&pb, x1, x2, &sb))
            eb = vbl_vsl_kernel(vbl_v3_madd(c_o, c_d, sb.u), c_d, g, vbl_v3_madd(lo, ld, sb.v), ld, g, r, 16,
                                vbl_rng_uniform(&rng), vbl_rng_uniform(&rng)) / sb.pdf;
        vbl_mean_add(&vrl, er);
        vbl_mean_add(&vbl, eb);
    }
    double var_r = vrl.m2 / (vrl.n - 1), var_b = vbl.m2 / (vbl.n - 1);
    printf("equal count (20000 VRLs, g=0.9, R=%g): VRL mean %.5g var %.5g | VBL mean %.5g var %.5g (ratio %.3g)\n", r,
           vrl.mean, var_r, vbl.mean, var_b, var_r / var_b);
    assert_true(var_b < var_r);
    assert_true(fabs(vbl.mean - vrl.mean) < 0.25 * vrl.mean);
}

int main(int argc, char** argv)
{
    if (argc > 1) cmocka_set_test_filter(argv[1]);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_vbl_pair_normalisation),
        cmocka_unit_test(test_vbl_pair_stage1_closed_form),
        cmocka_unit_test(test_vsl_kernel_pair_extremes),
        cmocka_unit_test(test_vbl_pair_marginal_chi2),
        cmocka_unit_test(test_vbl_pair_conditional_chi2),
        cmocka_unit_test(test_vbl_pair_joint_chi2),
        cmocka_unit_test(test_vbl_pair_chi2_detects_wrong_pdf),
        cmocka_unit_test(test_vsl_kernel_far_limit),
        cmocka_unit_test(test_vsl_kernel_bounded),
        cmocka_unit_test(test_vsl_kernel_unbiased_over_jitter),
        cmocka_unit_test(test_vsl_kernel_r_to_zero),
        cmocka_unit_test(test_vbl_pair_unbiased),
        cmocka_unit_test(test_vbl_lower_variance_than_vrl),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
