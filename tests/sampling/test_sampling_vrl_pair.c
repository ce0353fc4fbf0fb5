/* VRL product sampling (VRL paper section 4, appendix A): 2D chi-square over (u, v) against the
 * integral of vbl_vrl_pair_pdf per cell, normalisation, sample/pdf consistency, degenerate
 * geometry, and unbiasedness of the two-stage estimator of eq (7) (sigma = T = V = 1). */
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

#define NGEOM 7
static geom geoms(int i)
{
    switch (i) {
    case 0: return make("skew", vbl_v3(1, 0.5, -1), vbl_v3(0.3, 0.2, 1), 0.0, 2.5);
    case 1: return make("skew backwards", vbl_v3(3, 0.3, 0.4), vbl_v3(-1, 0.4, -0.2), 0.0, 3.0);
    case 2: return make("near parallel", vbl_v3(0.5, 0.4, 0), vbl_v3(1, 1e-6, 0), -0.5, 2.0);
    case 3: return make("parallel", vbl_v3(0.5, 0.4, 0.1), vbl_v3(1, 0, 0), -0.5, 2.0);
    case 4: return make("crossing", vbl_v3(1.5, -1, 0), vbl_v3(0, 1, 0), 0.0, 2.0);
    case 5: return make("near crossing h=1e-4", vbl_v3(1.5, -1, 1e-4), vbl_v3(0.2, 1, 0), 0.0, 2.0);
    default: return make("far short", vbl_v3(-4, 6, 2), vbl_v3(0.1, 0.3, 1), 0.0, 0.3);
    }
}

static const double kGPairs[][2] = {{0.0, 0.0}, {0.9, 0.9}, {-0.5, 0.8}, {0.999, -0.999}, {0.3, 0.0}};
#define NGP ((int)(sizeof kGPairs / sizeof kGPairs[0]))

/* The camera segment of geometry g over [a, b] and a VRL segment, as pointers to temporaries. */
#define CAM(g, a, b) (&(vbl_segment){(g).c_o, (g).c_d, (a), (b)})
#define SEG(o, d, a, b) (&(vbl_segment){(o), (d), (a), (b)})

static int init_pair(vbl_vrl_pair* p, const geom* g, double gc, double gl)
{
    const vbl_segment camera = vbl_segment_make(g->c_o, g->c_d, g->u0, g->u1);
    const vbl_segment light = vbl_segment_make(g->l_o, g->l_d, g->v0, g->v1);
    return vbl_vrl_pair_init(p, &camera, &light, gc, gl);
}

/* ---- quadrature helpers over the pdf ---- */
typedef struct qctx { const vbl_vrl_pair* p; double v, ua, ub; double (*f)(const vbl_vrl_pair*, double, double); } qctx;
/* Integral of the conditional over [a, b] with the substitution u = up + d tan(phi) (up, d: the
 * projection of the VRL point on the camera line, d raised to the documented relative floor
 * VBL_SAMPLING_H_FLOOR_REL), which turns the near-crossing spike into a smooth integrand. */
typedef struct phictx { qctx q; double up, d; } phictx;
static double cond_phi(double phi, void* c)
{
    phictx* k = (phictx*)c;
    double t = tan(phi);
    return vbl_vrl_pair_conditional_pdf(k->q.p, k->q.v, k->up + k->d * t) * k->d * (1.0 + t * t);
}
static double cond_mass(const vbl_vrl_pair* p, double v, double a, double b, double abs_tol, double rel_tol)
{
    vbl_vec3 rel = vbl_v3_sub(vbl_v3_madd(p->l_o, p->l_d, v), p->c_o);
    phictx k = {{p, v, a, b, NULL}, vbl_v3_dot(rel, p->c_d), vbl_v3_length(vbl_v3_cross(rel, p->c_d))};
    k.d = fmax(k.d, VBL_SAMPLING_H_FLOOR_REL * fmax(fabs(p->u0 - k.up), fabs(p->u1 - k.up)));
    double pa = atan2(a - k.up, k.d), pb = atan2(b - k.up, k.d);
    return vbl_quad_adaptive(cond_phi, &k, pa, pb, abs_tol, rel_tol);
}
static double marg_times_cell(double v, void* c)
{
    qctx* q = (qctx*)c;
    double pv = vbl_vrl_pair_marginal_pdf(q->p, v);
    if (!(pv > 0.0)) return 0.0;
    return pv * cond_mass(q->p, v, q->ua, q->ub, 1e-7, 1e-5);
}
/* Mass of the cell [va, vb] x [q->ua, q->ub]: composite 16-point GL over v (the conditional is
 * piecewise smooth in v: appendix A's vertex placement jumps as the peak index changes, so an
 * adaptive rule would chase the jumps), adaptive quadrature over u in the angle domain. */
