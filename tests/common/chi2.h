/* Statistical helpers for sampling tests: chi-square goodness of fit with pooling of sparse
 * cells and Sidak-corrected significance, plus mean-within-k-standard-errors checks. */
#ifndef VBL_TEST_CHI2_H
#define VBL_TEST_CHI2_H

#ifdef __cplusplus
extern "C" {
#endif

typedef struct vbl_chi2_result {
    double statistic;  /* Pearson chi-square over the pooled cells */
    int dof;           /* pooled cells - 1 */
    double p_value;    /* P(chi2_dof >= statistic) */
    int cells;         /* cells after pooling */
    int outside;       /* observations in cells whose expected count is 0 (impossible samples) */
    double observed_total, expected_total;
} vbl_chi2_result;

/* Pearson chi-square of observed vs expected counts (n cells). Cells with expected count below
 * min_expected (5 is customary) are pooled, smallest first, until each pooled cell reaches it.
 * Cells with expected 0 and observed > 0 are counted in `outside`. */
vbl_chi2_result vbl_chi2_compute(const double* observed, const double* expected, int n, double min_expected);

/* Upper tail of the chi-square distribution: Q(dof/2, x/2) (regularised incomplete gamma). */
double vbl_chi2_survival(double x, double dof);

/* Per-test significance so that `tests` independent tests have family-wise level alpha:
 * 1 - (1 - alpha)^(1/tests) (Sidak). */
double vbl_sidak_alpha(double alpha, int tests);

/* Runs the test, prints one line (label, statistic, dof, p) and returns 1 if the fit is accepted:
 * no outside samples, p >= Sidak-corrected alpha, and at least one degree of freedom. */
int vbl_chi2_check(const char* label, const double* observed, const double* expected, int n, double alpha,
                   int tests);

/* Running mean / standard error. */
typedef struct vbl_mean_acc { double n, mean, m2; } vbl_mean_acc;
void vbl_mean_add(vbl_mean_acc* a, double x);
double vbl_mean_stderr(const vbl_mean_acc* a);
/* Prints and returns 1 if |mean - reference| <= k stderr (+ abs_slack for the reference's own error). */
int vbl_mean_check(const char* label, const vbl_mean_acc* a, double reference, double k, double abs_slack);

#ifdef __cplusplus
}
#endif

#endif
