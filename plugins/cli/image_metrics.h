/* Image difference metrics (pure functions, no I/O): relative mean absolute error, RMSE and
 * maximum absolute error of an image A against a reference B. Used by `vbl diff` and
 * benchmarks; channels are addressed by pointer + pixel stride, so planar (EXR reader, stride 1)
 * and interleaved (film layers, stride = channel count) buffers both work. */
#ifndef VBL_IMAGE_METRICS_H
#define VBL_IMAGE_METRICS_H

#include <stddef.h>

typedef struct vbl_image_metrics {
    double rmae;          /* mean over pixels and channels of |A-B| / (|B| + 0.01 mean|B|) */
    double rmse;          /* sqrt(mean (A-B)^2) */
    double max_abs;       /* max |A-B| */
    double mean_abs_ref;  /* mean |B| over pixels and channels */
    size_t pixels;
    int channels;
    size_t non_finite;    /* values where A or B is NaN/Inf (left out of every metric) */
} vbl_image_metrics;

/* The rMAE offset: 0.01 * mean|B|; when the reference is entirely zero, 0.01 is used instead
 * so the metric stays finite (it then equals 100 * mean|A-B|). */
double vbl_image_metrics_offset(double mean_abs_ref);

/* Metrics of `channels` channels over `pixels` pixels: channel c of pixel p is
 * a[c][p * stride] (resp. b). B is the reference. */
void vbl_image_metrics_compute(const float* const* a, const float* const* b, int channels,
                               size_t pixels, size_t stride, vbl_image_metrics* out);

#endif
