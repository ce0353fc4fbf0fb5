/* The `render` block of a scene file from the options table (docs/readme/options_table.md):
 * keys "passes" or "vbl.alpha" (the object render.vbl, key alpha), typed as the table says. */
#include "scene/scene_render_block.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "render/options.h"

#define VBL_RENDER_BLOCK_MAX_KEYS (VBL_OPT_COUNT + 1)

/* The keys allowed in render (group = NULL) or in render.<group>: the leaves of the table's keys,
 * plus the group names at the top. */
static void vbl_render_block_keys(const char* group, size_t group_len, const char** keys, char names[][64])
{
    int n = 0;
    for (int i = 0; i < VBL_OPT_COUNT; ++i) {
        const char* key = vbl_render_option_desc(i)->key;
        if (!key) continue;
        const char* dot = strchr(key, '.');
        const char* leaf = NULL;
        char buf[64];
        if (!group) {
            size_t len = dot ? (size_t)(dot - key) : strlen(key);
            snprintf(buf, sizeof buf, "%.*s", (int)len, key);
            leaf = buf;
        } else if (dot && (size_t)(dot - key) == group_len && !strncmp(key, group, group_len)) {
            leaf = dot + 1;
        }
        if (!leaf) continue;
        int seen = 0;
        for (int k = 0; k < n; ++k) seen |= !strcmp(keys[k], leaf);
        if (seen) continue;
        snprintf(names[n], 64, "%s", leaf);
        keys[n] = names[n];
        ++n;
    }
    keys[n] = NULL;
}

/* One option from its JSON item (present). */
static vbl_result vbl_render_block_value(const vbl_json_ctx* ctx, const cJSON* item, const char* field, int index,
                                         vbl_render_options* o)
{
    const vbl_render_option_info* d = vbl_render_option_desc(index);
    char why[1024];
    double v = 0.0;
    switch (d->type) {
    case VBL_OPTION_BOOL:
        if (!cJSON_IsBool(item)) return vbl_json_fail(ctx, "%s must be true or false", field);
        v = cJSON_IsTrue(item) ? 1.0 : 0.0;
        break;
    case VBL_OPTION_ENUM:
        if (d->flags & VBL_OPTION_JSON_BOOL) { /* true / false: choices 1 / 2 */
            if (!cJSON_IsBool(item)) return vbl_json_fail(ctx, "%s must be true or false", field);
            v = cJSON_IsTrue(item) ? 1.0 : 2.0;
            break;
        }
        if (!cJSON_IsString(item) || !item->valuestring) return vbl_json_fail(ctx, "%s must be a string", field);
        if (vbl_option_assign_text(o, index, item->valuestring, 1, why, sizeof why))
            return vbl_json_fail(ctx, "%s %s", field, why);
        return VBL_SUCCESS;
    default:
        if (cJSON_IsString(item) && item->valuestring && !strcmp(d->name, "hybrid_pt_classes")) { /* layer names */
            if (vbl_option_assign_text(o, index, item->valuestring, 1, why, sizeof why))
                return vbl_json_fail(ctx, "%s %s", field, why);
            return VBL_SUCCESS;
        }
        if (!cJSON_IsNumber(item)) return vbl_json_fail(ctx, "%s must be a number", field);
        v = item->valuedouble;
        if (!isfinite(v)) return vbl_json_fail(ctx, "%s must be finite", field);
        /* a JSON number holds integers exactly up to 2^53 */
        if (d->type == VBL_OPTION_UINT64 && v == floor(v) && !(v >= 0.0 && v <= 9007199254740992.0))
            return vbl_json_fail(ctx, "%s = %.17g is outside [0, 9007199254740992]", field, v);
        break;
    }
    if (vbl_option_assign_number(o, index, v, 1, why, sizeof why)) return vbl_json_fail(ctx, "%s %s", field, why);
    return VBL_SUCCESS;
}

vbl_result vbl_scene_parse_render_block(const vbl_json_ctx* ctx, const cJSON* root, vbl_render_options* o)
{
    const cJSON* render = NULL;
    vbl_result r;
    if ((r = vbl_json_object(ctx, root, "", "render", 0, &render))) return r;
    if (!render) return VBL_SUCCESS;
    const char* keys[VBL_RENDER_BLOCK_MAX_KEYS];
    char names[VBL_RENDER_BLOCK_MAX_KEYS][64];
    vbl_render_block_keys(NULL, 0, keys, names);
    if ((r = vbl_json_check_keys(ctx, render, "render", keys))) return r;
    for (int i = 0; i < VBL_OPT_COUNT; ++i) {
        const char* key = vbl_render_option_desc(i)->key;
        if (!key) continue;
        const char* dot = strchr(key, '.');
        const cJSON* parent = render;
        char field[160];
        snprintf(field, sizeof field, "render.%s", key);
        if (dot) {
            char group[64], group_field[80];
            snprintf(group, sizeof group, "%.*s", (int)(dot - key), key);
            snprintf(group_field, sizeof group_field, "render.%s", group);
            parent = NULL;
            if ((r = vbl_json_object(ctx, render, "render", group, 0, &parent))) return r;
            if (!parent) continue;
            vbl_render_block_keys(group, strlen(group), keys, names);
            if ((r = vbl_json_check_keys(ctx, parent, group_field, keys))) return r;
        }
        const cJSON* item = cJSON_GetObjectItemCaseSensitive(parent, dot ? dot + 1 : key);
        if (item && (r = vbl_render_block_value(ctx, item, field, i, o))) return r;
    }
    return VBL_SUCCESS;
}
