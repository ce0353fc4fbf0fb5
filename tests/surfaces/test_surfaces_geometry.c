/* Surfaces: Embree intersection against analytic ray/triangle results, mesh files (OBJ, PLY)
 * through assimp, OpenSubdiv refinement, scene "surfaces" parsing and every bad input. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "core/rng.h"
#include "geometry/mesh_load.h"
#include "geometry/subdivide.h"
#include "geometry/surfaces.h"
#include "render_test_util.h"
#include "scene/scene.h"
#include "vbl/vbl.h"

static vbl_surfaces* make_triangle(vbl_vec3 a, vbl_vec3 b, vbl_vec3 c)
{
    double p[9] = {a.x, a.y, a.z, b.x, b.y, b.z, c.x, c.y, c.z};
    unsigned idx[3] = {0, 1, 2};
    vbl_mesh_data m = {p, NULL, 3, idx, 1};
    vbl_surfaces* s = NULL;
    assert_int_equal(vbl_surfaces_create("test", &s), VBL_SUCCESS);
    assert_int_equal(vbl_surfaces_add_mesh(s, &m, 7, NULL, "triangle", NULL), VBL_SUCCESS);
    return s;
}

/* Moller-Trumbore in double: 1 and t, (u, v) if the ray hits the triangle. */
static int analytic_hit(vbl_vec3 o, vbl_vec3 d, vbl_vec3 a, vbl_vec3 b, vbl_vec3 c, double* t, double* u, double* v)
{
    vbl_vec3 e1 = vbl_v3_sub(b, a), e2 = vbl_v3_sub(c, a);
    vbl_vec3 p = vbl_v3_cross(d, e2);
    double det = vbl_v3_dot(e1, p);
    if (fabs(det) < 1e-14) return 0;
    vbl_vec3 s = vbl_v3_sub(o, a);
    *u = vbl_v3_dot(s, p) / det;
    vbl_vec3 q = vbl_v3_cross(s, e1);
    *v = vbl_v3_dot(d, q) / det;
    *t = vbl_v3_dot(e2, q) / det;
    return *u >= 0.0 && *v >= 0.0 && *u + *v <= 1.0 && *t > 0.0;
}

static void test_intersection_matches_analytic(void** state)
{
    (void)state;
    vbl_vec3 a = vbl_v3(-1.0, -0.5, 2.0), b = vbl_v3(1.5, -0.7, 2.4), c = vbl_v3(0.2, 1.3, 1.6);
    vbl_surfaces* s = make_triangle(a, b, c);
    vbl_rng rng = vbl_rng_make(11, 0, 0);
    int agree = 0, hits = 0, interior = 0;
    for (int i = 0; i < 20000; ++i) {
        vbl_vec3 o = vbl_v3(4.0 * vbl_rng_uniform(&rng) - 2.0, 4.0 * vbl_rng_uniform(&rng) - 2.0, -1.0);
        vbl_vec3 target = vbl_v3(4.0 * vbl_rng_uniform(&rng) - 2.0, 4.0 * vbl_rng_uniform(&rng) - 2.0, 2.0);
        vbl_vec3 d = vbl_v3_normalize(vbl_v3_sub(target, o));
        double t = 0.0, u = -1.0, v = -1.0;
        int expect = analytic_hit(o, d, a, b, c, &t, &u, &v);
        vbl_surface_hit hit;
        int got = vbl_surfaces_intersect(s, o, d, 0.0, INFINITY, &hit);
        /* rays within 1e-5 (barycentric) of an edge may go either way in float */
        int near_edge = fabs(u) < 1e-5 || fabs(v) < 1e-5 || fabs(1.0 - u - v) < 1e-5;
        if (near_edge) continue;
        ++interior;
        if (got == expect) ++agree;
        if (got && expect) {
            ++hits;
            assert_true(fabs(hit.t - t) < 1e-5 * (1.0 + t));
            vbl_vec3 p = vbl_v3_madd(o, d, t);
            assert_true(vbl_v3_length(vbl_v3_sub(hit.position, p)) < 1e-5);
            assert_true(vbl_v3_dot(hit.geometric_normal, d) < 0.0);
            assert_true(fabs(vbl_v3_length(hit.geometric_normal) - 1.0) < 1e-12);
            assert_int_equal(hit.material, 7);
            assert_int_equal(hit.surface, 0);
        }
    }
    assert_int_equal(agree, interior);
    assert_true(hits > 1000);
    vbl_surfaces_release(s);
}

