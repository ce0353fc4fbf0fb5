/* The render options table (vbl/vbl_render_options.h) drives every front end the same way:
 * - every option round-trips scene file -> struct -> options hash (a non-default value read from a
 *   `render` block lands in its field, and changes vbl:options_hash exactly for the options whose
 *   effect is HASH);
 * - the library (vbl_render_option_set, vbl_render_options_validate), scene files and `vbl render`
 *   flags reject the same out-of-range values (min - epsilon, max + epsilon; the open bound itself)
 *   and accept the same in-range one;
 * - the options hash of the options older than the table is the formula files were written with
 *   before it (so checkpoints and farm parts of older binaries still merge);
 * - the defaults: VBL_RENDER_OPTIONS_DEFAULT, vbl_render_options_init and the descriptors agree. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "cli_test_util.h"
#include "render_cli.h"
#include "vbl/vbl.h"

static char* dir;

static int setup_each(void** state)
{
    (void)state;
    dir = ct_make_dir();
    return dir ? 0 : -1;
}

static int teardown_each(void** state)
{
    (void)state;
    ct_remove_dir(dir);
    free(dir);
    return 0;
}

/* Field by field (the struct has padding): every option's text, the callbacks and size. */
static int options_equal(const vbl_render_options* a, const vbl_render_options* b)
{
    if (a->size != b->size || a->callback != b->callback || a->callback_user_data != b->callback_user_data) return 0;
    for (int i = 0; i < vbl_render_option_count(); ++i) {
        char x[256], y[256];
        const char* name = vbl_render_option_desc(i)->name;
        if (vbl_render_option_get(a, name, x, sizeof x) || vbl_render_option_get(b, name, y, sizeof y) || strcmp(x, y))
            return 0;
    }
    return 1;
}

/* `value` (JSON text) at the option's scene key inside the render block. */
static void write_render_scene(const char* path, const char* key, const char* value)
{
    char render[512];
    const char* dot = strchr(key, '.');
    if (dot)
        snprintf(render, sizeof render, "{\"%.*s\": {\"%s\": %s}}", (int)(dot - key), key, dot + 1, value);
    else
        snprintf(render, sizeof render, "{\"%s\": %s}", key, value);
    char text[2048];
    snprintf(text, sizeof text,
             "{\"camera\": {\"position\": [0, -3, 0], \"look_at\": [0, 0, 0], \"fov_deg\": 40, \"resolution\": [4, 3]},\n"
             " \"render\": %s}\n",
             render);
    ct_write_file(path, text);
}

/* 0 if the scene loads (then *out receives its render options), else the result. */
static vbl_result load_render(const char* key, const char* json, vbl_render_options* out)
{
    const char* path = ct_path(dir, "scene.json");
    write_render_scene(path, key, json);
    vbl_scene* scene = NULL;
    vbl_result r = vbl_scene_load(path, &scene);
    if (!r) {
        vbl_render_options_init(out);
        r = vbl_scene_render_options(scene, out);
    }
    vbl_scene_release(scene);
    vbl_clear_error();
    return r;
}

/* What `vbl render SCENE -o OUT FLAG VALUE` does with the flag: its own parser
 * (plugins/cli/render_options.c, compiled in): 2 = refused; -1 (goes on to load the scene) -> 3. */
static int cli_exit(const char* flag, const char* value)
{
    char* argv[] = {"render", "scene.json", "-o", "out.exr", (char*)flag, (char*)value, NULL};
    vbl_render_args args;
    int code = vbl_render_parse_args(6, argv, &args);
    return code < 0 ? 3 : code;
}

/* The real binary, for the one flag of the issue (--beams-alpha 1 used to pass the CLI): exit code. */
static int binary_exit(const char* flag, const char* value)
{
    char args[1024];
    snprintf(args, sizeof args, "render '%s' -o '%s' %s '%s'", ct_path(dir, "missing.json"), ct_path(dir, "out.exr"),
             flag, value);
    return ct_vbl_run(args, NULL, 0);
}

/* Text (for the library and the CLI) and JSON of a number as the option's type writes it. */
static void number_text(const vbl_render_option_info* d, double v, char* text, size_t size)
{
    if (d->type == VBL_OPTION_DOUBLE) snprintf(text, size, "%.17g", v);
    else snprintf(text, size, "%.0f", v);
}

