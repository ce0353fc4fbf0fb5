/* The render options table (vbl/vbl_render_options.h) at run time: descriptors, defaults, the one
 * validator, text set/get and the options hash. */
#include "render/options.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "scene/scene.h"
#include "vbl/vbl_film.h"

#define VBL_OPT_TYPE_NAME_INT "int"
#define VBL_OPT_TYPE_NAME_UINT64 "uint64"
#define VBL_OPT_TYPE_NAME_DOUBLE "double"
#define VBL_OPT_TYPE_NAME_BOOL "bool"
#define VBL_OPT_TYPE_NAME_ENUM "enum"

#define VBL_OPT_DESC_(prefix, name, member, ctype, type, key, flag, def, lo, hi, flags, choices, effect, help)              \
    {#name, key, flag, VBL_OPTION_##type, VBL_OPT_TYPE_NAME_##type, (double)(def), (double)(lo), (double)(hi), \
     (flags), choices, VBL_OPTION_EFFECT_##effect, help},
static const vbl_render_option_info vbl_option_descs[VBL_OPT_COUNT] = {
    VBL_RENDER_OPTION_LIST(VBL_OPT_DESC_, VBL_OPT_SKIP_)};

/* ---- typed access by index (generated) ----------------------------------------------------- */

double vbl_option_number(const vbl_render_options* o, int index)
{
    switch (index) {
#define VBL_OPT_GET_(prefix, name, member, ...) \
    case VBL_OPT_##name: return (double)o->prefix member;
        VBL_RENDER_OPTION_LIST(VBL_OPT_GET_, VBL_OPT_SKIP_)
    default: return 0.0;
    }
}

static void vbl_option_store(vbl_render_options* o, int index, double v)
{
    switch (index) {
#define VBL_OPT_SET_(prefix, name, member, ctype, ...) \
    case VBL_OPT_##name: o->prefix member = (ctype)v; break;
        VBL_RENDER_OPTION_LIST(VBL_OPT_SET_, VBL_OPT_SKIP_)
    default: break;
    }
}

/* uint64 options exactly (the others never come here) */
#define VBL_OPT_U64_INT(x) 0
#define VBL_OPT_U64_DOUBLE(x) 0
#define VBL_OPT_U64_BOOL(x) 0
#define VBL_OPT_U64_ENUM(x) 0
#define VBL_OPT_U64_UINT64(x) (x)
#define VBL_OPT_U64_SET_INT(field, ctype, v)
#define VBL_OPT_U64_SET_DOUBLE(field, ctype, v)
#define VBL_OPT_U64_SET_BOOL(field, ctype, v)
#define VBL_OPT_U64_SET_ENUM(field, ctype, v)
#define VBL_OPT_U64_SET_UINT64(field, ctype, v) field = (ctype)(v);
static uint64_t vbl_option_u64(const vbl_render_options* o, int index)
{
    switch (index) {
#define VBL_OPT_GET_U64_(prefix, name, member, ctype, type, ...) \
    case VBL_OPT_##name: return (uint64_t)VBL_OPT_U64_##type(o->prefix member);
        VBL_RENDER_OPTION_LIST(VBL_OPT_GET_U64_, VBL_OPT_SKIP_)
    default: return 0;
    }
}

static void vbl_option_store_u64(vbl_render_options* o, int index, uint64_t v)
{
    switch (index) {
#define VBL_OPT_SET_U64_(prefix, name, member, ctype, type, ...) \
    case VBL_OPT_##name: VBL_OPT_U64_SET_##type(o->prefix member, ctype, v) break;
        VBL_RENDER_OPTION_LIST(VBL_OPT_SET_U64_, VBL_OPT_SKIP_)
    default: break;
    }
}

/* ---- checks -------------------------------------------------------------------------------- */

static void vbl_option_bound(double v, char* out, size_t size)
{
    if (isinf(v)) snprintf(out, size, "%s", v > 0 ? "inf" : "-inf");
    else snprintf(out, size, "%.15g", v);
}

/* "pt, vpl, vrl" from "pt|vpl|vrl" (strict ZERO_DEFAULT enums: without choice 0). */
static void vbl_option_enum_list(const vbl_render_option_info* d, int strict, char* out, size_t size)
{
    out[0] = 0;
    const char* p = d->choices ? d->choices : "";
    size_t len = 0;
    for (int k = 0; *p || k == 0; ++k) {
        size_t n = strcspn(p, "|");
        if (!(k == 0 && strict && (d->flags & VBL_OPTION_ZERO_DEFAULT)) && len < size) {
            int w = snprintf(out + len, size - len, "%s%.*s", len ? ", " : "", (int)n, p);
            if (w > 0) len += (size_t)w;
        }
        p += n;
        if (*p != '|') break;
        ++p;
    }
}

int vbl_option_enum_value(int index, const char* name, int strict)
{
    if (index < 0 || index >= VBL_OPT_COUNT || !name) return -1;
    const vbl_render_option_info* d = &vbl_option_descs[index];
    const char* p = d->choices ? d->choices : "";
    for (int k = 0;; ++k) {
        size_t n = strcspn(p, "|");
        if (n == strlen(name) && !strncmp(p, name, n))
            return k == 0 && strict && (d->flags & VBL_OPTION_ZERO_DEFAULT) ? -1 : k;
        p += n;
        if (*p != '|') return -1;
        ++p;
    }
}

int vbl_option_check_number(int index, double v, int strict, char* why, size_t size)
{
    if (index < 0 || index >= VBL_OPT_COUNT) {
        snprintf(why, size, "is not an option");
        return 1;
    }
    const vbl_render_option_info* d = &vbl_option_descs[index];
    if (!isfinite(v)) {
        snprintf(why, size, "= %g must be a finite number", v);
        return 1;
    }
    if (d->type != VBL_OPTION_DOUBLE && v != floor(v)) {
        snprintf(why, size, d->type == VBL_OPTION_BOOL ? "must be true or false" : "must be an integer");
        return 1;
    }
    if ((d->flags & VBL_OPTION_ZERO_DEFAULT) && v == 0.0 && !strict) return 0;
    const int lo_ok = (d->flags & VBL_OPTION_MIN_OPEN) ? v > d->min : v >= d->min;
    const int hi_ok = (d->flags & VBL_OPTION_MAX_OPEN) ? v < d->max : v <= d->max;
    if (d->type == VBL_OPTION_ENUM) {
        if (lo_ok && hi_ok && !(strict && (d->flags & VBL_OPTION_ZERO_DEFAULT) && v == 0.0)) return 0;
        char list[512];
        vbl_option_enum_list(d, strict, list, sizeof list);
        snprintf(why, size, "= %.17g is not one of %s", v, list);
        return 1;
    }
    if (d->type == VBL_OPTION_BOOL) {
        if (v == 0.0 || v == 1.0) return 0;
        snprintf(why, size, "= %.17g must be 0 or 1 (false or true)", v);
        return 1;
    }
    if (lo_ok && hi_ok) return 0;
    char lo[64], hi[64];
    vbl_option_bound(d->min, lo, sizeof lo);
    vbl_option_bound(d->max, hi, sizeof hi);
    if (d->type == VBL_OPTION_DOUBLE)
        snprintf(why, size, "= %g is outside %c%s, %s%c", v, (d->flags & VBL_OPTION_MIN_OPEN) ? '(' : '[', lo, hi,
                 (d->flags & VBL_OPTION_MAX_OPEN) || isinf(d->max) ? ')' : ']');
    else
        snprintf(why, size, "= %.17g is outside %c%s, %s%c", v, (d->flags & VBL_OPTION_MIN_OPEN) ? '(' : '[', lo, hi,
                 (d->flags & VBL_OPTION_MAX_OPEN) ? ')' : ']');
    return 1;
}

int vbl_option_assign_number(vbl_render_options* o, int index, double v, int strict, char* why, size_t size)
{
    if (vbl_option_check_number(index, v, strict, why, size)) return 1;
    if (vbl_option_descs[index].type == VBL_OPTION_UINT64) vbl_option_store_u64(o, index, (uint64_t)v);
    else vbl_option_store(o, index, v);
    return 0;
}

/* hybrid_pt_classes as text: comma-separated layer names (vbl_transport_class_parse) -> the bit mask. */
static int vbl_option_assign_classes(vbl_render_options* o, int index, const char* text, int strict, char* why,
                                     size_t size)
{
    int mask = 0;
    const char* p = text;
    for (;;) {
        size_t n = strcspn(p, ",");
        char name[64];
        vbl_transport_class c;
        if (n == 0 || n >= sizeof name) {
            snprintf(why, size, "= \"%s\" is not a bit mask or a comma-separated list of layer names", text);
            return 1;
        }
        memcpy(name, p, n);
        name[n] = '\0';
        if (vbl_transport_class_parse(name, &c) != VBL_SUCCESS) {
            vbl_clear_error();
            snprintf(why, size, "= \"%s\": \"%s\" is not a transport class layer (background, surface_direct, ...)",
                     text, name);
            return 1;
        }
        mask |= 1 << (int)c;
        if (!p[n]) break;
        p += n + 1;
    }
    return vbl_option_assign_number(o, index, mask, strict, why, size);
}

int vbl_option_assign_text(vbl_render_options* o, int index, const char* text, int strict, char* why, size_t size)
{
    if (index < 0 || index >= VBL_OPT_COUNT) {
        snprintf(why, size, "is not an option");
        return 1;
    }
    const vbl_render_option_info* d = &vbl_option_descs[index];
    if (!text) text = "";
    char* end = NULL;
    errno = 0;
    switch (d->type) {
    case VBL_OPTION_UINT64: {
        unsigned long long u = strtoull(text, &end, 10);
        if (text[0] < '0' || text[0] > '9' || errno || !end || *end) {
            snprintf(why, size, "= \"%s\" is not an integer in [0, 18446744073709551615]", text);
            return 1;
        }
        vbl_option_store_u64(o, index, (uint64_t)u);
        return 0;
    }
    case VBL_OPTION_INT: {
        long long v = strtoll(text, &end, 10);
        if (index == VBL_OPT_hybrid_pt_classes && (end == text || (end && *end))) /* layer names */
            return vbl_option_assign_classes(o, index, text, strict, why, size);
        if (errno || !end || *end || end == text) {
            snprintf(why, size, "= \"%s\" is not an integer", text);
            return 1;
        }
        return vbl_option_assign_number(o, index, (double)v, strict, why, size);
    }
    case VBL_OPTION_DOUBLE: {
        double v = strtod(text, &end);
        if (errno || !end || *end || end == text || !isfinite(v)) {
            snprintf(why, size, "= \"%s\" is not a finite number", text);
            return 1;
        }
        return vbl_option_assign_number(o, index, v, strict, why, size);
    }
    case VBL_OPTION_BOOL: {
        int v = -1;
        if (!strcmp(text, "true") || !strcmp(text, "on") || !strcmp(text, "1")) v = 1;
        if (!strcmp(text, "false") || !strcmp(text, "off") || !strcmp(text, "0")) v = 0;
        if (v < 0) {
            snprintf(why, size, "= \"%s\" must be true or false", text);
            return 1;
        }
        return vbl_option_assign_number(o, index, v, strict, why, size);
    }
    case VBL_OPTION_ENUM: {
        int v = vbl_option_enum_value(index, text, strict);
        if (v < 0) {
            char list[512];
            vbl_option_enum_list(d, strict, list, sizeof list);
            snprintf(why, size, "= \"%s\" is not one of %s", text, list);
            return 1;
        }
        return vbl_option_assign_number(o, index, v, strict, why, size);
    }
    }
    return 1;
}

/* ---- public -------------------------------------------------------------------------------- */

int vbl_render_option_count(void) { return VBL_OPT_COUNT; }

const vbl_render_option_info* vbl_render_option_desc(int index)
{
    return index >= 0 && index < VBL_OPT_COUNT ? &vbl_option_descs[index] : NULL;
}

int vbl_render_option_find(const char* name)
{
    if (!name) return -1;
    for (int i = 0; i < VBL_OPT_COUNT; ++i) {
        const vbl_render_option_info* d = &vbl_option_descs[i];
        if (!strcmp(d->name, name) || (d->key && !strcmp(d->key, name)) || (d->flag && !strcmp(d->flag, name)))
            return i;
    }
    return -1;
}

void vbl_render_options_init(vbl_render_options* options)
{
    if (options) *options = (vbl_render_options)VBL_RENDER_OPTIONS_DEFAULT;
}

int vbl_render_options_light_paths(const vbl_render_options* o)
{
    if (!o) return 0;
    if (o->light_paths > 0) return o->light_paths;
    switch (o->method) {
    case VBL_RENDER_VRL: return VBL_LIGHT_PATHS_DEFAULT_VRL;
    case VBL_RENDER_VBL: return VBL_LIGHT_PATHS_DEFAULT_VBL;
    default: return VBL_LIGHT_PATHS_DEFAULT;
    }
}

int vbl_render_light_paths(const vbl_scene* scene, const vbl_render_options* o)
{
    if (!o || o->light_paths > 0 || !scene) return vbl_render_options_light_paths(o);
    if ((o->method == VBL_RENDER_VRL || o->method == VBL_RENDER_VBL) && !scene->has_surfaces)
        return VBL_LIGHT_PATHS_DEFAULT_VL_MEDIA_ONLY;
    return vbl_render_options_light_paths(o);
}

vbl_result vbl_render_options_validate(const vbl_render_options* o)
{
    if (!o) return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_render: NULL options");
    if (o->size < sizeof(vbl_render_options))
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_render: options.size is too small");
    char why[1024];
    for (int i = 0; i < VBL_OPT_COUNT; ++i) {
        if (vbl_option_descs[i].type == VBL_OPTION_UINT64) continue; /* every value is valid */
        if (vbl_option_check_number(i, vbl_option_number(o, i), 0, why, sizeof why))
            return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_render: %s %s", vbl_option_descs[i].name, why);
    }
    if ((long long)o->first_pass + (long long)o->passes > 0x7fffffffLL)
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_render: first_pass + passes overflows");
    return VBL_SUCCESS;
}

static vbl_result vbl_render_option_set_mode(vbl_render_options* options, const char* name, const char* value,
                                             int strict, const char* fn)
{
    if (!options || !name || !value) return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "%s: NULL argument", fn);
    int i = vbl_render_option_find(name);
    if (i < 0) return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "%s: unknown render option '%s'", fn, name);
    char why[1024];
    if (vbl_option_assign_text(options, i, value, strict, why, sizeof why))
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "%s: %s %s", fn, vbl_option_descs[i].name, why);
    return VBL_SUCCESS;
}

