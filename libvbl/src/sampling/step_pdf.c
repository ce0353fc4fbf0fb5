/* Piecewise-constant 1D density (step_pdf.h). */
#include "sampling/step_pdf.h"

#include <math.h>

int vbl_step_pdf_init(vbl_step_pdf* p, const double* x, const double* y, int n, double defensive)
{
    p->count = 0;
    if (n < 1 || n > VBL_STEP_PDF_MAX_PIECES || !(defensive >= 0.0 && defensive < 1.0)) return 0;
    if (!isfinite(x[0]) || !isfinite(x[n]) || !(x[n] > x[0])) return 0;
    p->defensive = defensive;
    p->x[0] = x[0];
    p->cdf[0] = 0.0;
    for (int k = 0; k < n; ++k) {
        if (!isfinite(x[k + 1]) || x[k + 1] < x[k]) return 0;
        p->x[k + 1] = x[k + 1];
        p->y[k] = y[k] > 0.0 && isfinite(y[k]) ? y[k] : 0.0;
        p->cdf[k + 1] = p->cdf[k] + p->y[k] * (x[k + 1] - x[k]);
    }
    if (!(p->cdf[n] > 0.0 && isfinite(p->cdf[n]))) p->defensive = 1.0; /* uniform fallback */
    p->count = n;
    return 1;
}

/* Index k of the piece holding x (x_k <= x < x_{k+1}, the last piece for x = x_n). */
static int piece_of(const vbl_step_pdf* p, double x)
{
    int lo = 0, hi = p->count - 1;
    while (lo < hi) {
        int mid = (lo + hi + 1) >> 1;
        if (p->x[mid] <= x) lo = mid;
        else hi = mid - 1;
    }
    return lo;
}

double vbl_step_pdf_pdf(const vbl_step_pdf* p, double x)
{
    const int n = p->count;
    if (n < 1 || !(x >= p->x[0] && x <= p->x[n])) return 0.0;
    const double width = p->x[n] - p->x[0];
    double d = p->defensive / width;
    if (p->defensive < 1.0) d += (1.0 - p->defensive) * p->y[piece_of(p, x)] / p->cdf[n];
    return d;
}

double vbl_step_pdf_sample(const vbl_step_pdf* p, double xi, double* pdf)
{
    const int n = p->count;
    if (n < 1) {
        if (pdf) *pdf = 0.0;
        return 0.0;
    }
    const double a = p->x[0], b = p->x[n];
    double x;
    if (xi < p->defensive || p->defensive >= 1.0) {
        x = a + (b - a) * (p->defensive > 0.0 ? xi / p->defensive : xi);
    } else {
        /* the step part: find the piece whose CDF interval holds the target mass */
        double target = (xi - p->defensive) / (1.0 - p->defensive) * p->cdf[n];
        int lo = 0, hi = n - 1;
        while (lo < hi) {
            int mid = (lo + hi + 1) >> 1;
            if (p->cdf[mid] <= target) lo = mid;
            else hi = mid - 1;
        }
        while (lo < n - 1 && !(p->y[lo] > 0.0)) ++lo; /* never land in an empty piece */
        double mass = p->y[lo] * (p->x[lo + 1] - p->x[lo]);
        double f = mass > 0.0 ? (target - p->cdf[lo]) / mass : 0.0;
        x = p->x[lo] + (p->x[lo + 1] - p->x[lo]) * (f < 0.0 ? 0.0 : (f > 1.0 ? 1.0 : f));
        /* stay inside piece lo (its right edge belongs to the next piece, which may be empty) */
        if (x >= p->x[lo + 1] && lo + 1 < n) x = nextafter(p->x[lo + 1], p->x[lo]);
        if (x < p->x[lo]) x = p->x[lo];
    }
    x = x < a ? a : (x > b ? b : x);
    if (pdf) *pdf = vbl_step_pdf_pdf(p, x);
    return x;
}