/* The enum / bool value k as text and as JSON. */
static void choice_text(const vbl_render_option_info* d, int k, char* text, size_t tsize, char* json, size_t jsize)
{
    if (d->type == VBL_OPTION_BOOL) {
        snprintf(text, tsize, "%s", k ? "true" : "false");
        snprintf(json, jsize, "%s", k ? "true" : "false");
        return;
    }
    const char* p = d->choices;
    for (int i = 0; i < k; ++i) p = strchr(p, '|') + 1;
    snprintf(text, tsize, "%.*s", (int)strcspn(p, "|"), p);
    if (d->flags & VBL_OPTION_JSON_BOOL) snprintf(json, jsize, "%s", k == 1 ? "true" : "false");
    else snprintf(json, jsize, "\"%.200s\"", text);
}

static int choice_count(const vbl_render_option_info* d)
{
    if (d->type == VBL_OPTION_BOOL) return 2;
    int n = 1;
    for (const char* p = d->choices; *p; ++p) n += *p == '|';
    return n;
}

/* A valid value different from the default: text and JSON. */
static void good_value(const vbl_render_option_info* d, char* text, size_t tsize, char* json, size_t jsize)
{
    if (d->type == VBL_OPTION_ENUM || d->type == VBL_OPTION_BOOL) {
        /* the last choice that is not the default ("off", not "on" which the default 0 stands for) */
        int first = (d->flags & VBL_OPTION_ZERO_DEFAULT) ? 1 : 0, k = choice_count(d) - 1;
        while (k == (int)d->default_value) --k;
        assert_true(k >= first);
        choice_text(d, k, text, tsize, json, jsize);
        return;
    }
    double v;
    if (d->type == VBL_OPTION_UINT64) v = 12345.0;
    else if (d->type == VBL_OPTION_INT) v = d->min + 1.0 == d->default_value ? d->min + 2.0 : d->min + 1.0;
    else if (isinf(d->max)) v = d->min + 1.5;
    else v = d->min + 0.25 * (d->max - d->min);
    assert_true(v != d->default_value && v >= d->min && v <= d->max);
    number_text(d, v, text, tsize);
    snprintf(json, jsize, "%s", text);
}

static void test_every_option_round_trips_scene_struct_hash(void** state)
{
    (void)state;
    vbl_render_options defaults = VBL_RENDER_OPTIONS_DEFAULT;
    char default_hash[64];
    vbl_render_options_hash(&defaults, default_hash, sizeof default_hash);
    int checked = 0, hashed = 0;
    for (int i = 0; i < vbl_render_option_count(); ++i) {
        const vbl_render_option_info* d = vbl_render_option_desc(i);
        if (!d->key) continue;
        char text[256], json[256], got[256], hash[64];
        good_value(d, text, sizeof text, json, sizeof json);
        vbl_render_options o;
        assert_int_equal(load_render(d->key, json, &o), VBL_SUCCESS);
        assert_int_equal(vbl_render_option_get(&o, d->name, got, sizeof got), VBL_SUCCESS);
        if (strcmp(got, text)) fail_msg("%s: scene %s read back as %s", d->name, json, got);
        /* only this field moved */
        vbl_render_options expect = defaults;
        assert_int_equal(vbl_render_option_set(&expect, d->name, text), VBL_SUCCESS);
        expect.callback = o.callback;
        expect.callback_user_data = o.callback_user_data;
        if (!options_equal(&expect, &o)) fail_msg("%s: other fields changed", d->name);
        vbl_render_options_hash(&o, hash, sizeof hash);
        if ((strcmp(hash, default_hash) != 0) != (d->effect == VBL_OPTION_EFFECT_HASH))
            fail_msg("%s: options hash %s vs default %s (effect %d)", d->name, hash, default_hash, (int)d->effect);
        hashed += d->effect == VBL_OPTION_EFFECT_HASH;
        ++checked;
    }
    assert_true(checked >= 24);
    assert_true(hashed >= 17);
}