vbl_result vbl_render_option_set(vbl_render_options* options, const char* name, const char* value)
{
    return vbl_render_option_set_mode(options, name, value, 0, "vbl_render_option_set");
}

vbl_result vbl_render_option_set_strict(vbl_render_options* options, const char* name, const char* value)
{
    return vbl_render_option_set_mode(options, name, value, 1, "vbl_render_option_set_strict");
}

vbl_result vbl_render_option_get(const vbl_render_options* options, const char* name, char* out, size_t size)
{
    if (!options || !name || !out || size == 0)
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_render_option_get: NULL argument");
    int i = vbl_render_option_find(name);
    if (i < 0) return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_render_option_get: unknown render option '%s'", name);
    const vbl_render_option_info* d = &vbl_option_descs[i];
    double v = vbl_option_number(options, i);
    int n = 0;
    switch (d->type) {
    case VBL_OPTION_UINT64: n = snprintf(out, size, "%llu", (unsigned long long)vbl_option_u64(options, i)); break;
    case VBL_OPTION_INT: n = snprintf(out, size, "%lld", (long long)v); break;
    case VBL_OPTION_DOUBLE: /* the shortest text that reads back as v */
        for (int digits = 15; digits <= 17; ++digits) {
            n = snprintf(out, size, "%.*g", digits, v);
            if (n < 0 || (size_t)n >= size || strtod(out, NULL) == v) break;
        }
        break;
    case VBL_OPTION_BOOL: n = snprintf(out, size, "%s", v != 0.0 ? "true" : "false"); break;
    case VBL_OPTION_ENUM: {
        const char* p = d->choices ? d->choices : "";
        int k = 0;
        while (k < (int)v && (p = strchr(p, '|')) != NULL) ++p, ++k;
        if (p && v >= 0.0 && k == (int)v) n = snprintf(out, size, "%.*s", (int)strcspn(p, "|"), p);
        else n = snprintf(out, size, "%lld", (long long)v);
        break;
    }
    }
    if (n < 0 || (size_t)n >= size)
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_render_option_get: %s does not fit in %zu bytes", name, size);
    return VBL_SUCCESS;
}

