/* Chi-square goodness of fit and mean checks for sampling tests. */
#include "chi2.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

/* Regularised lower incomplete gamma P(a, x) by its power series (x < a + 1). */
static double gamma_p_series(double a, double x)
{
    double term = 1.0 / a, sum = term;
    for (int k = 1; k < 100000; ++k) {
        term *= x / (a + k);
        sum += term;
        if (fabs(term) < fabs(sum) * 1e-16) break;
    }
    return sum * exp(-x + a * log(x) - lgamma(a));
}

/* Regularised upper incomplete gamma Q(a, x) by its continued fraction (modified Lentz), x >= a + 1. */
static double gamma_q_fraction(double a, double x)
{
    const double tiny = 1e-300;
    double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
    for (int i = 1; i < 100000; ++i) {
        double an = -i * (i - a);
        b += 2.0;
        d = an * d + b;
        if (fabs(d) < tiny) d = tiny;
        c = b + an / c;
        if (fabs(c) < tiny) c = tiny;
        d = 1.0 / d;
        double delta = d * c;
        h *= delta;
        if (fabs(delta - 1.0) < 1e-16) break;
    }
    return exp(-x + a * log(x) - lgamma(a)) * h;
}

double vbl_chi2_survival(double x, double dof)
{
    if (!(x > 0.0)) return 1.0;
    double a = 0.5 * dof, hx = 0.5 * x;
    return hx < a + 1.0 ? 1.0 - gamma_p_series(a, hx) : gamma_q_fraction(a, hx);
}

double vbl_sidak_alpha(double alpha, int tests)
{
    return tests <= 1 ? alpha : -expm1(log1p(-alpha) / tests);
}

typedef struct cell { double obs, exp; } cell;

static int cell_cmp(const void* a, const void* b)
{
    double x = ((const cell*)a)->exp, y = ((const cell*)b)->exp;
    return (x > y) - (x < y);
}

vbl_chi2_result vbl_chi2_compute(const double* observed, const double* expected, int n, double min_expected)
{
    vbl_chi2_result r = {0.0, 0, 1.0, 0, 0, 0.0, 0.0};
    cell* cells = (cell*)malloc(sizeof(cell) * (size_t)(n > 0 ? n : 1));
    int m = 0;
    for (int i = 0; i < n; ++i) {
        r.observed_total += observed[i];
        r.expected_total += expected[i];
        if (!(expected[i] > 0.0)) {
            if (observed[i] > 0.0) r.outside += (int)observed[i];
            continue;
        }
        cells[m].obs = observed[i];
        cells[m].exp = expected[i];
        ++m;
    }
    qsort(cells, (size_t)m, sizeof(cell), cell_cmp);
    double pool_obs = 0.0, pool_exp = 0.0;
    for (int i = 0; i < m; ++i) {
        double o = cells[i].obs, e = cells[i].exp;
        if (pool_exp > 0.0 || e < min_expected) {
            pool_obs += o;
            pool_exp += e;
            if (pool_exp < min_expected && i + 1 < m) continue;
            o = pool_obs;
            e = pool_exp;
            pool_obs = pool_exp = 0.0;
        }
        r.statistic += (o - e) * (o - e) / e;
        r.cells++;
    }
    free(cells);
    r.dof = r.cells - 1;
    r.p_value = r.dof > 0 ? vbl_chi2_survival(r.statistic, r.dof) : 1.0;
    return r;
}

int vbl_chi2_check(const char* label, const double* observed, const double* expected, int n, double alpha,
                   int tests)
{
    vbl_chi2_result r = vbl_chi2_compute(observed, expected, n, 5.0);
    double level = vbl_sidak_alpha(alpha, tests);
    int ok = r.outside == 0 && r.dof > 0 && r.p_value >= level;
    printf("chi2 %-48s stat=%10.2f dof=%4d p=%.4g (level %.3g) outside=%d obs=%.0f exp=%.1f %s\n", label, r.statistic,
           r.dof, r.p_value, level, r.outside, r.observed_total, r.expected_total, ok ? "ok" : "FAIL");
    return ok;
}

void vbl_mean_add(vbl_mean_acc* a, double x)
{
    a->n += 1.0;
    double d = x - a->mean;
    a->mean += d / a->n;
    a->m2 += d * (x - a->mean);
}

double vbl_mean_stderr(const vbl_mean_acc* a)
{
    return a->n > 1.0 ? sqrt(a->m2 / (a->n - 1.0) / a->n) : INFINITY;
}

int vbl_mean_check(const char* label, const vbl_mean_acc* a, double reference, double k, double abs_slack)
{
    double se = vbl_mean_stderr(a);
    double err = fabs(a->mean - reference);
    int ok = isfinite(a->mean) && err <= k * se + abs_slack;
    printf("mean %-48s est=%.8g ref=%.8g |err|=%.3g se=%.3g (%.2f se) %s\n", label, a->mean, reference, err, se,
           se > 0.0 ? err / se : 0.0, ok ? "ok" : "FAIL");
    return ok;
}
