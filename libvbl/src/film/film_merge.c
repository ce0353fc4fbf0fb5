/* Merging films of disjoint pass ranges (vbl/vbl_film.h): double running sums per channel, one
 * film at a time, with the rules the `vbl merge` command had on EXR channels (weighted means by
 * passes, summed samples, variance of the mean, Z weighted by passes x alpha, beauty re-summed). */
#include <stdio.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "film/film.h"

typedef enum vbl_merge_rule {
    VBL_MERGE_RULE_MEAN = 0,     /* sum n_i x_i / N */
    VBL_MERGE_RULE_SUM = 1,      /* sum x_i */
    VBL_MERGE_RULE_VARIANCE = 2, /* sum n_i^2 x_i / N^2 */
    VBL_MERGE_RULE_DEPTH = 3     /* sum n_i A_i x_i / sum n_i A_i over x_i > 0 */
} vbl_merge_rule;

typedef struct vbl_merge_layer {
    char name[32];
    int channels;
    char channel_names[4][16];
    vbl_merge_rule rule;
    double* sum;    /* n * channels */
    double* weight; /* DEPTH: sum n_i A_i */
    double* plain;  /* DEPTH: sum n_i x_i (where no film has a weight) */
    double* misses; /* DEPTH: sum n_i over films with x_i = VBL_FILM_Z_MISS */
} vbl_merge_layer;

typedef struct vbl_merge_range {
    int first, passes;
} vbl_merge_range;

struct vbl_film_merger {
    int count; /* films added */
    int width, height;
    vbl_film_stats stats; /* the first film's, with the sums so far */
    int layer_count;
    vbl_merge_layer layers[VBL_FILM_MAX_LAYERS];
    vbl_merge_range* ranges;
    int range_capacity;
};

static vbl_merge_rule vbl_merge_rule_of(const char* layer)
{
    if (!strcmp(layer, "Z")) return VBL_MERGE_RULE_DEPTH;
    if (!strcmp(layer, "samples")) return VBL_MERGE_RULE_SUM;
    if (!strcmp(layer, "variance")) return VBL_MERGE_RULE_VARIANCE;
    return VBL_MERGE_RULE_MEAN; /* transport layers, the beauty (R, G, B re-summed at the end), others */
}

static void vbl_merger_clear(vbl_film_merger* m)
{
    for (int k = 0; k < m->layer_count; ++k) {
        free(m->layers[k].sum);
        free(m->layers[k].weight);
        free(m->layers[k].plain);
        free(m->layers[k].misses);
    }
    free(m->ranges);
    memset(m, 0, sizeof *m);
}

vbl_result vbl_film_merger_create(vbl_film_merger** out_merger)
{
    if (!out_merger) return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_film_merger_create: NULL argument");
    *out_merger = calloc(1, sizeof **out_merger);
    return *out_merger ? VBL_SUCCESS : vbl_error(VBL_ERROR_OUT_OF_MEMORY, "vbl_film_merger_create: out of memory");
}

void vbl_film_merger_destroy(vbl_film_merger* merger)
{
    if (!merger) return;
    vbl_merger_clear(merger);
    free(merger);
}

/* The first film fixes the size, the layers and the identity. */
static vbl_result vbl_merger_start(vbl_film_merger* m, const vbl_film* film)
{
    m->width = film->width;
    m->height = film->height;
    m->stats = film->stats;
    m->stats.passes = 0;
    m->stats.render_seconds = 0.0;
    m->stats.cancelled = m->stats.time_limited = 0;
    const size_t n = (size_t)film->width * (size_t)film->height;
    for (int k = 0; k < film->layer_count; ++k) {
        const vbl_film_layer_data* src = &film->layers[k];
        vbl_merge_layer* l = &m->layers[m->layer_count++];
        snprintf(l->name, sizeof l->name, "%s", src->name);
        l->channels = src->channels;
        for (int c = 0; c < src->channels; ++c) snprintf(l->channel_names[c], sizeof l->channel_names[c], "%s", src->channel_names[c]);
        l->rule = vbl_merge_rule_of(src->name);
        size_t values = n * (size_t)src->channels;
        l->sum = calloc(values ? values : 1, sizeof(double));
        if (l->rule == VBL_MERGE_RULE_DEPTH) {
            l->weight = calloc(values ? values : 1, sizeof(double));
            l->plain = calloc(values ? values : 1, sizeof(double));
            l->misses = calloc(values ? values : 1, sizeof(double));
        }
        if (!l->sum || (l->rule == VBL_MERGE_RULE_DEPTH && (!l->weight || !l->plain || !l->misses)))
            return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "vbl_film_merger_add: out of memory for the running sums");
    }
    return VBL_SUCCESS;
}

