/* EXR <-> film for merging (exr_film.h). */
#define _POSIX_C_SOURCE 200809L
#include "exr_film.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* R, G, B, A, Y first (the film's channel order), then the others in file order. */
static int vbl_exr_film_rank(const char* channel)
{
    static const char* const order[5] = {"R", "G", "B", "A", "Y"};
    for (int i = 0; i < 5; ++i)
        if (!strcmp(channel, order[i])) return i;
    return 5;
}

static void vbl_exr_film_split(const char* full, char* layer, size_t size, const char** channel)
{
    const char* dot = strrchr(full, '.');
    if (!dot) { /* beauty R, G, B, A or Z */
        snprintf(layer, size, "%s", strcmp(full, "Z") ? "" : "Z");
        *channel = full;
        return;
    }
    snprintf(layer, size, "%.*s", (int)(dot - full), full);
    *channel = dot + 1;
}

static int vbl_exr_film_attr_int(const vbl_exr_image* image, const char* name, long long* out)
{
    const char* text = vbl_exr_image_attribute(image, name, NULL);
    if (!text) return 0;
    char* end = NULL;
    long long v = strtoll(text, &end, 10);
    if (!end || *end || end == text) return 0;
    *out = v;
    return 1;
}

vbl_result vbl_cli_film_from_exr(const vbl_exr_image* image, const char* path, int passes, vbl_film** out_film)
{
    *out_film = NULL;
    vbl_film_stats stats;
    memset(&stats, 0, sizeof stats);
    stats.size = sizeof stats;
    long long v = 0;
    const char* method = vbl_exr_image_attribute(image, "vbl:method", NULL);
    if (method && vbl_render_method_parse(method, &stats.method)) vbl_clear_error();
    if (vbl_exr_film_attr_int(image, "vbl:spp", &v)) stats.spp = (int)v;
    if (vbl_exr_film_attr_int(image, "vbl:light_paths", &v)) stats.light_paths = (int)v;
    const char* seed = vbl_exr_image_attribute(image, "vbl:seed", NULL);
    if (seed) stats.seed = strtoull(seed, NULL, 10);
    stats.passes = passes >= 1 ? passes : (vbl_exr_film_attr_int(image, "vbl:passes", &v) ? (int)v : 0);
    if (vbl_exr_film_attr_int(image, "vbl:first_pass", &v)) stats.first_pass = (int)v;
    if (vbl_exr_film_attr_int(image, "vbl:transparent", &v)) stats.transparent = v != 0;
    const char* seconds = vbl_exr_image_attribute(image, "vbl:render_seconds", NULL);
    if (seconds) stats.render_seconds = atof(seconds);
    const int w = vbl_exr_image_width(image), h = vbl_exr_image_height(image);
    vbl_film* film = NULL;
    vbl_result r = vbl_film_create(w, h, &stats, &film);
    char why[1024];
    if (r) {
        snprintf(why, sizeof why, "%s", vbl_last_error_message());
        return vbl_report_error(r, "%s: %s", path, why);
    }
    const size_t n = (size_t)w * (size_t)h;
    const int count = vbl_exr_image_channel_count(image);
    char* done = calloc((size_t)(count > 0 ? count : 1), 1);
    float* pixels = malloc(sizeof(float) * 4 * (n ? n : 1));
    if (!done || !pixels) r = vbl_report_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    for (int c = 0; !r && c < count; ++c) {
        if (done[c]) continue;
        char layer[256];
        const char* first = NULL;
        vbl_exr_film_split(vbl_exr_image_channel_name(image, c), layer, sizeof layer, &first);
        /* the channels of this layer, ranked */
        int members[4], ranks[4], m = 0;
        for (int d = c; d < count; ++d) {
            char other[256];
            const char* channel = NULL;
            vbl_exr_film_split(vbl_exr_image_channel_name(image, d), other, sizeof other, &channel);
            if (done[d] || strcmp(other, layer)) continue;
            if (m == 4) {
                r = vbl_report_error(VBL_ERROR_CORRUPT_FILE, "%s: layer '%s' has more than 4 channels", path, layer);
                break;
            }
            int rank = vbl_exr_film_rank(channel), k = m++;
            while (k > 0 && ranks[k - 1] > rank) members[k] = members[k - 1], ranks[k] = ranks[k - 1], --k;
            members[k] = d, ranks[k] = rank;
            done[d] = 1;
        }
        if (r) break;
        const char* names[4];
        char split_layer[256];
        for (int k = 0; k < m; ++k) {
            vbl_exr_film_split(vbl_exr_image_channel_name(image, members[k]), split_layer, sizeof split_layer, &names[k]);
            const float* src = vbl_exr_image_channel_pixels(image, members[k]);
            for (size_t i = 0; i < n; ++i) pixels[(size_t)m * i + (size_t)k] = src[i];
        }
        r = vbl_film_add_layer(film, layer, m, names, pixels);
        if (r) {
            snprintf(why, sizeof why, "%s", vbl_last_error_message());
            r = vbl_report_error(r, "%s: %s", path, why);
        }
    }
    free(done);
    free(pixels);
    if (r) {
        vbl_film_release(film);
        return r;
    }
    *out_film = film;
    return VBL_SUCCESS;
}

int vbl_cli_film_channel(const vbl_film* film, const char* name, float* out, size_t n)
{
    char layer[256];
    const char* channel = NULL;
    vbl_exr_film_split(name, layer, sizeof layer, &channel);
    int channels = 0;
    const float* pixels = vbl_film_layer(film, layer, &channels);
    if (!pixels) return 0;
    for (int k = 0; k < channels; ++k) {
        const char* cn = vbl_film_layer_channel_name(film, layer, k);
        if (!cn || strcmp(cn, channel)) continue;
        for (size_t i = 0; i < n; ++i) out[i] = pixels[(size_t)channels * i + (size_t)k];
        return 1;
    }
    return 0;
}
