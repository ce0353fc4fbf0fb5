/* Writing the layers and header of `vbl render -o` (vbl_render_exr.h): HALF rules, compression,
 * tiles, colour space and chromaticities. */
#include <string.h>

#include "vbl_render_exr.h"

static int vbl_render_exr_list_has(const char* list, const char* name)
{
    size_t len = strlen(name);
    for (const char* p = list; p && *p;) {
        size_t n = strcspn(p, ",");
        if (n == len && !strncmp(p, name, n)) return 1;
        p += n;
        if (*p == ',') ++p;
    }
    return 0;
}

static int vbl_render_exr_store_half(const vbl_render_exr_settings* s, const char* name, vbl_render_exr_kind kind)
{
    if (kind == VBL_RENDER_EXR_Z || kind == VBL_RENDER_EXR_SAMPLES) return 0;
    return s->half_all || vbl_render_exr_list_has(s->half_layers, kind == VBL_RENDER_EXR_BEAUTY ? "beauty" : name);
}

vbl_result vbl_render_exr_write_layers(const char* path, int width, int height, const vbl_render_exr_settings* s,
                                       const vbl_render_exr_layers* L, const vbl_render_exr_meta* m)
{
    static const char* const z_names[1] = {"Z"};
    static const char* const y_names[1] = {"Y"};
    vbl_exr_layer layers[VBL_RENDER_EXR_MAX_LAYERS];
    for (int i = 0; i < L->count; ++i) {
        vbl_exr_layer* l = &layers[i];
        memset(l, 0, sizeof *l);
        l->name = L->kinds[i] == VBL_RENDER_EXR_Z ? "" : L->names[i];
        l->channel_count = L->channels[i];
        l->channel_names = L->kinds[i] == VBL_RENDER_EXR_Z ? z_names : (L->channels[i] == 1 ? y_names : NULL);
        l->pixels = L->pixels[i];
        l->store_half = vbl_render_exr_store_half(s, L->names[i], L->kinds[i]);
    }
    vbl_exr_write_options wo = VBL_EXR_WRITE_OPTIONS_DEFAULT;
    wo.attributes = m->attrs;
    /* oiio:ColorSpace, last: written by the EXR writer (wo.color_space) */
    wo.attribute_count = m->count - (s->output_space && m->count > 0 ? 1 : 0);
    if (s->compression >= 0) wo.compression = (vbl_exr_compression)s->compression;
    wo.tiled = s->tiled;
    wo.tile_size = s->tile_size;
    wo.color_space = s->output_space;
    wo.chromaticities = s->have_chroma ? s->chroma : NULL;
    return vbl_exr_write(path, width, height, layers, L->count, &wo);
}

vbl_result vbl_render_exr_write_film(const char* path, const vbl_film* film, const vbl_render_exr_settings* s,
                                     const vbl_render_options* options, int passes_requested, const char* status,
                                     double render_seconds)
{
    vbl_film_stats stats;
    memset(&stats, 0, sizeof stats);
    stats.size = sizeof stats;
    vbl_result r = vbl_film_get_stats(film, &stats);
    if (r) return r;
    if (!status) status = stats.time_limited ? "time_limit" : (stats.cancelled ? "interrupted" : "complete");
    if (render_seconds < 0.0) render_seconds = stats.render_seconds;
    vbl_render_exr_layers L;
    r = vbl_render_exr_layers_make(s, film, &L);
    if (r) return r;
    vbl_render_exr_meta m;
    vbl_render_exr_meta_make(s, &stats, options, stats.passes, stats.first_pass, passes_requested, status,
                             render_seconds, &m);
    r = vbl_render_exr_write_layers(path, vbl_film_width(film), vbl_film_height(film), s, &L, &m);
    vbl_render_exr_layers_free(&L);
    return r;
}