/* Same render, same layers, a pass range of its own. */
static vbl_result vbl_merger_check(const vbl_film_merger* m, const vbl_film* film)
{
    const int i = m->count;
    if (film->width != m->width || film->height != m->height)
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_film_merge: film %d is %dx%d, film 0 is %dx%d", i,
                         film->width, film->height, m->width, m->height);
    const vbl_film_stats* a = &m->stats;
    const vbl_film_stats* b = &film->stats;
    if (a->method != b->method || a->spp != b->spp || a->light_paths != b->light_paths || a->seed != b->seed)
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT,
                         "vbl_film_merge: film %d is not the same render as film 0 (method %s / %s, spp %d / %d, "
                         "light paths %d / %d, seed %llu / %llu)",
                         i, vbl_render_method_name(b->method), vbl_render_method_name(a->method), b->spp, a->spp,
                         b->light_paths, a->light_paths, (unsigned long long)b->seed, (unsigned long long)a->seed);
    if (a->hybrid != b->hybrid || a->hybrid_pt_classes != b->hybrid_pt_classes || a->hybrid_pt_spp != b->hybrid_pt_spp)
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT,
                         "vbl_film_merge: film %d's hybrid plan (pt classes 0x%x, pt_spp %d) is not film 0's (0x%x, %d)", i,
                         (unsigned)b->hybrid_pt_classes, b->hybrid_pt_spp, (unsigned)a->hybrid_pt_classes, a->hybrid_pt_spp);
    if (a->transparent != b->transparent)
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_film_merge: film %d is %s, film 0 is %s", i,
                         b->transparent ? "transparent" : "opaque", a->transparent ? "transparent" : "opaque");
    if (film->layer_count != m->layer_count)
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_film_merge: film %d has %d layers, film 0 has %d", i,
                         film->layer_count, m->layer_count);
    for (int k = 0; k < m->layer_count; ++k) {
        const vbl_merge_layer* l = &m->layers[k];
        const vbl_film_layer_data* src = NULL;
        for (int j = 0; j < film->layer_count; ++j)
            if (!strcmp(film->layers[j].name, l->name)) src = &film->layers[j];
        if (!src || src->channels != l->channels)
            return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_film_merge: film %d %s layer '%s' as film 0 has it", i,
                             src ? "does not have the" : "has no", l->name);
        for (int c = 0; c < l->channels; ++c)
            if (strcmp(src->channel_names[c], l->channel_names[c]))
                return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_film_merge: film %d layer '%s' channel %d is %s, not %s",
                                 i, l->name, c, src->channel_names[c], l->channel_names[c]);
    }
    const long long first = b->first_pass, last = first + b->passes - 1;
    for (int j = 0; j < m->count; ++j) {
        const vbl_merge_range* r = &m->ranges[j];
        if (first <= (long long)r->first + r->passes - 1 && r->first <= last)
            return vbl_error(VBL_ERROR_INVALID_ARGUMENT,
                             "vbl_film_merge: film %d (passes %lld-%lld) overlaps film %d (passes %d-%d): pass ranges "
                             "must be disjoint",
                             i, first, last, j, r->first, r->first + r->passes - 1);
    }
    return VBL_SUCCESS;
}

vbl_result vbl_film_merger_add(vbl_film_merger* m, const vbl_film* film)
{
    if (!m || !film) return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_film_merger_add: NULL argument");
    if (film->stats.passes < 1)
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_film_merge: film %d has no passes", m->count);
    if ((long long)m->stats.passes + film->stats.passes > INT_MAX)
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT,
                         "vbl_film_merge: film %d: the films' passes add up beyond the 2147483647 a film holds (a "
                         "film's pass count is wrong)",
                         m->count);
    vbl_result r = m->count == 0 ? vbl_merger_start(m, film) : vbl_merger_check(m, film);
    if (r) {
        if (m->count == 0) vbl_merger_clear(m);
        return r;
    }
    if (m->count == m->range_capacity) {
        int capacity = m->range_capacity ? 2 * m->range_capacity : 16;
        vbl_merge_range* grown = realloc(m->ranges, sizeof *grown * (size_t)capacity);
        if (!grown) return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "vbl_film_merger_add: out of memory");
        m->ranges = grown;
        m->range_capacity = capacity;
    }
    m->ranges[m->count].first = film->stats.first_pass;
    m->ranges[m->count].passes = film->stats.passes;

    const size_t n = (size_t)m->width * (size_t)m->height;
    const double p = film->stats.passes;
    const float* alpha = NULL; /* the beauty's A, for Z */
    for (int j = 0; j < film->layer_count; ++j)
        if (!film->layers[j].name[0] && film->layers[j].channels == 4) alpha = film->layers[j].pixels + 3;
    for (int k = 0; k < m->layer_count; ++k) {
        vbl_merge_layer* l = &m->layers[k];
        const float* x = NULL;
        for (int j = 0; j < film->layer_count; ++j)
            if (!strcmp(film->layers[j].name, l->name)) x = film->layers[j].pixels;
        const size_t values = n * (size_t)l->channels;
        switch (l->rule) {
        case VBL_MERGE_RULE_SUM:
            for (size_t v = 0; v < values; ++v) l->sum[v] += x[v];
            break;
        case VBL_MERGE_RULE_VARIANCE:
            for (size_t v = 0; v < values; ++v) l->sum[v] += p * p * x[v];
            break;
        case VBL_MERGE_RULE_DEPTH:
            for (size_t v = 0; v < values; ++v) {
                double a = alpha ? alpha[4 * (v / (size_t)l->channels)] : 1.0;
                /* Z = 0 (files before VBL_FILM_Z_MISS) or VBL_FILM_Z_MISS: no collision, no depth */
                const int miss = !(x[v] > 0.0f && x[v] < VBL_FILM_Z_MISS);
                double w = !miss && a > 0.0 ? p * a : 0.0;
                l->sum[v] += w * x[v];
                l->weight[v] += w;
                l->plain[v] += p * x[v];
                if (x[v] >= VBL_FILM_Z_MISS) l->misses[v] += p;
            }
            break;
        default:
            for (size_t v = 0; v < values; ++v) l->sum[v] += p * x[v];
            break;
        }
    }
    m->stats.passes += film->stats.passes;
    if (film->stats.first_pass < m->stats.first_pass) m->stats.first_pass = film->stats.first_pass;
    m->stats.render_seconds += film->stats.render_seconds;
    m->stats.cancelled |= film->stats.cancelled;
    m->stats.time_limited |= film->stats.time_limited;
    ++m->count;
    return VBL_SUCCESS;
}

