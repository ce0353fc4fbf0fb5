/* The stop latch of the blue-noise preparation's parallel loops (vbl_bn_prepare_options.stop). */
#ifndef VBL_BLUE_NOISE_STOP_LATCH_H
#define VBL_BLUE_NOISE_STOP_LATCH_H

/* 1 when iteration i is to be skipped: *stopped is already set, or stop(user) (asked every 256
 * iterations; NULL: never) says stop now, which sets *stopped for the other threads. */
static inline int vbl_bn_stop_latch(int* stopped, long long i, int (*stop)(void*), void* user)
{
    int s;
#pragma omp atomic read
    s = *stopped;
    if (s) return 1;
    if ((i & 255) == 0 && stop && stop(user)) {
#pragma omp atomic write
        *stopped = 1;
        return 1;
    }
    return 0;
}

#endif