static double joint_cell(qctx* q, double va, double vb, int panels)
{
    double m = 0.0;
    for (int k = 0; k < panels; ++k)
        m += vbl_quad_gl16(marg_times_cell, q, va + (vb - va) * k / panels, va + (vb - va) * (k + 1) / panels);
    return m;
}
static double marg(double v, void* c) { return vbl_vrl_pair_marginal_pdf(((qctx*)c)->p, v); }

#define NU 8
#define NV 8
#define NS 100000

static int chi2_pair(const geom* g, double gc, double gl, uint64_t seed, int tests)
{
    vbl_vrl_pair p;
    if (!init_pair(&p, g, gc, gl)) return 0;
    double ve[NV + 1], ue[NU + 1];
    for (int i = 0; i <= NV; ++i) ve[i] = p.v0 + vbl_sinh_marginal_sample_t(&p.marginal, (double)i / NV, NULL);
    ve[0] = p.v0;
    ve[NV] = p.v1;
    for (int i = 0; i <= NU; ++i) ue[i] = p.u0 + (p.u1 - p.u0) * i / NU;
    double obs[NU * NV] = {0}, expct[NU * NV];
    vbl_rng rng = vbl_rng_make(seed, 5, 0);
    long bad = 0;
    for (int s = 0; s < NS; ++s) {
        vbl_vrl_pair_sample smp;
        double x1 = vbl_rng_uniform(&rng), x2 = vbl_rng_uniform(&rng);
        if (!vbl_vrl_pair_draw(&p, x1, x2, &smp)) {
            ++bad;
            continue;
        }
        double q = vbl_vrl_pair_density(&p, smp.u, smp.v);
        if (!(smp.u >= p.u0 && smp.u <= p.u1 && smp.v >= p.v0 && smp.v <= p.v1) || !isfinite(smp.pdf) ||
            !(fabs(smp.pdf - q) <= 1e-9 * q))
            ++bad;
        int vi = 0, ui = 0;
        while (vi + 1 < NV && smp.v >= ve[vi + 1]) ++vi;
        while (ui + 1 < NU && smp.u >= ue[ui + 1]) ++ui;
        obs[vi * NU + ui] += 1.0;
    }
    double total = 0.0;
    for (int vi = 0; vi < NV; ++vi)
        for (int ui = 0; ui < NU; ++ui) {
            qctx q = {&p, 0.0, ue[ui], ue[ui + 1], NULL};
            double m = joint_cell(&q, ve[vi], ve[vi + 1], 4);
            expct[vi * NU + ui] = NS * m;
            total += m;
        }
    char label[96];
    snprintf(label, sizeof label, "vrl %s gc=%g gl=%g", g->name, gc, gl);
    int ok = vbl_chi2_check(label, obs, expct, NU * NV, 0.01, tests);
    printf("     mass %.9f, bad samples %ld\n", total, bad);
    return ok && bad == 0 && fabs(total - 1.0) < 1e-4;
}

static void test_vrl_pair_chi2(void** state)
{
    (void)state;
    int ok = 1;
    const int joint[] = {0, 2, 4, 5, 6}; /* skew, near parallel, crossing, near crossing, far short */
    for (int j = 0; j < 5; ++j) {
        int i = joint[j];
        geom g = geoms(i);
        /* Joint 2D test for the isotropic and the most anisotropic pair; all pairs get the
         * conditional test below (the joint density is marginal x conditional). */
        ok &= chi2_pair(&g, 0.0, 0.0, 1000 + 10 * i, 10);
        ok &= chi2_pair(&g, 0.999, -0.999, 5001 + 10 * i, 10);
    }
    assert_true(ok);
}


