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

/* Length of a "%[0][width]d" conversion at p (p[0] == '%'), else 0. */
static size_t vbl_frames_conversion(const char* p, int* width, int* zero)
{
    size_t i = 1;
    *zero = 0;
    *width = 0;
    if (p[i] == '0') {
        *zero = 1;
        ++i;
    }
    while (p[i] >= '0' && p[i] <= '9' && *width < 100) *width = *width * 10 + (p[i++] - '0');
    return p[i] == 'd' ? i + 1 : 0;
}

int vbl_frames_has_pattern(const char* path)
{
    if (!path) return 0;
    for (const char* p = path; *p; ++p) {
        int width, zero;
        if (*p == '#') return 1;
        if (*p == '%' && vbl_frames_conversion(p, &width, &zero)) return 1;
        if (*p == '%' && p[1] == '%') ++p;
    }
    return 0;
}

int vbl_frames_format(const char* pattern, int frame, char* out, size_t size)
{
    size_t n = 0;
    for (const char* p = pattern; *p;) {
        char piece[128];
        size_t len = 1, used = 1;
        int width = 0, zero = 0;
        if (*p == '#') {
            while (p[width] == '#') ++width;
            used = (size_t)width;
            len = (size_t)snprintf(piece, sizeof piece, "%0*d", width, frame);
        } else if (*p == '%' && p[1] == '%') {
            used = 2;
            piece[0] = '%';
        } else if (*p == '%') {
            used = vbl_frames_conversion(p, &width, &zero);
            if (!used) return -1;
            len = (size_t)(zero ? snprintf(piece, sizeof piece, "%0*d", width, frame)
                                : snprintf(piece, sizeof piece, "%*d", width, frame));
        } else {
            piece[0] = *p;
        }
        if (len >= sizeof piece || n + len + 1 > size) return -1;
        memcpy(out + n, piece, len);
        n += len;
        p += used;
    }
    if (n + 1 > size) return -1;
    out[n] = 0;
    return 0;
}