static void test_grazing_edges_and_occlusion(void** state)
{
    (void)state;
    /* a unit square in z = 0 made of two triangles sharing the diagonal (0,0)-(1,1) */
    double p[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    unsigned idx[6] = {0, 1, 2, 0, 2, 3};
    vbl_mesh_data m = {p, NULL, 4, idx, 2};
    vbl_surfaces* s = NULL;
    assert_int_equal(vbl_surfaces_create("square", &s), VBL_SUCCESS);
    assert_int_equal(vbl_surfaces_add_mesh(s, &m, 0, NULL, "square", NULL), VBL_SUCCESS);
    assert_int_equal(vbl_surfaces_triangle_count(s), 2);
    /* watertight shared edge: rays exactly through the diagonal always hit (robust mode) */
    for (int i = 1; i < 1000; ++i) {
        double x = i / 1000.0;
        vbl_surface_hit hit;
        vbl_vec3 o = vbl_v3(x, x, 1.0), d = vbl_v3(0.0, 0.0, -1.0);
        assert_true(vbl_surfaces_intersect(s, o, d, 0.0, INFINITY, &hit));
        assert_true(fabs(hit.t - 1.0) < 1e-6);
        assert_true(hit.geometric_normal.z > 0.999);
        /* from below the normal faces down */
        assert_true(vbl_surfaces_intersect(s, vbl_v3(x, x, -2.0), vbl_v3(0, 0, 1), 0.0, INFINITY, &hit));
        assert_true(hit.geometric_normal.z < -0.999);
    }
    /* grazing: a ray in the plane of the square misses or hits but never returns garbage */
    vbl_surface_hit hit;
    int g = vbl_surfaces_intersect(s, vbl_v3(-1.0, 0.5, 0.0), vbl_v3(1.0, 0.0, 0.0), 0.0, INFINITY, &hit);
    if (g) assert_true(isfinite(hit.t) && hit.t >= 0.0);
    /* nearly grazing from above hits at the analytic distance */
    vbl_vec3 d = vbl_v3_normalize(vbl_v3(1.0, 0.0, -1e-3));
    assert_true(vbl_surfaces_intersect(s, vbl_v3(-0.5, 0.5, 1e-3), d, 0.0, INFINITY, &hit));
    assert_true(fabs(hit.position.x - 0.5) < 1e-3);
    /* t range and occlusion */
    vbl_vec3 o = vbl_v3(0.3, 0.6, 2.0), down = vbl_v3(0, 0, -1);
    assert_false(vbl_surfaces_intersect(s, o, down, 0.0, 1.9, &hit));
    assert_false(vbl_surfaces_intersect(s, o, down, 2.1, INFINITY, &hit));
    assert_true(vbl_surfaces_occluded(s, o, down, 0.0, 2.1));
    assert_false(vbl_surfaces_occluded(s, o, down, 0.0, 1.9));
    assert_false(vbl_surfaces_occluded(s, o, vbl_v3(0, 0, 1), 0.0, INFINITY));
    /* a ray spawned off the hit with the epsilon does not hit the same surface again */
    assert_true(vbl_surfaces_intersect(s, o, down, 0.0, INFINITY, &hit));
    double eps = vbl_surfaces_ray_epsilon(s, hit.position);
    assert_true(eps > 0.0 && eps < 1e-4);
    vbl_vec3 up = vbl_v3_normalize(vbl_v3(0.3, 0.1, 1e-2));
    assert_false(vbl_surfaces_occluded(s, vbl_v3_madd(hit.position, hit.geometric_normal, eps), up, 0.0, INFINITY));
    /* NULL surfaces: nothing, no Embree */
    assert_false(vbl_surfaces_intersect(NULL, o, down, 0.0, INFINITY, &hit));
    assert_false(vbl_surfaces_occluded(NULL, o, down, 0.0, INFINITY));
    vbl_surfaces_release(s);
}

static void test_degenerate_triangles(void** state)
{
    (void)state;
    double p[15] = {0, 0, 0, 1, 0, 0, 2, 0, 0, 0, 1, 0, 0, 0, 0};
    unsigned only_bad[9] = {0, 1, 2, 0, 0, 3, 0, 4, 1}; /* collinear, repeated index, coincident vertices */
    vbl_mesh_data m = {p, NULL, 5, only_bad, 3};
    vbl_surfaces* s = NULL;
    assert_int_equal(vbl_surfaces_create("degenerate", &s), VBL_SUCCESS);
    size_t dropped = 0;
    assert_int_equal(vbl_surfaces_add_mesh(s, &m, 0, NULL, "bad mesh", &dropped), VBL_ERROR_SCENE);
    assert_non_null(strstr(vbl_last_error_message(), "bad mesh"));
    assert_non_null(strstr(vbl_last_error_message(), "degenerate"));
    unsigned mixed[12] = {0, 1, 2, 0, 1, 3, 0, 0, 3, 9, 1, 3}; /* one good, one out of range */
    vbl_mesh_data m2 = {p, NULL, 5, mixed, 4};
    assert_int_equal(vbl_surfaces_add_mesh(s, &m2, 0, NULL, "mixed", &dropped), VBL_SUCCESS);
    assert_int_equal(dropped, 3);
    assert_int_equal(vbl_surfaces_triangle_count(s), 1);
    /* non-finite vertices are an error */
    double nanp[9] = {0, 0, 0, 1, 0, 0, NAN, 1, 0};
    unsigned one[3] = {0, 1, 2};
    vbl_mesh_data m3 = {nanp, NULL, 3, one, 1};
    assert_int_equal(vbl_surfaces_add_mesh(s, &m3, 0, NULL, "nan", NULL), VBL_ERROR_SCENE);
    vbl_surfaces_release(s);
}

/* ---- files ------------------------------------------------------------------------------ */

static const char* const cube_obj =
    "# unit cube, quads, no normals\n"
    "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n"
    "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";

static void test_obj_and_ply(void** state)
{
    (void)state;
    char dir[256], path[512];
    rt_make_temp_dir(dir);
    rt_write_file(dir, "cube.obj", cube_obj, path);
    vbl_mesh_data m;
    size_t dropped = 99;
    assert_int_equal(vbl_mesh_load(path, &m, &dropped), VBL_SUCCESS);
    assert_int_equal(m.triangle_count, 12);
    assert_int_equal(m.vertex_count, 8);
    assert_null(m.normals); /* no normals in the file: geometric normals */
    assert_int_equal(dropped, 0);
    for (size_t i = 0; i < 3 * m.vertex_count; ++i) assert_true(fabs(fabs(m.positions[i]) - 1.0) < 1e-6);
    vbl_mesh_data_free(&m);

    /* OBJ with normals, and a degenerate face next to a good one */
    rt_write_file(dir, "tri.obj",
                  "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nvn 0 0 1\n"
                  "f 1//1 2//1 3//1\nf 1//1 2//1 4//1\n",
                  path);
    assert_int_equal(vbl_mesh_load(path, &m, &dropped), VBL_SUCCESS);
    assert_true(m.triangle_count >= 1);
    assert_non_null(m.normals);
    assert_true(fabs(m.normals[2] - 1.0) < 1e-6);
    vbl_mesh_data_free(&m);

    /* ASCII PLY */
    rt_write_file(dir, "quad.ply",
                  "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                  "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                  "0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n",
                  path);
    assert_int_equal(vbl_mesh_load(path, &m, NULL), VBL_SUCCESS);
    assert_int_equal(m.triangle_count, 2);
    vbl_mesh_data_free(&m);

    /* a file that does not exist, garbage, no faces */
    char missing[600];
    snprintf(missing, sizeof missing, "%s/nope.obj", dir);
    assert_int_equal(vbl_mesh_load(missing, &m, NULL), VBL_ERROR_FILE_NOT_FOUND);
    assert_non_null(strstr(vbl_last_error_message(), "nope.obj"));
    rt_write_file(dir, "garbage.ply", "ply\nthis is not a ply file\n", path);
    vbl_result r = vbl_mesh_load(path, &m, NULL);
    assert_true(r == VBL_ERROR_CORRUPT_FILE || r == VBL_ERROR_SCENE);
    assert_non_null(strstr(vbl_last_error_message(), "garbage.ply"));
    rt_write_file(dir, "points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n", path);
    r = vbl_mesh_load(path, &m, NULL);
    assert_true(r == VBL_ERROR_CORRUPT_FILE || r == VBL_ERROR_SCENE);
    rt_write_file(dir, "flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n", path);
    r = vbl_mesh_load(path, &m, NULL);
    if (r == VBL_SUCCESS) { /* assimp may keep it: then the surfaces layer drops it */
        vbl_surfaces* s = NULL;
        assert_int_equal(vbl_surfaces_create("flat", &s), VBL_SUCCESS);
        assert_int_equal(vbl_surfaces_add_mesh(s, &m, 0, NULL, "flat.obj", NULL), VBL_ERROR_SCENE);
        vbl_surfaces_release(s);
        vbl_mesh_data_free(&m);
    }
    rt_remove_dir(dir);
}

/* ---- subdivision --------------------------------------------------------------------- */

static void test_subdivide_cube(void** state)
{
    (void)state;
    double p[24] = {-1, -1, -1, 1, -1, -1, 1, 1, -1, -1, 1, -1, -1, -1, 1, 1, -1, 1, 1, 1, 1, -1, 1, 1};
    int sizes[6] = {4, 4, 4, 4, 4, 4};
    int idx[24] = {0, 3, 2, 1, 4, 5, 6, 7, 0, 1, 5, 4, 1, 2, 6, 5, 2, 3, 7, 6, 3, 0, 4, 7};
    /* Catmull-Clark: V' = V + E + F, each quad -> 4 quads -> 8 triangles */
    const size_t verts[3] = {8, 26, 98}, tris[3] = {12, 48, 192};
    for (int level = 0; level <= 2; ++level) {
        vbl_mesh_data m;
        assert_int_equal(vbl_subdivide(p, 8, sizes, 6, idx, level, "cube", &m), VBL_SUCCESS);
        assert_int_equal(m.vertex_count, verts[level]);
        assert_int_equal(m.triangle_count, tris[level]);
        if (level > 0) {
            assert_non_null(m.normals);
            double max_norm = 0.0, min_len = 9.0;
            for (size_t i = 0; i < m.vertex_count; ++i)
                min_len = fmin(min_len, sqrt(m.positions[3 * i] * m.positions[3 * i] +
                                             m.positions[3 * i + 1] * m.positions[3 * i + 1] +
                                             m.positions[3 * i + 2] * m.positions[3 * i + 2]));
            assert_true(min_len > 0.8 && min_len < 0.9); /* face centres: 68/81 of the half size */
            for (size_t i = 0; i < m.vertex_count; ++i) {
                vbl_vec3 q = vbl_v3(m.positions[3 * i], m.positions[3 * i + 1], m.positions[3 * i + 2]);
                /* the limit surface lies strictly inside the cube (a rounded cube) */
                assert_true(fabs(q.x) < 1.0 && fabs(q.y) < 1.0 && fabs(q.z) < 1.0);
                max_norm = fmax(max_norm, fmax(fabs(q.x), fmax(fabs(q.y), fabs(q.z))));
                /* limit normals point roughly away from the centre (either orientation) */
                vbl_vec3 n = vbl_v3(m.normals[3 * i], m.normals[3 * i + 1], m.normals[3 * i + 2]);
                assert_true(fabs(vbl_v3_dot(n, vbl_v3_normalize(q))) > 0.5);
            }
            assert_true(max_norm > 0.6);
        }
        vbl_mesh_data_free(&m);
    }
    /* Loop on a tetrahedron: level 1 = 4 + 6 vertices, 16 triangles */
    double t[12] = {1, 1, 1, -1, -1, 1, -1, 1, -1, 1, -1, -1};
    int ts[4] = {3, 3, 3, 3};
    int ti[12] = {0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2};
    vbl_mesh_data m;
    assert_int_equal(vbl_subdivide(t, 4, ts, 4, ti, 1, "tetra", &m), VBL_SUCCESS);
    assert_int_equal(m.vertex_count, 10);
    assert_int_equal(m.triangle_count, 16);
    vbl_mesh_data_free(&m);
}

static void test_subdivide_bad_input(void** state)
{
    (void)state;
    double p[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    int sizes[2] = {3, 3};
    int out_of_range[6] = {0, 1, 2, 0, 2, 7};
    vbl_mesh_data m;
    assert_int_equal(vbl_subdivide(p, 4, sizes, 2, out_of_range, 1, "oor", &m), VBL_ERROR_SCENE);
    assert_non_null(strstr(vbl_last_error_message(), "oor"));
    int repeated[6] = {0, 1, 1, 0, 2, 3};
    assert_int_equal(vbl_subdivide(p, 4, sizes, 2, repeated, 1, "rep", &m), VBL_ERROR_SCENE);
    int two[2] = {2, 4};
    int idx[6] = {0, 1, 0, 1, 2, 3};
    assert_int_equal(vbl_subdivide(p, 4, two, 2, idx, 1, "two", &m), VBL_ERROR_SCENE);
    int ok[6] = {0, 1, 2, 0, 2, 3};
    assert_int_equal(vbl_subdivide(p, 4, sizes, 2, ok, 7, "deep", &m), VBL_ERROR_SCENE);
    /* non-manifold: three triangles sharing the edge 0-1 (documented: accepted, finite) */
    double q[15] = {0, 0, 0, 1, 0, 0, 0.5, 1, 0, 0.5, -1, 0, 0.5, 0, 1};
    int qs[3] = {3, 3, 3};
    int qi[9] = {0, 1, 2, 1, 0, 3, 0, 1, 4};
    vbl_result r = vbl_subdivide(q, 5, qs, 3, qi, 2, "nonmanifold", &m);
    if (r == VBL_SUCCESS) {
        assert_true(m.triangle_count > 3);
        for (size_t i = 0; i < 3 * m.vertex_count; ++i) assert_true(isfinite(m.positions[i]));
        vbl_mesh_data_free(&m);
    } else {
        assert_int_equal(r, VBL_ERROR_SCENE);
    }
}

/* ---- scene files ------------------------------------------------------------------------ */

static vbl_result load_scene_text(const char* dir, const char* surfaces_json, vbl_scene** scene)
{
    char text[4096], path[512];
    snprintf(text, sizeof text,
             "{\"camera\": {\"position\": [0, -5, 1], \"look_at\": [0, 0, 0], \"resolution\": [8, 6]},\n"
             " \"lights\": [{\"type\": \"point\", \"position\": [0, 0, 3], \"intensity\": 10}],\n"
             " \"surfaces\": %s}\n",
             surfaces_json);
    rt_write_file(dir, "scene.json", text, path);
    return vbl_scene_load(path, scene);
}

static void expect_scene_error(const char* dir, const char* surfaces_json, vbl_result code, const char* fragment)
{
    vbl_scene* scene = NULL;
    vbl_result r = load_scene_text(dir, surfaces_json, &scene);
    if (r != code || !strstr(vbl_last_error_message(), fragment))
        fail_msg("%s -> %s: %s (expected %s)", surfaces_json, vbl_result_name(r), vbl_last_error_message(), fragment);
    assert_null(scene);
}

static void test_scene_surfaces(void** state)
{
    (void)state;
    char dir[256], path[512];
    rt_make_temp_dir(dir);
    rt_write_file(dir, "cube.obj", cube_obj, path);
    vbl_scene* scene = NULL;
    vbl_result lr = load_scene_text(dir,
                                     "[{\"mesh\": \"cube.obj\", \"material\": {\"type\": \"phong\", \"albedo\": 0.3, "
                                     "\"specular\": [0.2, 0.2, 0.2], \"exponent\": 80}},\n"
                                     " {\"mesh\": \"cube.obj\", \"transform\": [[2,0,0,5],[0,2,0,0],[0,0,2,0],[0,0,0,1]],"
                                     " \"material\": {\"type\": \"ggx\", \"roughness\": 0.2}},\n"
                                     " {\"mesh\": \"cube.obj\", \"subdivision\": {\"level\": 2}}]",
                                     &scene);
    if (lr) fail_msg("%s", vbl_last_error_message());
    assert_int_equal(scene->surface_count, 3);
    assert_true(scene->has_surfaces);
    assert_int_equal(scene->materials[0].type, VBL_MATERIAL_PHONG);
    assert_true(fabs(scene->materials[0].exponent - 80.0) < 1e-12);
    assert_int_equal(scene->materials[1].type, VBL_MATERIAL_GGX);
    assert_int_equal(scene->materials[2].type, VBL_MATERIAL_LAMBERT);
    assert_int_equal(vbl_surfaces_triangle_count(scene->surfaces), 12 + 12 + 192);
    vbl_vec3 lo, hi;
    assert_true(vbl_surfaces_bounds(scene->surfaces, &lo, &hi));
    assert_true(fabs(hi.x - 7.0) < 1e-9 && fabs(lo.x + 1.0) < 1e-9);
    /* the transformed cube is hit at x = 3 from the left */
    vbl_surface_hit hit;
    assert_true(vbl_surfaces_intersect(scene->surfaces, vbl_v3(1.5, 0.1, 0.2), vbl_v3(1, 0, 0), 0.0, INFINITY, &hit));
    assert_true(fabs(hit.position.x - 3.0) < 1e-6);
    assert_int_equal(hit.material, 1);
    vbl_scene_release(scene);

    expect_scene_error(dir, "[{\"mesh\": \"missing.obj\"}]", VBL_ERROR_FILE_NOT_FOUND, "missing.obj");
    expect_scene_error(dir, "[{\"mesh\": \"cube.obj\", \"material\": {\"type\": \"phong\", \"exponent\": -3}}]",
                       VBL_ERROR_SCENE, "surfaces[0].material.exponent = -3 must be >= 0");
    expect_scene_error(dir, "[{\"mesh\": \"cube.obj\", \"material\": {\"type\": \"glass\"}}]", VBL_ERROR_SCENE,
                       "surfaces[0].material.type");
    expect_scene_error(dir, "[{\"mesh\": \"cube.obj\", \"material\": {\"albedo\": 1.5}}]", VBL_ERROR_SCENE,
                       "surfaces[0].material.albedo");
    expect_scene_error(dir, "[{\"mesh\": \"cube.obj\", \"material\": {\"type\": \"lambert\", \"exponent\": 3}}]",
                       VBL_ERROR_SCENE, "exponent");
    expect_scene_error(dir,
                       "[{\"mesh\": \"cube.obj\", \"material\": {\"type\": \"phong\", \"albedo\": 0.8, "
                       "\"specular\": 0.5}}]",
                       VBL_ERROR_SCENE, "surfaces[0].material");
    expect_scene_error(dir, "[{\"mesh\": \"cube.obj\", \"material\": {\"type\": \"ggx\", \"roughness\": 0}}]",
                       VBL_ERROR_SCENE, "roughness");
    expect_scene_error(dir, "[{\"mesh\": \"cube.obj\", \"subdivision\": {\"level\": 9}}]", VBL_ERROR_SCENE,
                       "surfaces[0].subdivision.level");
    expect_scene_error(dir, "[{\"mesh\": \"cube.obj\", \"transform\": [[0,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]}]",
                       VBL_ERROR_SCENE, "surfaces[0].transform");
    expect_scene_error(dir, "[{\"mesh\": \"cube.obj\", \"colour\": 1}]", VBL_ERROR_SCENE, "colour");
    expect_scene_error(dir, "{\"mesh\": \"cube.obj\"}", VBL_ERROR_SCENE, "surfaces must be an array");
    rt_write_file(dir, "flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n", path);
    vbl_scene* s2 = NULL;
    vbl_result r = load_scene_text(dir, "[{\"mesh\": \"flat.obj\"}]", &s2);
    assert_int_not_equal(r, VBL_SUCCESS);
    assert_non_null(strstr(vbl_last_error_message(), "surfaces[0]"));
    rt_remove_dir(dir);
}

static void test_programmatic_mesh(void** state)
{
    (void)state;
    vbl_camera cam = rt_camera(vbl_v3(0, -3, 1), vbl_v3(0, 0, 0), 40.0, 4, 4);
    vbl_scene* scene = NULL;
    assert_int_equal(vbl_scene_create_empty("prog", &cam, &scene), VBL_SUCCESS);
    assert_null(scene->surfaces); /* media-only scenes never create an Embree device */
    double p[12] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
    unsigned idx[6] = {0, 1, 2, 0, 2, 3};
    vbl_material mat = {VBL_MATERIAL_LAMBERT, {0.5, 0.5, 0.5}, {0, 0, 0}, 0.0, 0.0};
    assert_int_equal(vbl_scene_add_mesh(scene, p, 4, idx, 2, &mat, NULL), VBL_SUCCESS);
    mat.albedo.x = 2.0;
    assert_int_equal(vbl_scene_add_mesh(scene, p, 4, idx, 2, &mat, NULL), VBL_ERROR_SCENE);
    assert_non_null(strstr(vbl_last_error_message(), "albedo"));
    assert_int_equal(scene->surface_count, 1);
    vbl_scene_release(scene);
}

static vbl_result halve(void* user, const char* space, const char* field, double rgb[3])
{
    int* calls = user;
    (void)space;
    if (strstr(field, "surfaces[0].material.")) ++*calls;
    for (int k = 0; k < 3; ++k) rgb[k] *= 0.5;
    return VBL_SUCCESS;
}

/* surface colours go through the loader's colour conversion like media albedo */
static void test_surface_color_space(void** state)
{
    (void)state;
    char dir[256], path[512];
    rt_make_temp_dir(dir);
    rt_write_file(dir, "cube.obj", cube_obj, path);
    rt_write_file(dir, "scene.json",
                  "{\"color_space\": \"test\", \"camera\": {\"position\": [0, -5, 1], \"look_at\": [0, 0, 0], "
                  "\"resolution\": [8, 6]},\n \"surfaces\": [{\"mesh\": \"cube.obj\", \"material\": {\"type\": "
                  "\"phong\", \"albedo\": [0.8, 0.4, 0.2], \"specular\": 0.2}}]}\n",
                  path);
    int calls = 0;
    vbl_scene_load_options o = VBL_SCENE_LOAD_OPTIONS_DEFAULT;
    o.convert_color = halve;
    o.convert_color_user = &calls;
    vbl_scene* scene = NULL;
    if (vbl_scene_load_ex(path, &o, &scene)) fail_msg("%s", vbl_last_error_message());
    assert_int_equal(calls, 2);
    assert_true(fabs(scene->materials[0].albedo.x - 0.4) < 1e-12 && fabs(scene->materials[0].albedo.z - 0.1) < 1e-12);
    assert_true(fabs(scene->materials[0].specular.y - 0.1) < 1e-12);
    vbl_scene_release(scene);
    rt_remove_dir(dir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_intersection_matches_analytic),
        cmocka_unit_test(test_grazing_edges_and_occlusion),
        cmocka_unit_test(test_degenerate_triangles),
        cmocka_unit_test(test_obj_and_ply),
        cmocka_unit_test(test_subdivide_cube),
        cmocka_unit_test(test_subdivide_bad_input),
        cmocka_unit_test(test_scene_surfaces),
        cmocka_unit_test(test_programmatic_mesh),
        cmocka_unit_test(test_surface_color_space),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