/* Values just outside the range: min - epsilon, max + epsilon (the bound itself when open). */
static int bad_values(const vbl_render_option_info* d, double out[2])
{
    int n = 0;
    if (d->type == VBL_OPTION_INT) {
        out[n++] = d->min - 1.0 == 0.0 && (d->flags & VBL_OPTION_ZERO_DEFAULT) ? -1.0 : d->min - 1.0;
        out[n++] = d->max + 1.0;
        return n;
    }
    if (d->type != VBL_OPTION_DOUBLE) return 0;
    const double eps = 1e-9;
    if (d->flags & VBL_OPTION_MIN_OPEN) out[n++] = d->min == 0.0 && (d->flags & VBL_OPTION_ZERO_DEFAULT) ? -eps : d->min;
    else out[n++] = d->min - eps * (1.0 + fabs(d->min));
    if (!isinf(d->max)) out[n++] = (d->flags & VBL_OPTION_MAX_OPEN) ? d->max : d->max + eps * (1.0 + fabs(d->max));
    return n;
}

static void test_library_scene_and_cli_reject_the_same_values(void** state)
{
    (void)state;
    int rejected = 0, cli_checked = 0;
    for (int i = 0; i < vbl_render_option_count(); ++i) {
        const vbl_render_option_info* d = vbl_render_option_desc(i);
        char text[256], json[256];
        /* the in-range value: everyone takes it */
        good_value(d, text, sizeof text, json, sizeof json);
        vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
        assert_int_equal(vbl_render_option_set(&o, d->name, text), VBL_SUCCESS);
        assert_int_equal(vbl_render_options_validate(&o), VBL_SUCCESS);
        if (d->key) assert_int_equal(load_render(d->key, json, &o), VBL_SUCCESS);
        if (d->flag) {
            int code = cli_exit(d->flag, text);
            if (code != 3) fail_msg("%s %s: the CLI refused a valid value (exit %d)", d->flag, text, code);
            ++cli_checked;
        }
        double bad[2];
        int n = bad_values(d, bad);
        for (int k = 0; k < n; ++k) {
            number_text(d, bad[k], text, sizeof text);
            vbl_render_options p = VBL_RENDER_OPTIONS_DEFAULT;
            if (vbl_render_option_set(&p, d->name, text) != VBL_ERROR_INVALID_ARGUMENT)
                fail_msg("%s = %s: vbl_render_option_set took it", d->name, text);
            vbl_clear_error();
            if (!options_equal(&p, &(vbl_render_options)VBL_RENDER_OPTIONS_DEFAULT))
                fail_msg("%s: a refused set changed the options", d->name);
            if (d->key) {
                if (load_render(d->key, text, &o) != VBL_ERROR_SCENE)
                    fail_msg("render.%s = %s: the scene file took it", d->key, text);
            }
            if (d->flag && cli_exit(d->flag, text) != 2) fail_msg("%s %s: the CLI took it", d->flag, text);
            ++rejected;
        }
        if (d->flags & VBL_OPTION_ZERO_DEFAULT) {
            /* 0 (or choice 0) is the library's stand-in for the default: scene files and flags refuse it */
            vbl_render_options p = VBL_RENDER_OPTIONS_DEFAULT;
            char zero[256], zero_json[256];
            if (d->type == VBL_OPTION_ENUM) choice_text(d, 0, zero, sizeof zero, zero_json, sizeof zero_json);
            else snprintf(zero, sizeof zero, "0"), snprintf(zero_json, sizeof zero_json, "0");
            assert_int_equal(vbl_render_option_set(&p, d->name, zero), VBL_SUCCESS);
            assert_int_equal(vbl_render_options_validate(&p), VBL_SUCCESS);
            assert_int_equal(vbl_render_option_set_strict(&p, d->name, zero), VBL_ERROR_INVALID_ARGUMENT);
            vbl_clear_error();
            if (d->key && !(d->flags & VBL_OPTION_JSON_BOOL))
                assert_int_equal(load_render(d->key, zero_json, &o), VBL_ERROR_SCENE);
            if (d->flag) assert_int_equal(cli_exit(d->flag, zero), 2);
        }
        if (d->type == VBL_OPTION_ENUM || d->type == VBL_OPTION_BOOL) {
            vbl_render_options p = VBL_RENDER_OPTIONS_DEFAULT;
            assert_int_equal(vbl_render_option_set(&p, d->name, "no_such_value"), VBL_ERROR_INVALID_ARGUMENT);
            vbl_clear_error();
            if (d->key) assert_int_equal(load_render(d->key, "\"no_such_value\"", &o), VBL_ERROR_SCENE);
            if (d->flag) assert_int_equal(cli_exit(d->flag, "no_such_value"), 2);
            ++rejected;
        }
    }
    assert_true(rejected >= 34);
    assert_true(cli_checked >= 24);
    /* the binary parses with the same code */
    assert_int_equal(binary_exit("--beams-alpha", "1"), 2);
    assert_int_equal(binary_exit("--beams-alpha", "0.5"), 3);
}

