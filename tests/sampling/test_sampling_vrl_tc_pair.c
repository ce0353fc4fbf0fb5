/* Camera-transmittance x geometry pair sampling (sampling/vrl_tc_pair.h): the u marginal's
 * normalisation and 1D chi-square, the 2D chi-square of the MIS draw over (u, v) against the
 * integral of its mixture density per cell, the draw's pdf equal to vbl_vrl_tc_pair_density,
 * the swapped pair's target equal to the pair's (v given u follows the same lobes), and
 * unbiasedness of f / pdf for an integrand with the camera transmittance as a step function
 * (eq 7 of Novak et al. 2012 (VRL) with sigma = 1, T_c the steps, T(w) = e^(-w)). Two staircases:
 * 6 steps ending in Tc = 0 (the cache's roulette kill), and 80 noisy steps (more than
 * VBL_VRL_TC_MAX_PIECES: the merge). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <cmocka.h>

#include "chi2.h"
#include "core/rng.h"
#include "quad.h"
#include "sampling/vrl_tc_pair.h"

typedef struct geom {
    const char* name;
    vbl_vec3 l_o, l_d;
    double v0, v1, gc, gl;
} geom;

#define NGEOM 5
static const geom kGeoms[NGEOM] = {
    {"skew g 0.8", {1, 0.5, -1}, {0.3, 0.2, 1}, 0.0, 2.5, 0.8, 0.8},
    {"skew backwards g -0.5/0.8", {3, 0.3, 0.4}, {-1, 0.4, -0.2}, 0.0, 3.0, -0.5, 0.8},
    {"deep crossing isotropic", {2.4, -1, 0.05}, {0, 1, 0}, 0.0, 2.0, 0.0, 0.0},
    {"near-parallel g 0.3", {0.5, 0.3, 0.1}, {1, 0.01, 0.0}, 0.0, 1.5, 0.3, 0.3},
    {"parallel (flat form) g 0.5", {0.6, 0.4, 0.2}, {1, 0, 0}, 0.0, 1.8, 0.5, 0.5},
};

/* Camera segment [0.2, 3] along +x. */
#define MAXS 80
typedef struct stair {
    int n;
    double x[MAXS + 1], y[MAXS];
} stair;

static void make_stair(int which, stair* st)
{
    if (which == 0) {
        static const double x[] = {0.2, 0.4, 0.7, 1.0, 1.5, 2.2, 3.0};
        static const double y[] = {1.0, 0.6, 0.3, 0.1, 0.01, 0.0};
        st->n = 6;
        for (int i = 0; i <= 6; ++i) st->x[i] = x[i];
        for (int i = 0; i < 6; ++i) st->y[i] = y[i];
        return;
    }
    /* ratio-tracking-like: e^(-1.5 (u - 0.2)) times a factor in [0.5, 1.5], uneven steps */
    vbl_rng rng = vbl_rng_make(99, 3, 5);
    st->n = MAXS;
    double acc = 0.0, w[MAXS];
    for (int i = 0; i < MAXS; ++i) acc += (w[i] = 0.2 + vbl_rng_uniform(&rng));
    st->x[0] = 0.2;
    double c = 0.0;
    for (int i = 0; i < MAXS; ++i) {
        c += w[i];
        st->x[i + 1] = i + 1 == MAXS ? 3.0 : 0.2 + 2.8 * c / acc;
        st->y[i] = exp(-1.5 * (st->x[i] - 0.2)) * (0.5 + vbl_rng_uniform(&rng));
    }
}

typedef struct setup_t {
    vbl_vrl_pair p;
    vbl_step_pdf s;
    vbl_vrl_tc_marginal m;
    stair st;
} setup_t;

/* which: 0, 1 the staircases with Tc weights; 2, 3 the same with drop weights (free flight) */
static void setup(int i, int which, setup_t* t)
{
    const geom* g = &kGeoms[i];
    const vbl_segment camera = vbl_segment_make(vbl_v3(0, 0, 0), vbl_v3(1, 0, 0), 0.2, 3.0);
    const vbl_segment light = vbl_segment_make(g->l_o, vbl_v3_normalize(g->l_d), g->v0, g->v1);
    make_stair(which & 1, &t->st);
    assert_true(vbl_vrl_pair_init(&t->p, &camera, &light, g->gc, g->gl));
    assert_true(vbl_step_pdf_init(&t->s, t->st.x, t->st.y, t->st.n, 0.0));
    assert_true(vbl_vrl_tc_marginal_init(&t->m, &t->p, &t->s, which >> 1));
}

