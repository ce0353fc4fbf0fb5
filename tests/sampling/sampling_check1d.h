/* Shared 1D check for sampling tests: chi-square of a sampler against the integral of its pdf
 * over bins, sample/pdf consistency, in-domain samples and normalisation. Header-only (static). */
#ifndef VBL_TEST_SAMPLING_CHECK1D_H
#define VBL_TEST_SAMPLING_CHECK1D_H

#include <math.h>
#include <stdint.h>
#include <stdio.h>

#include "chi2.h"
#include "core/rng.h"
#include "quad.h"

typedef double (*check1d_sample_fn)(void* ctx, double xi, double* pdf);
typedef double (*check1d_pdf_fn)(void* ctx, double x);

typedef struct check1d_pdf_ctx { check1d_pdf_fn pdf; void* ctx; } check1d_pdf_ctx;
static double check1d_pdf_thunk(double x, void* c)
{
    const check1d_pdf_ctx* p = (const check1d_pdf_ctx*)c;
    return p->pdf(p->ctx, x);
}

#define CHECK1D_MAX_BINS 64

/* Bins: `nbins` cells whose edges are the sampler's own quantiles (xi = i/nbins; duplicates kept
 * as empty cells) unless `uniform_bins`. Expected counts integrate pdf (adaptive quadrature). */
static int check1d(const char* label, check1d_sample_fn sample, check1d_pdf_fn pdf, void* ctx, double a, double b,
                   int nbins, int uniform_bins, long n, uint64_t seed, int tests)
{
    double edges[CHECK1D_MAX_BINS + 1], obs[CHECK1D_MAX_BINS] = {0}, expct[CHECK1D_MAX_BINS];
    for (int i = 0; i <= nbins; ++i) {
        double p;
        edges[i] = uniform_bins ? a + (b - a) * i / nbins : sample(ctx, (double)i / nbins, &p);
    }
    edges[0] = a;
    edges[nbins] = b;
    for (int i = 1; i <= nbins; ++i)
        if (edges[i] < edges[i - 1]) edges[i] = edges[i - 1];
    vbl_rng rng = vbl_rng_make(seed, 11, 0);
    int ok = 1;
    long bad_consistency = 0, bad_domain = 0;
    for (long s = 0; s < n; ++s) {
        double p = -1.0;
        double x = sample(ctx, vbl_rng_uniform(&rng), &p);
        if (!(x >= a && x <= b) || !isfinite(p) || !(p > 0.0)) {
            ++bad_domain;
            continue;
        }
        double q = pdf(ctx, x);
        if (!(fabs(p - q) <= 1e-9 * fmax(p, q))) ++bad_consistency;
        int bi = 0;
        while (bi + 1 < nbins && x >= edges[bi + 1]) ++bi;
        obs[bi] += 1.0;
    }
    check1d_pdf_ctx pc = {pdf, ctx};
    double total = 0.0;
    for (int i = 0; i < nbins; ++i) {
        double m = vbl_quad_adaptive(check1d_pdf_thunk, &pc, edges[i], edges[i + 1], 1e-14, 1e-11);
        total += m;
        expct[i] = n * m;
    }
    ok &= vbl_chi2_check(label, obs, expct, nbins, 0.01, tests);
    printf("     %s: integral %.12f, out-of-domain %ld, pdf mismatches %ld\n", label, total, bad_domain,
           bad_consistency);
    ok &= fabs(total - 1.0) < 1e-7 && bad_domain == 0 && bad_consistency == 0;
    return ok;
}

#endif
