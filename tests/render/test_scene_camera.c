/* Shot controls of scene files (issue #17 part 3): focal length + sensor + fit against the field
 * of view computed by hand as Blender does, the resolution override, named cameras and camera
 * files, frame_media / "camera": "auto" containing the media's bounding box, grid_index, and the
 * refusals. No rendering: loads only (fixtures box.vdb, multi.vdb). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render_test_util.h"
#include "vbl/vbl.h"

static char box_vdb[1024], multi_vdb[1024];

static int setup(void** state)
{
    const char* fixtures = getenv("VBL_FIXTURE_DIR");
    if (!fixtures) return -1;
    snprintf(box_vdb, sizeof box_vdb, "%s/box.vdb", fixtures);
    snprintf(multi_vdb, sizeof multi_vdb, "%s/multi.vdb", fixtures);
    return rt_temp_dir_setup(state);
}

/* A scene with `camera` (the JSON text after "camera": ) and extra top-level text. */
static vbl_result load_with(const char* camera, const char* extra, const vbl_scene_load_options* options,
                            vbl_scene** scene)
{
    char text[8192], path[512];
    snprintf(text, sizeof text,
             "{\"camera\": %s,%s \"lights\": [{\"type\": \"distant\", \"direction\": [0, 0, -1], \"irradiance\": 1}],"
             " \"media\": [{\"vdb\": \"%s\"}]}",
             camera, extra ? extra : "", box_vdb);
    rt_write_file(rt_temp_dir, "scene.json", text, path);
    *scene = NULL;
    return vbl_scene_load_ex(path, options, scene);
}

/* The camera looks along +y with up +z, so worldToNDC has sx = 0.5 / tan(hfov / 2) at [0][0] and
 * -sy = -0.5 / tan(vfov / 2) at [2][1]; returns tan(hfov / 2) and tan(vfov / 2). */
static void tans(const vbl_scene* scene, double* tan_h, double* tan_v)
{
    double w2c[16], w2n[16];
    assert_int_equal(vbl_scene_camera_matrices(scene, w2c, w2n), VBL_SUCCESS);
    *tan_h = 0.5 / w2n[0];
    *tan_v = -0.5 / w2n[9];
}

#define LENS "\"position\": [0.75, -4, 0.75], \"look_at\": [0.75, 0.75, 0.75], \"focal_length\": 50"

static void test_sensor_fit(void** state)
{
    (void)state;
    static const struct {
        const char* lens;
        int w, h;
        double tan_h, tan_v; /* by hand: tan = sensor / (2 f), the other axis through the aspect */
    } cases[] = {
        /* auto, landscape: the 36 mm width spans the width */
        {"", 16, 9, 36.0 / 100.0, 36.0 / 100.0 * 9.0 / 16.0},
        /* auto, portrait: the 36 mm width spans the height */
        {"", 9, 16, 36.0 / 100.0 * 9.0 / 16.0, 36.0 / 100.0},
        /* horizontal with a 24 mm sensor width */
        {", \"sensor_fit\": \"horizontal\", \"sensor_width\": 24", 10, 10, 0.24, 0.24},
        /* vertical: the sensor height (default 24) spans the height */
        {", \"sensor_fit\": \"vertical\"", 16, 9, 24.0 / 100.0 * 16.0 / 9.0, 24.0 / 100.0},
        {", \"sensor_fit\": \"vertical\", \"sensor_height\": 18", 9, 16, 18.0 / 100.0 * 9.0 / 16.0, 18.0 / 100.0},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        char camera[1024];
        snprintf(camera, sizeof camera, "{" LENS "%s, \"resolution\": [%d, %d]}", cases[i].lens, cases[i].w,
                 cases[i].h);
        vbl_scene* scene = NULL;
        if (load_with(camera, NULL, NULL, &scene)) fail_msg("case %zu: %s", i, vbl_last_error_message());
        double th, tv;
        tans(scene, &th, &tv);
        if (fabs(th - cases[i].tan_h) > 1e-12 || fabs(tv - cases[i].tan_v) > 1e-12)
            fail_msg("case %zu: tan h %.15g v %.15g, want %.15g %.15g", i, th, tv, cases[i].tan_h, cases[i].tan_v);
        vbl_scene_release(scene);
    }
}