static double tc_of(const stair* st, double u)
{
    for (int i = 0; i < st->n; ++i)
        if (u < st->x[i + 1]) return st->y[i];
    return st->y[st->n - 1];
}

typedef struct qctx { const setup_t* t; double u, va, vb; int integrand; } qctx;
static double integrand(const qctx* q, double u, double v)
{
    const vbl_vrl_pair* p = &q->t->p;
    if (!q->integrand) return vbl_vrl_tc_pair_density(p, &q->t->m, u, v);
    vbl_vec3 xu = vbl_v3_madd(p->c_o, p->c_d, u), xv = vbl_v3_madd(p->l_o, p->l_d, v);
    double w = vbl_v3_length(vbl_v3_sub(xu, xv));
    return vbl_vrl_pair_phase_geometry(p, u, v) * tc_of(&q->t->st, u) * exp(-w);
}
static double inner_v(double v, void* c)
{
    qctx* q = (qctx*)c;
    return integrand(q, q->u, v);
}
static double outer_u(double u, void* c)
{
    qctx q = *(qctx*)c;
    q.u = u;
    double m = 0.0; /* composite Gauss-Legendre in v (appendix A's vertices jump with v) */
    for (int k = 0; k < 3; ++k)
        m += vbl_quad_gl16(inner_v, &q, q.va + (q.vb - q.va) * k / 3, q.va + (q.vb - q.va) * (k + 1) / 3);
    return m;
}
/* Integral over [ua, ub] x [va, vb], split at the staircase's breakpoints. */
static double cell(qctx* q, double ua, double ub, double va, double vb)
{
    q->va = va;
    q->vb = vb;
    double m = 0.0, a = ua;
    const stair* st = &q->t->st;
    for (int k = 1; k <= st->n && a < ub; ++k) {
        double b = fmin(st->x[k], ub);
        if (b > a) m += vbl_quad_adaptive(outer_u, q, a, b, 1e-9, q->integrand ? 1e-6 : 1e-4);
        a = fmax(a, b);
    }
    return m;
}

static double marg_pdf(double u, void* c) { return vbl_vrl_tc_marginal_pdf((const vbl_vrl_tc_marginal*)c, u); }

#define NU 6
#define NV 4
#define NS 25000

/* The u marginal alone: mass 1 (integrated piece by piece), 1D chi-square, pdf of the draw. */
static void test_tc_marginal(void** state)
{
    (void)state;
    int ok = 1;
    for (int which = 0; which < 4; ++which)
        for (int i = 0; i < NGEOM; ++i) {
            setup_t t;
            setup(i, which, &t);
            const vbl_vrl_tc_marginal* m = &t.m;
            double mass = 0.0;
            for (int k = 0; k < m->count; ++k) mass += vbl_quad_adaptive(marg_pdf, (void*)m, m->x[k], m->x[k + 1], 1e-12, 1e-8);
            enum { NB = 16 };
            double obs[NB] = {0}, expct[NB];
            for (int b = 0; b < NB; ++b) {
                double a = 0.2 + 2.8 * b / NB, z = 0.2 + 2.8 * (b + 1) / NB, e = 0.0, lo = a;
                for (int k = 0; k < m->count; ++k) { /* split at the pieces */
                    double hi = fmin(m->x[k + 1], z);
                    if (hi > lo) e += vbl_quad_adaptive(marg_pdf, (void*)m, lo, hi, 1e-12, 1e-8);
                    lo = fmax(lo, hi);
                }
                expct[b] = NS * e;
            }
            vbl_rng rng = vbl_rng_make(31, (uint64_t)i, (uint64_t)which);
            long bad = 0;
            for (int n = 0; n < NS; ++n) {
                double pdf;
                double u = vbl_vrl_tc_marginal_sample(m, vbl_rng_uniform(&rng), &pdf);
                double q = vbl_vrl_tc_marginal_pdf(m, u);
                if (!(u >= 0.2 && u <= 3.0) || !(pdf > 0.0) || fabs(pdf - q) > 1e-12 * q) ++bad;
                if ((which & 1) == 0 && u > 2.2) ++bad; /* no weight there (Tc = 0, no drop): never drawn */
                int b = (int)((u - 0.2) / 2.8 * NB);
                obs[b < 0 ? 0 : (b >= NB ? NB - 1 : b)] += 1.0;
            }
            char label[96];
            snprintf(label, sizeof label, "tc marginal %s, stair %d (%d pieces)", kGeoms[i].name, which, m->count);
            ok &= vbl_chi2_check(label, obs, expct, NB, 0.01, 4 * NGEOM);
            printf("     mass %.9f, bad samples %ld\n", mass, bad);
            ok &= bad == 0 && fabs(mass - 1.0) < 1e-6 && m->count <= VBL_VRL_TC_MAX_PIECES;
        }
    assert_true(ok);
}

