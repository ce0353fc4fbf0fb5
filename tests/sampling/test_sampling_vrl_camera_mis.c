/* Transmittance-aware pair sampling (sampling/vrl_camera_mis.h): 2D chi-square of the MIS draw
 * over (u, v) against the integral of its mixture density per cell, the draw's pdf equal to
 * vbl_vrl_camera_mis_density, and unbiasedness of f / pdf for an integrand with a falling
 * camera-transmittance staircase (eq 7 with sigma = 1, T_c a step function, T(w) = e^(-w)).
 * Mutations checked: technique 2's pdf without the equiangular factor, or the mixture without
 * the (1 - c) share, fail the chi-square and the mean checks. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <cmocka.h>

#include "chi2.h"
#include "core/rng.h"
#include "quad.h"
#include "sampling/vrl_camera_mis.h"

typedef struct geom {
    const char* name;
    vbl_vec3 l_o, l_d;
    double v0, v1, gc, gl;
} geom;

#define NGEOM 4
static const geom kGeoms[NGEOM] = {
    {"skew g 0.8", {1, 0.5, -1}, {0.3, 0.2, 1}, 0.0, 2.5, 0.8, 0.8},
    {"skew backwards g -0.5/0.8", {3, 0.3, 0.4}, {-1, 0.4, -0.2}, 0.0, 3.0, -0.5, 0.8},
    {"deep crossing isotropic", {2.4, -1, 0.05}, {0, 1, 0}, 0.0, 2.0, 0.0, 0.0},
    {"far short g 0.3", {-1, 2, 1}, {0.1, 0.3, 1}, 0.0, 0.5, 0.3, 0.3},
};

/* Camera segment [0.2, 3] along +x; its "transmittance": a falling staircase. */
static const double kX[] = {0.2, 0.4, 0.7, 1.0, 1.5, 2.2, 3.0};
static const double kY[] = {1.0, 0.6, 0.3, 0.1, 0.01, 1e-4};

static void setup(int i, vbl_vrl_pair* p, vbl_step_pdf* s)
{
    const geom* g = &kGeoms[i];
    const vbl_segment camera = vbl_segment_make(vbl_v3(0, 0, 0), vbl_v3(1, 0, 0), 0.2, 3.0);
    const vbl_segment light = vbl_segment_make(g->l_o, vbl_v3_normalize(g->l_d), g->v0, g->v1);
    assert_true(vbl_vrl_pair_init(p, &camera, &light, g->gc, g->gl));
    assert_true(vbl_step_pdf_init(s, kX, kY, 6, 0.0));
}

typedef struct qctx { const vbl_vrl_pair* p; const vbl_step_pdf* s; double u, va, vb; int integrand; } qctx;
static double integrand(const qctx* q, double u, double v)
{
    if (!q->integrand) return vbl_vrl_camera_mis_density(q->p, q->s, u, v);
    vbl_vec3 xu = vbl_v3_madd(q->p->c_o, q->p->c_d, u), xv = vbl_v3_madd(q->p->l_o, q->p->l_d, v);
    double w = vbl_v3_length(vbl_v3_sub(xu, xv));
    return vbl_vrl_pair_phase_geometry(q->p, u, v) * vbl_step_pdf_pdf(q->s, u) * exp(-w);
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
    /* composite 16-point Gauss-Legendre in v: piecewise smooth (appendix A's vertex placement
     * jumps with v), an adaptive rule would chase the jumps */
    double m = 0.0;
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
    for (int k = 1; k <= 6 && a < ub; ++k) {
        double b = fmin(kX[k], ub);
        if (b > a) m += vbl_quad_adaptive(outer_u, q, a, b, 1e-10, 1e-6);
        a = fmax(a, b);
    }
    return m;
}

#define NU 6
#define NV 4
#define NS 60000