/* --resolution: the image size changes, the lens keeps its rule (vertical fov, or the fit). */
static void test_resolution_override(void** state)
{
    (void)state;
    vbl_scene_load_options o = VBL_SCENE_LOAD_OPTIONS_DEFAULT;
    o.width = 20;
    o.height = 10;
    vbl_scene* scene = NULL;
    assert_int_equal(load_with("{\"position\": [0.75, -4, 0.75], \"look_at\": [0.75, 0.75, 0.75], \"fov_deg\": 40, "
                               "\"resolution\": [8, 8]}",
                               NULL, &o, &scene),
                     VBL_SUCCESS);
    int w = 0, h = 0;
    vbl_scene_resolution(scene, &w, &h);
    assert_int_equal(w, 20);
    assert_int_equal(h, 10);
    double th, tv;
    tans(scene, &th, &tv);
    assert_float_equal(tv, tan(20.0 * 3.14159265358979323846 / 180.0), 1e-12);
    assert_float_equal(th, 2.0 * tv, 1e-12);
    vbl_scene_release(scene);
    /* focal length: auto fit is re-evaluated for the new aspect (as Blender does) */
    o.width = 10;
    o.height = 20;
    assert_int_equal(load_with("{" LENS ", \"resolution\": [16, 9]}", NULL, &o, &scene), VBL_SUCCESS);
    tans(scene, &th, &tv);
    assert_float_equal(tv, 0.36, 1e-12);
    assert_float_equal(th, 0.18, 1e-12);
    vbl_scene_release(scene);
}

static void test_named_camera_and_file(void** state)
{
    (void)state;
    const char* cameras = " \"cameras\": {\"close\": {\"position\": [0.75, -2, 0.75], \"look_at\": [0.75, 0.75, 0.75],"
                          " \"fov_deg\": 30, \"resolution\": [6, 4]}},";
    vbl_scene_load_options o = VBL_SCENE_LOAD_OPTIONS_DEFAULT;
    o.camera = "close";
    vbl_scene* scene = NULL;
    assert_int_equal(load_with("{" LENS ", \"resolution\": [16, 9]}", cameras, &o, &scene), VBL_SUCCESS);
    int w = 0, h = 0;
    vbl_scene_resolution(scene, &w, &h);
    assert_int_equal(w, 6);
    assert_int_equal(h, 4);
    double w2c[16], w2n[16];
    assert_int_equal(vbl_scene_camera_matrices(scene, w2c, w2n), VBL_SUCCESS);
    assert_float_equal(w2c[14], 2.0, 1e-12); /* the origin is 2 in front of the camera at y = -2 */
    vbl_scene_release(scene);
    /* a camera file, with a resolution override on top */
    char path[512];
    rt_write_file(rt_temp_dir, "cam.json",
                  "{\"camera\": {\"position\": [0.75, -3, 0.75], \"look_at\": [0.75, 0, 0.75], \"fov_deg\": 20, "
                  "\"resolution\": [4, 4]}}",
                  path);
    o.camera = path;
    o.width = 5;
    o.height = 3;
    assert_int_equal(load_with("{" LENS ", \"resolution\": [16, 9]}", cameras, &o, &scene), VBL_SUCCESS);
    vbl_scene_resolution(scene, &w, &h);
    assert_int_equal(w, 5);
    assert_int_equal(h, 3);
    assert_int_equal(vbl_scene_camera_matrices(scene, w2c, w2n), VBL_SUCCESS);
    assert_float_equal(w2c[14], 3.0, 1e-12);
    vbl_scene_release(scene);
    o.camera = "no_such_camera";
    assert_int_equal(load_with("{" LENS ", \"resolution\": [16, 9]}", cameras, &o, &scene), VBL_ERROR_FILE_NOT_FOUND);
    assert_non_null(strstr(vbl_last_error_message(), "no_such_camera"));
    assert_null(scene);
}

/* p M with the divide by w. */
static void project(const double m[16], const double p[3], double out[2], double* w)
{
    double v[4];
    for (int j = 0; j < 4; ++j) v[j] = p[0] * m[j] + p[1] * m[4 + j] + p[2] * m[8 + j] + m[12 + j];
    *w = v[3];
    out[0] = v[0] / v[3];
    out[1] = v[1] / v[3];
}

