/* `--frames` specs and frame patterns in paths (frames.h). */
#define _POSIX_C_SOURCE 200809L
#include "frames.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int vbl_frames_number(const char** p, long* out)
{
    const char* s = *p;
    if (*s < '0' || *s > '9') return 0;
    char* end = NULL;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (errno || v > 100000000L) return 0;
    *out = v;
    *p = end;
    return 1;
}

int vbl_frames_parse(const char* spec, int** out, char* err, size_t err_size)
{
    *out = NULL;
    size_t count = 0, cap = 0;
    int* frames = NULL;
    const char* p = spec;
    if (!p || !*p) {
        snprintf(err, err_size, "--frames: empty frame list");
        return 0;
    }
    while (*p) {
        const char* item = p;
        long first = 0, last = 0, step = 1;
        int ok = vbl_frames_number(&p, &first);
        last = first;
        if (ok && *p == '-') {
            ++p;
            ok = vbl_frames_number(&p, &last);
            if (ok && *p == 'x') {
                ++p;
                ok = vbl_frames_number(&p, &step) && step >= 1;
            }
        }
        if (ok && *p && *p != ',') ok = 0;
        if (!ok || last < first) {
            size_t n = strcspn(item, ",");
            snprintf(err, err_size,
                     "--frames: '%.*s' is not a frame, range or stepped range (5, 1-10, 1-100x2; frames >= 0, "
                     "ascending)",
                     (int)n, item);
            free(frames);
            return 0;
        }
        for (long f = first; f <= last; f += step) {
            if (count >= VBL_FRAMES_MAX) {
                snprintf(err, err_size, "--frames: more than %d frames", VBL_FRAMES_MAX);
                free(frames);
                return 0;
            }
            if (count == cap) {
                cap = cap ? 2 * cap : 64;
                int* grown = realloc(frames, cap * sizeof *frames);
                if (!grown) {
                    snprintf(err, err_size, "--frames: out of memory");
                    free(frames);
                    return 0;
                }
                frames = grown;
            }
            frames[count++] = (int)f;
        }
        if (*p == ',') {
            ++p;
            if (!*p) {
                snprintf(err, err_size, "--frames: trailing ','");
                free(frames);
                return 0;
            }
        }
    }
    *out = frames;
    return (int)count;
}