/* vbl_render_options_validate on out-of-range struct fields (callers that write the struct). */
static void test_validator_refuses_struct_fields(void** state)
{
    (void)state;
    vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
    assert_int_equal(vbl_render_options_validate(&o), VBL_SUCCESS);
    o.beams.alpha = 1.0; /* documented (0, 1) everywhere now: the CLI used to take 1 */
    assert_int_equal(vbl_render_options_validate(&o), VBL_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(vbl_last_error_message(), "beams_alpha = 1 is outside (0, 1)"));
    o = (vbl_render_options)VBL_RENDER_OPTIONS_DEFAULT;
    o.method = (vbl_render_method)7;
    assert_int_equal(vbl_render_options_validate(&o), VBL_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(vbl_last_error_message(), "method = 7 is not one of pt, vpl, vrl, vbl, beams"));
    o = (vbl_render_options)VBL_RENDER_OPTIONS_DEFAULT;
    o.beam_lights.alpha = 0.0; /* ZERO_DEFAULT: the library's stand-in for 0.7 */
    o.vsl.lights = 0;
    o.vrl.samples = 0;
    assert_int_equal(vbl_render_options_validate(&o), VBL_SUCCESS);
    assert_int_equal(vbl_render_option_set(&o, "vsl_lights", "0"), VBL_SUCCESS);
    assert_int_equal(vbl_render_option_set_strict(&o, "vsl_lights", "0"), VBL_ERROR_INVALID_ARGUMENT);
    o.vrl.long_vrls = 2;
    assert_int_equal(vbl_render_options_validate(&o), VBL_ERROR_INVALID_ARGUMENT);
    o = (vbl_render_options)VBL_RENDER_OPTIONS_DEFAULT;
    o.first_pass = 2147483647 - 3;
    assert_int_equal(vbl_render_options_validate(&o), VBL_ERROR_INVALID_ARGUMENT);
    vbl_clear_error();
}

/* The formula of vbl:options_hash before the table (render_output.c), as an oracle. */
static void legacy_hash(const vbl_render_options* op, char out[40])
{
    char text[1024];
    snprintf(text, sizeof text,
             "max_bounces=%d;transmittance=%d;mis=%d;vrl_samples=%d;vrl_long=%d;vrl_connect_march=%d;"
             "vrl_march_step=%.17g;vrl_prune_radius=%.17g;vrl_prune_min_probability=%.17g;"
             "vpl_clamp_distance=%.17g;vbl_radius0=%.17g;vbl_alpha=%.17g;vbl_single_scattering=%d;"
             "beams_radius0=%.17g;beams_alpha=%.17g;vsl_placement=%d;vsl_path_extension=%d;vsl_lights=%d",
             op->max_bounces, (int)op->transmittance, (int)op->mis, op->vrl.samples, op->vrl.long_vrls,
             op->vrl.connect, op->vrl.march_step, op->vrl.prune_radius, op->vrl.prune_min_probability,
             op->vpl.clamp_distance, op->beam_lights.radius0, op->beam_lights.alpha, (int)op->beam_lights.single_scattering,
             op->beams.radius0, op->beams.alpha, (int)op->vsl.placement,
             op->vsl.path_extension == VBL_VSL_PATH_EXTENSION_OFF ? 0 : 1,
             op->vsl.lights > 0 ? op->vsl.lights : VBL_VSL_LIGHTS_DEFAULT);
    uint64_t h = 0xcbf29ce484222325ull;
    for (const char* p = text; *p; ++p) h = (h ^ (unsigned char)*p) * 0x100000001b3ull;
    snprintf(out, 40, "fnv1a64:%016llx", (unsigned long long)h);
}

