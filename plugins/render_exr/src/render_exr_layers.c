/* The film's layers as `vbl render -o` writes them (vbl_render_exr.h): AOVs by request, RGB
 * converted to the output space, the beauty and the totals re-summed from the converted classes. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vbl_render_exr.h"

void vbl_render_exr_layers_free(vbl_render_exr_layers* L)
{
    for (int i = 0; i < L->count; ++i) free(L->owned[i]);
    L->count = 0;
}

vbl_result vbl_render_exr_layers_make(const vbl_render_exr_settings* s, const vbl_film* film, vbl_render_exr_layers* L)
{
    memset(L, 0, sizeof *L);
    const size_t n = (size_t)vbl_film_width(film) * (size_t)vbl_film_height(film);
    vbl_film_stats stats;
    memset(&stats, 0, sizeof stats);
    stats.size = sizeof stats;
    vbl_film_get_stats(film, &stats);
    int beauty = -1, transport_count = 0;
    for (int i = 0; i < vbl_film_layer_count(film) && L->count < VBL_RENDER_EXR_MAX_LAYERS; ++i) {
        const char* name = vbl_film_layer_name(film, i);
        vbl_render_exr_kind kind = vbl_render_exr_layer_kind(name);
        if ((kind == VBL_RENDER_EXR_Z && !s->aov_z) || (kind == VBL_RENDER_EXR_SAMPLES && !s->aov_samples) ||
            (kind == VBL_RENDER_EXR_VARIANCE && !s->aov_variance))
            continue;
        int channels = 0;
        const float* px = vbl_film_layer(film, name, &channels);
        if (!px) continue;
        int k = L->count++;
        L->names[k] = name;
        L->pixels[k] = px;
        L->channels[k] = channels;
        L->kinds[k] = kind;
        if (kind == VBL_RENDER_EXR_BEAUTY) beauty = k;
        if (kind == VBL_RENDER_EXR_TRANSPORT) ++transport_count;
        if (!s->convert || channels < 3 || kind == VBL_RENDER_EXR_Z || kind == VBL_RENDER_EXR_SAMPLES) continue;
        float* copy = malloc(sizeof(float) * (n ? n : 1) * (size_t)channels);
        if (!copy) {
            vbl_render_exr_layers_free(L);
            return vbl_report_error(VBL_ERROR_OUT_OF_MEMORY, "out of memory converting colours");
        }
        memcpy(copy, px, sizeof(float) * n * (size_t)channels);
        double m[9];
        for (int e = 0; e < 9; ++e) m[e] = kind == VBL_RENDER_EXR_VARIANCE ? s->matrix[e] * s->matrix[e] : s->matrix[e];
        for (size_t p = 0; p < n; ++p) {
            float* v = copy + p * (size_t)channels;
            double x = v[0], y = v[1], z = v[2];
            for (int r = 0; r < 3; ++r) v[r] = (float)(m[3 * r] * x + m[3 * r + 1] * y + m[3 * r + 2] * z);
        }
        L->owned[k] = copy;
        L->pixels[k] = copy;
    }
    /* the beauty: the sum of the converted classes in film order (float), as the film sums them;
     * a transparent render leaves the background out */
    if (s->convert && beauty >= 0 && transport_count > 0) {
        float* b = L->owned[beauty];
        for (size_t p = 0; p < n; ++p) {
            float sum[3] = {0.0f, 0.0f, 0.0f};
            for (int k = 0; k < L->count; ++k)
                if (L->kinds[k] == VBL_RENDER_EXR_TRANSPORT &&
                    !(stats.transparent && !strcmp(L->names[k], vbl_transport_class_name(VBL_CLASS_BACKGROUND))))
                    for (int c = 0; c < 3; ++c) sum[c] += L->pixels[k][p * (size_t)L->channels[k] + (size_t)c];
            for (int c = 0; c < 3; ++c) b[p * (size_t)L->channels[beauty] + (size_t)c] = sum[c];
        }
    }
    /* the totals, re-summed from the converted classes (class order, float) as the film sums them */
    for (int t = 0; s->convert && t < L->count; ++t) {
        if (L->kinds[t] != VBL_RENDER_EXR_TOTAL || !L->owned[t]) continue;
        const int volume = !strcmp(L->names[t], VBL_FILM_TOTAL_VOLUME_INDIRECT);
        /* the members of the total (vbl/vbl_film.h, VBL_FILM_TOTAL_*), by the library's names */
        const vbl_transport_class members[2] = {
            volume ? VBL_CLASS_VOLUME_FROM_SURFACE : VBL_CLASS_SURFACE_FROM_SURFACE,
            volume ? VBL_CLASS_VOLUME_FROM_VOLUME : VBL_CLASS_SURFACE_FROM_VOLUME};
        const float* src[2] = {NULL, NULL};
        for (int k = 0; k < L->count; ++k)
            for (int m = 0; m < 2; ++m)
                if (L->kinds[k] == VBL_RENDER_EXR_TRANSPORT && !strcmp(L->names[k], vbl_transport_class_name(members[m])))
                    src[m] = L->pixels[k];
        for (size_t v = 0; v < 3 * n; ++v) {
            float sum = 0.0f;
            for (int m = 0; m < 2; ++m)
                if (src[m]) sum += src[m][v];
            L->owned[t][v] = sum;
        }
    }
    return VBL_SUCCESS;
}

void vbl_render_exr_channel_name(const vbl_render_exr_layers* L, int k, int c, char* out, size_t size)
{
    static const char* const rgba[4] = {"R", "G", "B", "A"};
    if (L->kinds[k] == VBL_RENDER_EXR_Z) snprintf(out, size, "Z");
    else if (L->kinds[k] == VBL_RENDER_EXR_BEAUTY) snprintf(out, size, "%s", rgba[c]);
    else snprintf(out, size, "%s.%s", L->names[k], L->channels[k] == 1 ? "Y" : rgba[c]);
}