static void test_camera_mis_chi2(void** state)
{
    (void)state;
    int ok = 1;
    for (int i = 0; i < NGEOM; ++i) {
        vbl_vrl_pair p;
        vbl_step_pdf s;
        setup(i, &p, &s);
        double ue[NU + 1], ve[NV + 1], obs[NU * NV] = {0}, expct[NU * NV];
        for (int k = 0; k <= NU; ++k) ue[k] = p.u0 + (p.u1 - p.u0) * k / NU;
        for (int k = 0; k <= NV; ++k) ve[k] = p.v0 + (p.v1 - p.v0) * k / NV;
        vbl_rng rng = vbl_rng_make(4242, (uint64_t)i, 0);
        long bad = 0;
        for (int n = 0; n < NS; ++n) {
            vbl_vrl_pair_sample smp;
            double x0 = vbl_rng_uniform(&rng), x1 = vbl_rng_uniform(&rng), x2 = vbl_rng_uniform(&rng);
            if (!vbl_vrl_camera_mis_draw(&p, &s, x0, x1, x2, &smp)) {
                ++bad;
                continue;
            }
            double q = vbl_vrl_camera_mis_density(&p, &s, smp.u, smp.v);
            if (!(smp.u >= p.u0 && smp.u <= p.u1 && smp.v >= p.v0 && smp.v <= p.v1) || !isfinite(smp.pdf) ||
                !(fabs(smp.pdf - q) <= 1e-9 * q))
                ++bad;
            int ui = 0, vi = 0;
            while (ui + 1 < NU && smp.u >= ue[ui + 1]) ++ui;
            while (vi + 1 < NV && smp.v >= ve[vi + 1]) ++vi;
            obs[vi * NU + ui] += 1.0;
        }
        double total = 0.0;
        qctx q = {&p, &s, 0.0, 0.0, 0.0, 0};
        for (int vi = 0; vi < NV; ++vi)
            for (int ui = 0; ui < NU; ++ui) {
                double m = cell(&q, ue[ui], ue[ui + 1], ve[vi], ve[vi + 1]);
                expct[vi * NU + ui] = NS * m;
                total += m;
            }
        char label[96];
        snprintf(label, sizeof label, "camera MIS %s", kGeoms[i].name);
        ok &= vbl_chi2_check(label, obs, expct, NU * NV, 0.01, NGEOM);
        printf("     mass %.9f, bad samples %ld\n", total, bad);
        ok &= bad == 0 && fabs(total - 1.0) < 1e-4;
    }
    assert_true(ok);
}

static void test_camera_mis_unbiased(void** state)
{
    (void)state;
    int ok = 1;
    for (int i = 0; i < NGEOM; ++i) {
        vbl_vrl_pair p;
        vbl_step_pdf s;
        setup(i, &p, &s);
        qctx q = {&p, &s, 0.0, 0.0, 0.0, 1};
        double ref = cell(&q, p.u0, p.u1, p.v0, p.v1);
        vbl_rng rng = vbl_rng_make(777, (uint64_t)i, 1);
        vbl_mean_acc mis = {0, 0, 0}, prod = {0, 0, 0};
        for (int n = 0; n < 30000; ++n) {
            vbl_vrl_pair_sample smp;
            double x0 = vbl_rng_uniform(&rng), x1 = vbl_rng_uniform(&rng), x2 = vbl_rng_uniform(&rng);
            double est = 0.0;
            if (vbl_vrl_camera_mis_draw(&p, &s, x0, x1, x2, &smp)) est = integrand(&q, smp.u, smp.v) / smp.pdf;
            vbl_mean_add(&mis, est);
            est = 0.0;
            if (vbl_vrl_pair_draw(&p, x1, x2, &smp)) est = integrand(&q, smp.u, smp.v) / smp.pdf;
            vbl_mean_add(&prod, est);
        }
        char label[96];
        snprintf(label, sizeof label, "camera MIS mean %s", kGeoms[i].name);
        ok &= vbl_mean_check(label, &mis, ref, 4.0, 1e-6 * ref);
        printf("     relative stderr: MIS %.3g, product sampler alone %.3g\n", vbl_mean_stderr(&mis) / ref,
               vbl_mean_stderr(&prod) / ref);
    }
    assert_true(ok);
}

int main(int argc, char** argv)
{
    if (argc > 1) cmocka_set_test_filter(argv[1]);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_camera_mis_chi2),
        cmocka_unit_test(test_camera_mis_unbiased),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