/* Stage 2 alone: with xi1 fixed the draw samples u from the conditional at a fixed v. */
#define NCU 16
static void test_vrl_pair_conditional_chi2(void** state)
{
    (void)state;
    const double xi1s[] = {0.05, 0.5, 0.93};
    int ok = 1, tests = NGEOM * NGP * 3;
    for (int i = 0; i < NGEOM; ++i) {
        geom g = geoms(i);
        for (int k = 0; k < NGP; ++k) {
            vbl_vrl_pair p;
            init_pair(&p, &g, kGPairs[k][0], kGPairs[k][1]);
            for (int j = 0; j < 3; ++j) {
                vbl_vrl_pair_sample smp;
                vbl_vrl_pair_draw(&p, xi1s[j], 0.5, &smp);
                double v = smp.v, ue[NCU + 1], obs[NCU] = {0}, expct[NCU];
                /* u edges at the sampler's own quantiles (pdf integrated independently) */
                for (int b = 0; b <= NCU; ++b) {
                    vbl_vrl_pair_draw(&p, xi1s[j], (double)b / NCU, &smp);
                    ue[b] = smp.u;
                }
                ue[0] = p.u0;
                ue[NCU] = p.u1;
                vbl_rng rng = vbl_rng_make(2024, (uint64_t)(i * 100 + k), (uint64_t)j);
                long bad = 0;
                for (int s = 0; s < 20000; ++s) {
                    vbl_vrl_pair_draw(&p, xi1s[j], vbl_rng_uniform(&rng), &smp);
                    bad += smp.v != v;
                    int b = 0;
                    while (b + 1 < NCU && smp.u >= ue[b + 1]) ++b;
                    obs[b] += 1.0;
                }
                for (int b = 0; b < NCU; ++b) expct[b] = 20000 * cond_mass(&p, v, ue[b], ue[b + 1], 1e-10, 1e-8);
                char label[96];
                snprintf(label, sizeof label, "vrl|v %s gc=%g gl=%g xi1=%g", g.name, kGPairs[k][0], kGPairs[k][1], xi1s[j]);
                ok &= vbl_chi2_check(label, obs, expct, NCU, 0.01, tests) && bad == 0;
            }
        }
    }
    assert_true(ok);
}

/* Stage 1 alone: the v marginal of the draw. */
static void test_vrl_pair_marginal_chi2(void** state)
{
    (void)state;
    int ok = 1;
    for (int i = 0; i < NGEOM; ++i) {
        geom g = geoms(i);
        vbl_vrl_pair p;
        init_pair(&p, &g, 0.9, 0.5);
        double ve[NCU + 1], obs[NCU] = {0}, expct[NCU];
        for (int b = 0; b <= NCU; ++b) ve[b] = p.v0 + (p.v1 - p.v0) * b / NCU;
        vbl_rng rng = vbl_rng_make(4242, (uint64_t)i, 0);
        for (int s = 0; s < 50000; ++s) {
            vbl_vrl_pair_sample smp;
            vbl_vrl_pair_draw(&p, vbl_rng_uniform(&rng), vbl_rng_uniform(&rng), &smp);
            int b = (int)((smp.v - p.v0) / (p.v1 - p.v0) * NCU);
            obs[b < 0 ? 0 : (b >= NCU ? NCU - 1 : b)] += 1.0;
        }
        qctx q = {&p, 0.0, 0.0, 0.0, NULL};
        for (int b = 0; b < NCU; ++b) expct[b] = 50000 * vbl_quad_adaptive(marg, &q, ve[b], ve[b + 1], 1e-12, 1e-10);
        char label[96];
        snprintf(label, sizeof label, "vrl marginal v %s", g.name);
        ok &= vbl_chi2_check(label, obs, expct, NCU, 0.01, NGEOM);
    }
    assert_true(ok);
}

/* The chi-square must be able to fail: samples drawn for g = 0.9 judged against the pdf of g = 0.6. */
static void test_vrl_pair_chi2_detects_wrong_pdf(void** state)
{
    (void)state;
    geom g = geoms(0);
    vbl_vrl_pair drawn, judged;
    init_pair(&drawn, &g, 0.9, 0.9);
    init_pair(&judged, &g, 0.6, 0.6);
    double obs[NU] = {0}, expct[NU];
    vbl_rng rng = vbl_rng_make(77, 0, 0);
    for (int s = 0; s < NS; ++s) {
        vbl_vrl_pair_sample smp;
        vbl_vrl_pair_draw(&drawn, vbl_rng_uniform(&rng), vbl_rng_uniform(&rng), &smp);
        int ui = (int)((smp.u - g.u0) / (g.u1 - g.u0) * NU);
        obs[ui < 0 ? 0 : (ui >= NU ? NU - 1 : ui)] += 1.0;
    }
    for (int ui = 0; ui < NU; ++ui) {
        qctx q = {&judged, 0.0, g.u0 + (g.u1 - g.u0) * ui / NU, g.u0 + (g.u1 - g.u0) * (ui + 1) / NU, NULL};
        expct[ui] = NS * joint_cell(&q, g.v0, g.v1, 12);
    }
    assert_false(vbl_chi2_check("vrl g=0.9 vs pdf g=0.6 (must fail)", obs, expct, NU, 0.01, 1));
}