static void test_options_hash_matches_files_before_the_table(void** state)
{
    (void)state;
    vbl_render_options o = VBL_RENDER_OPTIONS_DEFAULT;
    char want[40], got[64];
    legacy_hash(&o, want);
    vbl_render_options_hash(&o, got, sizeof got);
    assert_string_equal(got, want);
    o.vsl.lights = 0; /* the old default spelling hashes as 1024 */
    vbl_render_options_hash(&o, got, sizeof got);
    assert_string_equal(got, want);
    o.max_bounces = 5;
    o.transmittance = VBL_TRANSMITTANCE_DELTA_TRACKING;
    o.mis = VBL_MIS_BALANCE;
    o.vrl.samples = 3;
    o.vrl.long_vrls = 1;
    o.vrl.connect = 1;
    o.vrl.march_step = 0.125;
    o.vrl.prune_radius = 0.3;
    o.vrl.prune_min_probability = 0.2;
    o.vpl.clamp_distance = 0.01;
    o.beam_lights.radius0 = 0.05;
    o.beam_lights.alpha = 0.6;
    o.beam_lights.single_scattering = VBL_SINGLE_SCATTERING_BEAMS;
    o.beams.radius0 = 0.02;
    o.beams.alpha = 0.8;
    o.vsl.placement = VBL_VSL_PLACEMENT_BLUE_NOISE;
    o.vsl.path_extension = VBL_VSL_PATH_EXTENSION_OFF;
    o.vsl.lights = 77;
    o.passes = 99; /* not hashed: passes, seed, spp, ... */
    o.seed = 42;
    o.threads = 3;
    legacy_hash(&o, want);
    vbl_render_options_hash(&o, got, sizeof got);
    assert_string_equal(got, want);
}

static void test_defaults_agree(void** state)
{
    (void)state;
    vbl_render_options a = VBL_RENDER_OPTIONS_DEFAULT, b;
    memset(&b, 0xab, sizeof b);
    vbl_render_options_init(&b);
    assert_true(options_equal(&a, &b));
    assert_int_equal(a.size, sizeof a);
    assert_null(a.callback);
    for (int i = 0; i < vbl_render_option_count(); ++i) {
        const vbl_render_option_info* d = vbl_render_option_desc(i);
        char text[256];
        assert_int_equal(vbl_render_option_get(&a, d->name, text, sizeof text), VBL_SUCCESS);
        vbl_render_options c = VBL_RENDER_OPTIONS_DEFAULT;
        c.passes = 3;
        c.method = VBL_RENDER_VRL;
        c.beam_lights.alpha = 0.5;
        assert_int_equal(vbl_render_option_set(&c, d->name, text), VBL_SUCCESS);
        char back[256];
        assert_int_equal(vbl_render_option_get(&c, d->name, back, sizeof back), VBL_SUCCESS);
        assert_string_equal(text, back);
        assert_int_equal(vbl_render_option_find(d->name), i);
        if (d->key) assert_int_equal(vbl_render_option_find(d->key), i);
        if (d->flag) assert_int_equal(vbl_render_option_find(d->flag), i);
    }
    assert_null(vbl_render_option_desc(vbl_render_option_count()));
    assert_int_equal(vbl_render_option_find("no_such_option"), -1);
    /* the method names of the table are vbl_render_method_name's */
    for (int m = 0; m <= (int)VBL_RENDER_BEAMS; ++m) {
        vbl_render_options c = VBL_RENDER_OPTIONS_DEFAULT;
        c.method = (vbl_render_method)m;
        char text[64];
        assert_int_equal(vbl_render_option_get(&c, "method", text, sizeof text), VBL_SUCCESS);
        assert_string_equal(text, vbl_render_method_name((vbl_render_method)m));
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_every_option_round_trips_scene_struct_hash, setup_each, teardown_each),
        cmocka_unit_test_setup_teardown(test_library_scene_and_cli_reject_the_same_values, setup_each, teardown_each),
        cmocka_unit_test(test_validator_refuses_struct_fields),
        cmocka_unit_test(test_options_hash_matches_files_before_the_table),
        cmocka_unit_test(test_defaults_agree),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