/* frame_media: every corner of the box's bounds lands inside the frame, and the box fills a fair
 * part of it (the framing is not just "far away"). */
static void test_frame_media(void** state)
{
    (void)state;
    vbl_volume* box = NULL;
    assert_int_equal(vbl_volume_load(box_vdb, NULL, &box), VBL_SUCCESS);
    vbl_volume_info info;
    memset(&info, 0, sizeof info);
    info.size = sizeof info;
    assert_int_equal(vbl_volume_get_info(box, &info), VBL_SUCCESS);
    vbl_volume_release(box);
    static const char* const cameras[3] = {
        "\"auto\"",
        "{\"frame_media\": {\"direction\": [1, 1, -0.5]}, \"fov_deg\": 30, \"resolution\": [16, 9]}",
        "{\"frame_media\": {\"direction\": [0, 1, 0], \"margin\": 1.5}, \"focal_length\": 35, \"resolution\": [9, 16]}",
    };
    for (int k = 0; k < 3; ++k) {
        vbl_scene* scene = NULL;
        if (load_with(cameras[k], NULL, NULL, &scene)) fail_msg("%s: %s", cameras[k], vbl_last_error_message());
        double w2c[16], w2n[16];
        assert_int_equal(vbl_scene_camera_matrices(scene, w2c, w2n), VBL_SUCCESS);
        double lo[2] = {1e30, 1e30}, hi[2] = {-1e30, -1e30};
        for (int c = 0; c < 8; ++c) {
            const double p[3] = {c & 1 ? info.world_bbox_max[0] : info.world_bbox_min[0],
                                 c & 2 ? info.world_bbox_max[1] : info.world_bbox_min[1],
                                 c & 4 ? info.world_bbox_max[2] : info.world_bbox_min[2]};
            double ndc[2], w = 0.0;
            project(w2n, p, ndc, &w);
            assert_true(w > 0.0);
            for (int a = 0; a < 2; ++a) {
                if (!(ndc[a] > 0.0 && ndc[a] < 1.0)) fail_msg("%s: corner %d at ndc %g, %g", cameras[k], c, ndc[0], ndc[1]);
                lo[a] = fmin(lo[a], ndc[a]);
                hi[a] = fmax(hi[a], ndc[a]);
            }
        }
        assert_true(fmax(hi[0] - lo[0], hi[1] - lo[1]) > 0.3);
        vbl_scene_release(scene);
    }
}

static void test_grid_index_and_refusals(void** state)
{
    (void)state;
    char text[4096], path[512];
    /* multi.vdb: "density" box (index 0 of that name), then "density" sphere (index 1) */
    vbl_scene* scene = NULL;
    for (int index = 0; index < 3; ++index) {
        snprintf(text, sizeof text,
                 "{\"camera\": \"auto\", \"media\": [{\"vdb\": \"%s\", \"grid\": \"density\", \"grid_index\": %d}]}",
                 multi_vdb, index);
        rt_write_file(rt_temp_dir, "grid.json", text, path);
        vbl_result r = vbl_scene_load(path, &scene);
        if (index < 2) {
            if (r) fail_msg("grid_index %d: %s", index, vbl_last_error_message());
            assert_int_equal(vbl_scene_light_count(scene), 0);
            assert_int_equal(vbl_scene_has_emission(scene), 0);
            vbl_scene_release(scene);
        } else {
            assert_int_equal(r, VBL_ERROR_GRID_NOT_FOUND);
            assert_non_null(strstr(vbl_last_error_message(), "media[0]"));
        }
    }
    static const char* const bad[] = {
        "{\"position\": [0, -4, 0], \"look_at\": [0, 0, 0], \"fov_deg\": 30, \"focal_length\": 50, \"resolution\": [4, 4]}",
        "{" LENS ", \"sensor_fit\": \"diagonal\", \"resolution\": [4, 4]}",
        "{" LENS ", \"sensor_width\": 0, \"resolution\": [4, 4]}",
        "{\"frame_media\": {}, \"position\": [0, -4, 0], \"resolution\": [4, 4]}",
        "{\"frame_media\": {\"margin\": 0.5}, \"resolution\": [4, 4]}",
        "\"front\"",
    };
    static const char* const why[] = {"not both", "sensor_fit", "sensor_width", "frame_media", "margin", "\"auto\""};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        assert_int_equal(load_with(bad[i], NULL, NULL, &scene), VBL_ERROR_SCENE);
        if (!strstr(vbl_last_error_message(), why[i])) fail_msg("%s: %s", bad[i], vbl_last_error_message());
        assert_null(scene);
    }
}


