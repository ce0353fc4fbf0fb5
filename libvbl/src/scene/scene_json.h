/* Typed, validated reads from cJSON objects for the scene loader. Every failure records
 * "<file>: <field> ..." with VBL_ERROR_SCENE and returns it. `field` is the full field path of
 * the value read, e.g. "media[0].phase.g". */
#ifndef VBL_SCENE_SCENE_JSON_H
#define VBL_SCENE_SCENE_JSON_H

#include <cjson/cJSON.h>

#include "core/math.h"
#include "vbl/vbl_core.h"

typedef struct vbl_json_ctx {
    const char* path; /* scene file path as given, for messages */
} vbl_json_ctx;

/* Records "<path>: <message>" with VBL_ERROR_SCENE. */
vbl_result vbl_json_fail(const vbl_json_ctx* ctx, const char* fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/* Joins a parent field path and a key: "media[0]" + "phase" -> "media[0].phase". */
void vbl_json_field(char* out, size_t size, const char* parent, const char* key);

/* Fails on keys of `object` not in the NULL-terminated `allowed` list (keys starting with '_'
 * are comments and always allowed). */
vbl_result vbl_json_check_keys(const vbl_json_ctx* ctx, const cJSON* object, const char* field,
                               const char* const* allowed);

/* Optional values keep *out when the key is absent; required ones fail. */
vbl_result vbl_json_object(const vbl_json_ctx* ctx, const cJSON* parent, const char* parent_field,
                           const char* key, int required, const cJSON** out);
vbl_result vbl_json_number(const vbl_json_ctx* ctx, const cJSON* parent, const char* parent_field,
                           const char* key, int required, double* out);
vbl_result vbl_json_int(const vbl_json_ctx* ctx, const cJSON* parent, const char* parent_field,
                        const char* key, int required, double min, double max, double* out);
vbl_result vbl_json_string(const vbl_json_ctx* ctx, const cJSON* parent, const char* parent_field,
                           const char* key, int required, const char** out);
vbl_result vbl_json_vec3(const vbl_json_ctx* ctx, const cJSON* parent, const char* parent_field,
                         const char* key, int required, vbl_vec3* out);
/* RGB: a number (grey) or [r, g, b]; every component finite and in [min, max]. */
vbl_result vbl_json_rgb(const vbl_json_ctx* ctx, const cJSON* parent, const char* parent_field,
                        const char* key, int required, double min, double max, vbl_vec3* out);

#endif
