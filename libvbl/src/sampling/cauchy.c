/* Truncated Cauchy sampling, VRL paper eq (14). */
#include "sampling/cauchy.h"

#include "core/math.h"

/* Floored h and the angular width B1 - B0 = atan(uhat1/h) - atan(uhat0/h), computed as
 * atan2((uhat1 - uhat0) h, h^2 + uhat0 uhat1) to avoid cancellation for far, short intervals. */
static int cauchy_setup(double h, double uhat0, double uhat1, double* h_eff, double* width)
{
    if (!(uhat1 > uhat0)) return 0;
    double scale = fmax(fabs(uhat0), fabs(uhat1));
    double hh = fmax(fabs(h), VBL_SAMPLING_H_FLOOR_REL * scale);
    if (!(hh > 0.0)) return 0;
    double w = atan2((uhat1 - uhat0) * hh, hh * hh + uhat0 * uhat1);
    if (!(w > 0.0)) return 0;
    *h_eff = hh;
    *width = w;
    return 1;
}

double vbl_cauchy_sample(double h, double uhat0, double uhat1, double xi, double* pdf)
{
    double hh, width;
    if (!cauchy_setup(h, uhat0, uhat1, &hh, &width)) {
        if (pdf) *pdf = 0.0;
        return uhat0;
    }
    double b0 = atan(uhat0 / hh);
    double x = hh * tan(b0 + vbl_clamp(xi, 0.0, 1.0) * width);
    x = vbl_clamp(x, uhat0, uhat1);
    if (pdf) *pdf = hh / (width * (hh * hh + x * x));
    return x;
}

double vbl_cauchy_pdf(double h, double uhat0, double uhat1, double uhat)
{
    double hh, width;
    if (!cauchy_setup(h, uhat0, uhat1, &hh, &width)) return 0.0;
    if (uhat < uhat0 || uhat > uhat1) return 0.0;
    return hh / (width * (hh * hh + uhat * uhat));
}