static void test_tc_pair_chi2(void** state)
{
    (void)state;
    int ok = 1;
    for (int which = 0; which < 3; ++which) /* the 80-step drop form: test_tc_marginal */
        for (int i = 0; i < NGEOM; ++i) {
            setup_t t;
            setup(i, which, &t);
            const vbl_vrl_pair* p = &t.p;
            double ue[NU + 1], ve[NV + 1], obs[NU * NV] = {0}, expct[NU * NV];
            for (int k = 0; k <= NU; ++k) ue[k] = p->u0 + (p->u1 - p->u0) * k / NU;
            for (int k = 0; k <= NV; ++k) ve[k] = p->v0 + (p->v1 - p->v0) * k / NV;
            vbl_rng rng = vbl_rng_make(4243, (uint64_t)i, (uint64_t)which);
            long bad = 0;
            for (int n = 0; n < NS; ++n) {
                vbl_vrl_pair_sample smp;
                double x0 = vbl_rng_uniform(&rng), x1 = vbl_rng_uniform(&rng), x2 = vbl_rng_uniform(&rng);
                if (!vbl_vrl_tc_pair_draw(p, &t.m, x0, x1, x2, &smp)) {
                    ++bad;
                    continue;
                }
                double q = vbl_vrl_tc_pair_density(p, &t.m, smp.u, smp.v);
                if (!(smp.u >= p->u0 && smp.u <= p->u1 && smp.v >= p->v0 && smp.v <= p->v1) || !isfinite(smp.pdf) ||
                    !(fabs(smp.pdf - q) <= 1e-9 * q))
                    ++bad;
                int ui = 0, vi = 0;
                while (ui + 1 < NU && smp.u >= ue[ui + 1]) ++ui;
                while (vi + 1 < NV && smp.v >= ve[vi + 1]) ++vi;
                obs[vi * NU + ui] += 1.0;
            }
            double total = 0.0;
            qctx q = {&t, 0.0, 0.0, 0.0, 0};
            for (int vi = 0; vi < NV; ++vi)
                for (int ui = 0; ui < NU; ++ui) {
                    double m = cell(&q, ue[ui], ue[ui + 1], ve[vi], ve[vi + 1]);
                    expct[vi * NU + ui] = NS * m;
                    total += m;
                }
            char label[96];
            snprintf(label, sizeof label, "tc pair MIS %s, stair %d", kGeoms[i].name, which);
            ok &= vbl_chi2_check(label, obs, expct, NU * NV, 0.01, 3 * NGEOM);
            printf("     mass %.9f, bad samples %ld\n", total, bad);
            ok &= bad == 0 && fabs(total - 1.0) < 1e-4;
        }
    assert_true(ok);
}

