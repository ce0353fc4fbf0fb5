/* Image difference metrics: rMAE, RMSE, max abs error against a reference (image_metrics.h). */
#include "image_metrics.h"

#include <math.h>
#include <string.h>

double vbl_image_metrics_offset(double mean_abs_ref)
{
    return mean_abs_ref > 0.0 ? 0.01 * mean_abs_ref : 0.01;
}

void vbl_image_metrics_compute(const float* const* a, const float* const* b, int channels,
                               size_t pixels, size_t stride, vbl_image_metrics* out)
{
    memset(out, 0, sizeof *out);
    out->pixels = pixels;
    out->channels = channels;
    if (channels <= 0 || pixels == 0) return;
    /* First pass: mean |B| over finite pairs (the rMAE offset). */
    double sum_ref = 0.0;
    size_t count = 0;
    for (int c = 0; c < channels; ++c)
        for (size_t p = 0; p < pixels; ++p) {
            double va = a[c][p * stride], vb = b[c][p * stride];
            if (!isfinite(va) || !isfinite(vb)) continue;
            sum_ref += fabs(vb);
            ++count;
        }
    out->non_finite = (size_t)channels * pixels - count;
    if (count == 0) return;
    out->mean_abs_ref = sum_ref / (double)count;
    const double offset = vbl_image_metrics_offset(out->mean_abs_ref); /* > 0: no division by 0 */
    double sum_rel = 0.0, sum_sq = 0.0, max_abs = 0.0;
    for (int c = 0; c < channels; ++c)
        for (size_t p = 0; p < pixels; ++p) {
            double va = a[c][p * stride], vb = b[c][p * stride];
            if (!isfinite(va) || !isfinite(vb)) continue;
            double d = fabs(va - vb);
            sum_rel += d / (fabs(vb) + offset);
            sum_sq += d * d;
            if (d > max_abs) max_abs = d;
        }
    out->rmae = sum_rel / (double)count;
    out->rmse = sqrt(sum_sq / (double)count);
    out->max_abs = max_abs;
}