/* Sequences: camera fields and a medium's transform per frame, interpolated between keyed frames,
 * held outside them; without a frame (no --frames) the static values. */
static void test_per_frame_camera_and_media(void** state)
{
    (void)state;
    char text[4096], path[512];
    snprintf(text, sizeof text,
             "{\"camera\": {\"position\": [0.75, -4, 0.75], \"look_at\": [0.75, 0.75, 0.75], \"fov_deg\": 40,"
             " \"resolution\": [8, 8], \"frames\": {\"1\": {\"position\": [0.75, -4, 0.75]},"
             " \"11\": {\"position\": [0.75, -2, 0.75], \"fov_deg\": 20}}},"
             " \"media\": [{\"vdb\": \"%s\", \"transform_frames\": {"
             "\"1\": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]],"
             "\"3\": [[2, 0, 0, 2], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]}}]}",
             box_vdb);
    rt_write_file(rt_temp_dir, "seq.json", text, path);
    static const struct {
        int use_frame, frame;
        double distance, tan_v, scale_x, offset_x;
    } cases[] = {
        {0, 0, 4.0, 0.36397023426620234, 1.0, 0.0},   /* static: fov 40, no transform */
        {1, 6, 3.0, 0.17632698070846498, 2.0, 2.0},   /* between camera keys; past the media keys */
        {1, 2, 3.8, 0.17632698070846498, 1.5, 1.0},   /* fov held at its only key (20) */
        {1, 20, 2.0, 0.17632698070846498, 2.0, 2.0},  /* held after the last key */
        {1, -5, 4.0, 0.17632698070846498, 1.0, 0.0},  /* held before the first key */
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        vbl_scene_load_options o = VBL_SCENE_LOAD_OPTIONS_DEFAULT;
        o.use_frame = cases[i].use_frame;
        o.frame = cases[i].frame;
        vbl_scene* scene = NULL;
        if (vbl_scene_load_ex(path, &o, &scene)) fail_msg("case %zu: %s", i, vbl_last_error_message());
        double w2c[16], w2n[16];
        assert_int_equal(vbl_scene_camera_matrices(scene, w2c, w2n), VBL_SUCCESS);
        double th, tv;
        tans(scene, &th, &tv);
        if (fabs(w2c[14] - cases[i].distance) > 1e-12 || fabs(tv - cases[i].tan_v) > 1e-12)
            fail_msg("case %zu: distance %.15g tan %.15g", i, w2c[14], tv);
        assert_float_equal(scene->media[0].volume_to_scene.m[0][0], cases[i].scale_x, 1e-12);
        assert_float_equal(scene->media[0].volume_to_scene.m[0][3], cases[i].offset_x, 1e-12);
        vbl_scene_release(scene);
    }
    /* frame keys must be integers */
    rt_write_file(rt_temp_dir, "seq_bad.json",
                  "{\"camera\": {\"position\": [0, -4, 0], \"look_at\": [0, 0, 0], \"resolution\": [4, 4],"
                  " \"frames\": {\"first\": {\"position\": [0, -3, 0]}}}}",
                  path);
    vbl_scene_load_options o = VBL_SCENE_LOAD_OPTIONS_DEFAULT;
    o.use_frame = 1;
    o.frame = 1;
    vbl_scene* scene = NULL;
    assert_int_equal(vbl_scene_load_ex(path, &o, &scene), VBL_ERROR_SCENE);
    assert_non_null(strstr(vbl_last_error_message(), "not a frame number"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sensor_fit),
        cmocka_unit_test(test_resolution_override),
        cmocka_unit_test(test_named_camera_and_file),
        cmocka_unit_test(test_frame_media),
        cmocka_unit_test(test_grid_index_and_refusals),
        cmocka_unit_test(test_per_frame_camera_and_media),
    };
    return cmocka_run_group_tests(tests, setup, rt_temp_dir_teardown);
}