static void test_tc_pair_unbiased(void** state)
{
    (void)state;
    int ok = 1;
    for (int which = 0; which < 3; ++which) /* the 80-step drop form: test_tc_marginal */
        for (int i = 0; i < NGEOM; ++i) {
            setup_t t;
            setup(i, which, &t);
            const vbl_vrl_pair* p = &t.p;
            qctx q = {&t, 0.0, 0.0, 0.0, 1};
            double ref = cell(&q, p->u0, p->u1, p->v0, p->v1);
            vbl_rng rng = vbl_rng_make(778, (uint64_t)i, (uint64_t)which);
            vbl_mean_acc mis = {0, 0, 0}, prod = {0, 0, 0};
            for (int n = 0; n < 20000; ++n) {
                vbl_vrl_pair_sample smp;
                double x0 = vbl_rng_uniform(&rng), x1 = vbl_rng_uniform(&rng), x2 = vbl_rng_uniform(&rng);
                double est = 0.0;
                if (vbl_vrl_tc_pair_draw(p, &t.m, x0, x1, x2, &smp)) est = integrand(&q, smp.u, smp.v) / smp.pdf;
                vbl_mean_add(&mis, est);
                est = 0.0;
                if (vbl_vrl_pair_draw(p, x1, x2, &smp)) est = integrand(&q, smp.u, smp.v) / smp.pdf;
                vbl_mean_add(&prod, est);
            }
            char label[96];
            snprintf(label, sizeof label, "tc pair MIS mean %s, stair %d", kGeoms[i].name, which);
            ok &= vbl_mean_check(label, &mis, ref, 4.0, 1e-6 * ref);
            printf("     relative stderr: MIS %.3g, product sampler alone %.3g\n", vbl_mean_stderr(&mis) / ref,
                   vbl_mean_stderr(&prod) / ref);
        }
    assert_true(ok);
}

/* No mass (Tc == 0 everywhere): the marginal is invalid and the draw falls back to the product
 * sampler with its own density. */
static void test_tc_pair_no_mass(void** state)
{
    (void)state;
    const vbl_segment camera = vbl_segment_make(vbl_v3(0, 0, 0), vbl_v3(1, 0, 0), 0.2, 3.0);
    const vbl_segment light = vbl_segment_make(vbl_v3(1, 0.5, -1), vbl_v3_normalize(vbl_v3(0.3, 0.2, 1)), 0.0, 2.5);
    vbl_vrl_pair p;
    assert_true(vbl_vrl_pair_init(&p, &camera, &light, 0.5, 0.5));
    const double x[] = {0.2, 1.0, 3.0}, y[] = {0.0, 0.0};
    vbl_step_pdf s;
    vbl_step_pdf_init(&s, x, y, 2, 0.0); /* uniform fallback; its values stay 0 */
    vbl_vrl_tc_marginal m;
    assert_false(vbl_vrl_tc_marginal_init(&m, &p, &s, 0));
    assert_false(vbl_vrl_tc_marginal_init(&m, &p, &s, 1));
    vbl_vrl_pair_sample a, b;
    assert_true(vbl_vrl_tc_pair_draw(&p, &m, 0.9, 0.3, 0.6, &a));
    assert_true(vbl_vrl_pair_draw(&p, 0.3, 0.6, &b));
    assert_true(a.u == b.u && a.v == b.v && a.pdf == b.pdf);
}

/* The swapped pair (v given u) targets the same phase x geometry term: f_s f_s / w^2 is symmetric
 * under the exchange of the segments (omega -> -omega, g values exchanged). */
static void test_swapped_target(void** state)
{
    (void)state;
    for (int i = 0; i < NGEOM; ++i) {
        setup_t t;
        setup(i, 0, &t);
        vbl_rng rng = vbl_rng_make(5, (uint64_t)i, 9);
        for (int n = 0; n < 200; ++n) {
            double u = t.p.u0 + (t.p.u1 - t.p.u0) * vbl_rng_uniform(&rng);
            double v = t.p.v0 + (t.p.v1 - t.p.v0) * vbl_rng_uniform(&rng);
            double a = vbl_vrl_pair_phase_geometry(&t.p, u, v), b = vbl_vrl_pair_phase_geometry(&t.m.swapped, v, u);
            assert_true(fabs(a - b) <= 1e-12 * a);
        }
    }
}

int main(int argc, char** argv)
{
    if (argc > 1) cmocka_set_test_filter(argv[1]);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_tc_marginal),
        cmocka_unit_test(test_tc_pair_chi2),
        cmocka_unit_test(test_tc_pair_unbiased),
        cmocka_unit_test(test_tc_pair_no_mass),
        cmocka_unit_test(test_swapped_target),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