static void test_vrl_pair_normalisation(void** state)
{
    (void)state;
    for (int i = 0; i < NGEOM; ++i) {
        geom g = geoms(i);
        for (int k = 0; k < NGP; ++k) {
            vbl_vrl_pair p;
            assert_true(init_pair(&p, &g, kGPairs[k][0], kGPairs[k][1]));
            qctx q = {&p, 0.0, p.u0, p.u1, NULL};
            double mv = vbl_quad_adaptive(marg, &q, p.v0, p.v1, 1e-12, 1e-10);
            assert_true(fabs(mv - 1.0) < 1e-7);
            for (int j = 0; j <= 4; ++j) {
                q.v = p.v0 + (p.v1 - p.v0) * j / 4.0;
                double mu = cond_mass(&p, q.v, p.u0, p.u1, 1e-11, 1e-9);
                if (fabs(mu - 1.0) > 1e-7) printf("conditional mass %s g=(%g,%g) v=%g: %.12f\n", g.name, kGPairs[k][0],
                                                   kGPairs[k][1], q.v, mu);
                assert_true(fabs(mu - 1.0) < 1e-7);
            }
        }
    }
}

/* Isotropic: stage 1 is eq (13) and stage 2 the equiangular / eq (14) density, pdf = product. */
static void test_vrl_pair_isotropic_is_analytic(void** state)
{
    (void)state;
    geom g = geoms(0);
    vbl_vrl_pair p;
    init_pair(&p, &g, 0.0, 0.0);
    for (int i = 0; i < 50; ++i) {
        vbl_vrl_pair_sample s;
        assert_true(vbl_vrl_pair_draw(&p, (i + 0.5) / 50.0, (i * 7 % 50 + 0.25) / 50.0, &s));
        vbl_vec3 x = vbl_v3_madd(g.l_o, g.l_d, s.v);
        /* conditional density proportional to 1/dist^2 along the camera segment */
        vbl_vec3 r = vbl_v3_sub(vbl_v3_madd(g.c_o, g.c_d, s.u), x);
        vbl_vec3 r0 = vbl_v3_sub(vbl_v3_madd(g.c_o, g.c_d, g.u0), x);
        double ratio = vbl_vrl_pair_conditional_pdf(&p, s.v, s.u) / vbl_vrl_pair_conditional_pdf(&p, s.v, g.u0);
        assert_true(fabs(ratio - vbl_v3_dot(r0, r0) / vbl_v3_dot(r, r)) < 1e-10 * ratio);
        assert_true(fabs(s.pdf - vbl_vrl_pair_pdf(CAM(g, g.u0, g.u1), SEG(g.l_o, g.l_d, g.v0, g.v1), 0.0, 0.0, s.u, s.v)) <
                    1e-12 * s.pdf);
    }
}