vbl_result vbl_film_merger_finish(vbl_film_merger* m, vbl_film** out_film)
{
    if (out_film) *out_film = NULL;
    if (!m || !out_film) return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_film_merger_finish: NULL argument");
    if (m->count == 0) return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_film_merge: no films");
    vbl_film* film = NULL;
    vbl_result r = vbl_film_create(m->width, m->height, &m->stats, &film);
    const size_t n = (size_t)m->width * (size_t)m->height;
    const double N = m->stats.passes;
    float* out = NULL;
    for (int k = 0; !r && k < m->layer_count; ++k) {
        const vbl_merge_layer* l = &m->layers[k];
        const size_t values = n * (size_t)l->channels;
        out = malloc(sizeof(float) * (values ? values : 1));
        if (!out) {
            r = vbl_error(VBL_ERROR_OUT_OF_MEMORY, "vbl_film_merge: out of memory");
            break;
        }
        for (size_t v = 0; v < values; ++v) {
            double x;
            switch (l->rule) {
            case VBL_MERGE_RULE_SUM: x = l->sum[v]; break;
            case VBL_MERGE_RULE_VARIANCE: x = l->sum[v] / (N * N); break;
            case VBL_MERGE_RULE_DEPTH:
                x = l->weight[v] > 0.0 ? l->sum[v] / l->weight[v]
                                       : (l->misses[v] >= N ? (double)VBL_FILM_Z_MISS : l->plain[v] / N);
                break;
            default: x = l->sum[v] / N; break;
            }
            out[v] = (float)x;
        }
        const char* names[4] = {l->channel_names[0], l->channel_names[1], l->channel_names[2], l->channel_names[3]};
        r = vbl_film_add_layer(film, l->name, l->channels, names, out);
        free(out);
    }
    /* the beauty R, G, B: the float sum of the merged transport layers in class order, as vbl_render
     * builds it, so that the layers still add up to it exactly */
    vbl_film_layer_data* beauty = NULL;
    const vbl_film_layer_data* transport[VBL_CLASS_COUNT] = {NULL};
    int transport_count = 0;
    for (int j = 0; film && j < film->layer_count; ++j) {
        if (!film->layers[j].name[0] && film->layers[j].channels >= 3) beauty = &film->layers[j];
        for (int c = 0; c < VBL_CLASS_COUNT; ++c)
            if (film->layers[j].channels == 3 && !strcmp(film->layers[j].name, vbl_transport_class_name((vbl_transport_class)c)))
                transport[c] = &film->layers[j], ++transport_count;
    }
    if (!r && beauty && transport_count > 0)
        for (size_t i = 0; i < n; ++i)
            for (int k = 0; k < 3; ++k) {
                float sum = 0.0f;
                for (int c = 0; c < VBL_CLASS_COUNT; ++c)
                    if (transport[c] && vbl_film_class_in_beauty(c, m->stats.transparent))
                        sum += transport[c]->pixels[3 * i + (size_t)k];
                beauty->pixels[(size_t)beauty->channels * i + (size_t)k] = sum;
            }
    if (!r && film) r = vbl_film_compute_totals(film); /* exact sums of the merged classes */
    vbl_merger_clear(m);
    if (r) {
        vbl_film_release(film);
        return r;
    }
    *out_film = film;
    return VBL_SUCCESS;
}

vbl_result vbl_film_merge(const vbl_film* const* films, int count, vbl_film** out_film)
{
    if (out_film) *out_film = NULL;
    if (!films || count < 1 || !out_film)
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_film_merge: no films (count = %d)", count);
    vbl_film_merger* m = NULL;
    vbl_result r = vbl_film_merger_create(&m);
    for (int i = 0; !r && i < count; ++i)
        r = films[i] ? vbl_film_merger_add(m, films[i])
                     : vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_film_merge: film %d is NULL", i);
    if (!r) r = vbl_film_merger_finish(m, out_film);
    vbl_film_merger_destroy(m);
    return r;
}