void vbl_render_options_hash(const vbl_render_options* o, char* out, size_t size)
{
    if (!out || size == 0) return;
    char text[8192];
    size_t len = 0;
    text[0] = 0;
    /* The options older than the grouped table in their old (flat) order, then the others in table
     * order: files written before the groups keep their hash. */
    static const int legacy[] = {VBL_OPT_max_bounces, VBL_OPT_transmittance, VBL_OPT_mis, VBL_OPT_vrl_samples,
                                 VBL_OPT_vrl_long, VBL_OPT_vrl_connect_march, VBL_OPT_vrl_march_step,
                                 VBL_OPT_vrl_prune_radius, VBL_OPT_vrl_prune_min_probability,
                                 VBL_OPT_vpl_clamp_distance, VBL_OPT_vbl_radius0, VBL_OPT_vbl_alpha,
                                 VBL_OPT_vbl_single_scattering, VBL_OPT_beams_radius0, VBL_OPT_beams_alpha,
                                 VBL_OPT_vsl_placement, VBL_OPT_vsl_path_extension, VBL_OPT_vsl_lights,
                                 VBL_OPT_vrl_select, VBL_OPT_pt_equiangular, VBL_OPT_transmittance_majorant_scale};
    enum { n_legacy = (int)(sizeof legacy / sizeof legacy[0]) };
    int order[VBL_OPT_COUNT], n = 0, seen[VBL_OPT_COUNT] = {0};
    for (int k = 0; k < n_legacy; ++k) order[n++] = legacy[k], seen[legacy[k]] = 1;
    for (int i = 0; i < VBL_OPT_COUNT; ++i)
        if (!seen[i]) order[n++] = i;
    for (int k = 0; o && k < n; ++k) {
        const int i = order[k];
        const vbl_render_option_info* d = &vbl_option_descs[i];
        if (d->effect != VBL_OPTION_EFFECT_HASH) continue;
        double v = vbl_option_number(o, i);
        if (i == VBL_OPT_vrl_select) {
            /* hashed against 0, its default before VBL_VRL_SELECT_DEFAULT, for vrl and vbl (which use
             * it): their files written before keep their hash, and a film of the former default
             * (every VRL) merges only with --vrl-select 0; the other methods omit it at either value */
            const int uses = o->method == VBL_RENDER_VRL || o->method == VBL_RENDER_VBL;
            if (v == 0.0 || (!uses && v == d->default_value)) continue;
        } else if (i == VBL_OPT_hybrid) {
            /* pt renders auto as off, so its hash omits the option at either value (pt files of every
             * version keep their hash); the virtual-light methods hash it against its default, auto.
             * A film of the former default (off, written before session 8) therefore has the hash of
             * an auto film, and the films' recorded plans (vbl:hybrid, film_merge.c) keep the two
             * apart; an off film of now has hybrid=0 in its hash */
            if (v == d->default_value || (o->method == VBL_RENDER_PT && v == VBL_HYBRID_OFF)) continue;
        } else if (!(d->flags & VBL_OPTION_HASH_ALWAYS) && v == d->default_value)
            continue;
        /* as files written before the table have them: on = 1, off = 0; 0 lights = the default */
        if (i == VBL_OPT_vsl_path_extension) v = v == VBL_VSL_PATH_EXTENSION_OFF ? 0.0 : 1.0;
        if (i == VBL_OPT_vsl_lights && !(v > 0.0)) v = VBL_VSL_LIGHTS_DEFAULT;
        int w = d->type == VBL_OPTION_DOUBLE
                    ? snprintf(text + len, sizeof text - len, "%s%s=%.17g", len ? ";" : "", d->name, v)
                    : snprintf(text + len, sizeof text - len, "%s%s=%lld", len ? ";" : "", d->name, (long long)v);
        if (w > 0 && (size_t)w < sizeof text - len) len += (size_t)w;
    }
    uint64_t h = 0xcbf29ce484222325ull;
    for (const char* p = text; *p; ++p) h = (h ^ (unsigned char)*p) * 0x100000001b3ull;
    snprintf(out, size, "fnv1a64:%016llx", (unsigned long long)h);
}

vbl_result vbl_render_options_create(vbl_render_options** out_options)
{
    if (!out_options) return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_render_options_create: NULL argument");
    *out_options = malloc(sizeof **out_options);
    if (!*out_options) return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "vbl_render_options_create: out of memory");
    vbl_render_options_init(*out_options);
    return VBL_SUCCESS;
}

void vbl_render_options_destroy(vbl_render_options* options) { free(options); }

void vbl_render_options_set_callback(vbl_render_options* options, vbl_render_pass_callback callback, void* user_data)
{
    if (!options) return;
    options->callback = callback;
    options->callback_user_data = user_data;
}