static void test_vrl_pair_extremes(void** state)
{
    (void)state;
    const double xs[] = {0.0, 1e-300, 1e-9, 0.5, 1.0 - 1e-9, nextafter(1.0, 0.0), 1.0};
    const double gs[][2] = {{0.999, 0.999}, {-0.999, -0.999}, {0.999, -0.999}, {0.0, 0.999}, {0.0, 0.0}};
    for (int i = 0; i < NGEOM; ++i) {
        geom g = geoms(i);
        for (int k = 0; k < 5; ++k) {
            for (size_t a = 0; a < sizeof xs / sizeof xs[0]; ++a) {
                for (size_t b = 0; b < sizeof xs / sizeof xs[0]; ++b) {
                    vbl_vrl_pair_sample s;
                    int r = vbl_vrl_pair_sample_draw(CAM(g, g.u0, g.u1), SEG(g.l_o, g.l_d, g.v0, g.v1), gs[k][0], gs[k][1],
                                                     xs[a], xs[b], &s);
                    assert_int_equal(r, 1);
                    assert_true(isfinite(s.u) && isfinite(s.v) && isfinite(s.pdf) && s.pdf > 0.0);
                    assert_true(s.u >= g.u0 && s.u <= g.u1 && s.v >= g.v0 && s.v <= g.v1);
                }
            }
        }
    }
    /* Zero-length segments have no support. */
    vbl_vrl_pair_sample s;
    geom g = geoms(0);
    assert_int_equal(vbl_vrl_pair_sample_draw(CAM(g, 1.0, 1.0), SEG(g.l_o, g.l_d, g.v0, g.v1), 0.5, 0.5, 0.3, 0.3, &s), 0);
    assert_true(s.pdf == 0.0);
    assert_int_equal(vbl_vrl_pair_sample_draw(CAM(g, g.u0, g.u1), SEG(g.l_o, g.l_d, 2.0, 2.0), 0.0, 0.0, 0.3, 0.3, &s), 0);
    assert_true(vbl_vrl_pair_pdf(CAM(g, g.u0, g.u1), SEG(g.l_o, g.l_d, 2.0, 2.0), 0.0, 0.0, 1.0, 2.0) == 0.0);
    /* VRL starting exactly on the camera ray (crossing at the segment end). */
    vbl_vec3 lo = vbl_v3(1.0, 0.0, 0.0);
    for (size_t a = 0; a < sizeof xs / sizeof xs[0]; ++a) {
        assert_int_equal(vbl_vrl_pair_sample_draw(CAM(g, g.u0, g.u1), SEG(lo, vbl_v3(0, 0, 1), 0.0, 1.0), 0.7, 0.7, xs[a],
                                                  xs[a], &s), 1);
        assert_true(isfinite(s.pdf) && s.pdf > 0.0);
    }
}

/* ---- unbiasedness of eq (7) with sigma = T = V = 1: E[f / pdf] vs brute-force quadrature ---- */
static double f_u(double u, void* c)
{
    qctx* q = (qctx*)c;
    return vbl_vrl_pair_phase_geometry(q->p, u, q->v);
}
static double f_v(double v, void* c)
{
    qctx* q = (qctx*)c;
    qctx inner = *q;
    inner.v = v;
    return vbl_quad_adaptive(f_u, &inner, q->p->u0, q->p->u1, 1e-13, 1e-8);
}

static void test_vrl_pair_unbiased(void** state)
{
    (void)state;
    const int geo[] = {0, 1, 2, 3, 6};
    const double gs[][2] = {{0.0, 0.0}, {0.6, 0.8}, {-0.5, 0.9}, {0.9, -0.3}};
    int ok = 1;
    for (size_t i = 0; i < sizeof geo / sizeof geo[0]; ++i) {
        geom g = geoms(geo[i]);
        for (int k = 0; k < 4; ++k) {
            vbl_vrl_pair p;
            init_pair(&p, &g, gs[k][0], gs[k][1]);
            qctx q = {&p, 0.0, 0.0, 0.0, NULL};
            double ref = vbl_quad_adaptive(f_v, &q, p.v0, p.v1, 1e-13, 1e-7);
            vbl_rng rng = vbl_rng_make(31337, (uint64_t)i, (uint64_t)k);
            vbl_mean_acc acc = {0, 0, 0};
            for (int s = 0; s < 50000; ++s) {
                vbl_vrl_pair_sample smp;
                double est = 0.0;
                if (vbl_vrl_pair_draw(&p, vbl_rng_uniform(&rng), vbl_rng_uniform(&rng), &smp))
                    est = vbl_vrl_pair_phase_geometry(&p, smp.u, smp.v) / smp.pdf;
                vbl_mean_add(&acc, est);
            }
            char label[96];
            snprintf(label, sizeof label, "eq7 %s gc=%g gl=%g", g.name, gs[k][0], gs[k][1]);
            ok &= vbl_mean_check(label, &acc, ref, 4.0, 1e-6 * ref);
            printf("     relative stderr %.3g\n", vbl_mean_stderr(&acc) / ref);
        }
    }
    assert_true(ok);
}

int main(int argc, char** argv)
{
    if (argc > 1) cmocka_set_test_filter(argv[1]);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_vrl_pair_normalisation),
        cmocka_unit_test(test_vrl_pair_isotropic_is_analytic),
        cmocka_unit_test(test_vrl_pair_extremes),
        cmocka_unit_test(test_vrl_pair_marginal_chi2),
        cmocka_unit_test(test_vrl_pair_conditional_chi2),
        cmocka_unit_test(test_vrl_pair_chi2),
        cmocka_unit_test(test_vrl_pair_chi2_detects_wrong_pdf),
        cmocka_unit_test(test_vrl_pair_unbiased),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
