/* Scene surfaces in one Embree 3 scene (surfaces.h). Embree traces in single precision; the
 * vertices are also kept in double so that hit positions and normals are recomputed in double
 * from the hit's barycentrics (the hit point lies on the triangle up to double rounding), and
 * rays leaving a surface are offset by vbl_surfaces_ray_epsilon along the geometric normal. */
#include "geometry/surfaces.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <embree3/rtcore.h>

#include "core/error.h"
#include "scene/scene_build.h"

typedef struct vbl_surface_geom {
    double* positions; /* 3 per vertex, scene space */
    double* normals;   /* 3 per vertex or NULL */
    unsigned* indices; /* 3 per triangle (kept triangles only) */
    size_t vertex_count, triangle_count;
    int material;
} vbl_surface_geom;

struct vbl_surfaces {
    RTCDevice device;
    RTCScene scene;
    char name[256];
    vbl_surface_geom* geoms;
    int count, cap;
    size_t triangles;
    vbl_vec3 lo, hi;
    double extent; /* max |coordinate| over all vertices, for the ray epsilon */
    int embree_failed;
    char embree_message[512];
};

static void vbl_embree_error(void* user, enum RTCError code, const char* str)
{
    vbl_surfaces* s = user;
    if (code == RTC_ERROR_NONE) return;
    s->embree_failed = 1;
    snprintf(s->embree_message, sizeof s->embree_message, "Embree error %d: %s", (int)code, str ? str : "");
}

static vbl_result vbl_embree_check(vbl_surfaces* s, const char* what)
{
    enum RTCError e = rtcGetDeviceError(s->device);
    if (!s->embree_failed && e == RTC_ERROR_NONE) return VBL_SUCCESS;
    vbl_result code = (e == RTC_ERROR_OUT_OF_MEMORY) ? VBL_ERROR_OUT_OF_MEMORY : VBL_ERROR_INTERNAL;
    return vbl_error(code, "%s: %s: %s", s->name, what,
                     s->embree_message[0] ? s->embree_message : "Embree reported an error");
}

vbl_result vbl_surfaces_create(const char* name, vbl_surfaces** out)
{
    *out = NULL;
    vbl_surfaces* s = calloc(1, sizeof *s);
    if (!s) return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory (surfaces)", name ? name : "surfaces");
    snprintf(s->name, sizeof s->name, "%s", name ? name : "surfaces");
    s->device = rtcNewDevice(NULL);
    if (!s->device) {
        enum RTCError e = rtcGetDeviceError(NULL);
        free(s);
        return vbl_error(VBL_ERROR_UNSUPPORTED, "%s: cannot create the Embree device (error %d)", name, (int)e);
    }
    rtcSetDeviceErrorFunction(s->device, vbl_embree_error, s);
    s->scene = rtcNewScene(s->device);
    vbl_result r = VBL_SUCCESS;
    if (s->scene) {
        rtcSetSceneFlags(s->scene, RTC_SCENE_FLAG_ROBUST);
        rtcSetSceneBuildQuality(s->scene, RTC_BUILD_QUALITY_HIGH);
        rtcCommitScene(s->scene);
    }
    if (!s->scene || (r = vbl_embree_check(s, "creating the scene"))) {
        if (!s->scene) r = vbl_error(VBL_ERROR_INTERNAL, "%s: cannot create the Embree scene", s->name);
        vbl_surfaces_release(s);
        return r;
    }
    s->lo = vbl_v3(INFINITY, INFINITY, INFINITY);
    s->hi = vbl_v3(-INFINITY, -INFINITY, -INFINITY);
    *out = s;
    return VBL_SUCCESS;
}

void vbl_surfaces_release(vbl_surfaces* s)
{
    if (!s) return;
    for (int i = 0; i < s->count; ++i) {
        free(s->geoms[i].positions);
        free(s->geoms[i].normals);
        free(s->geoms[i].indices);
    }
    free(s->geoms);
    if (s->scene) rtcReleaseScene(s->scene);
    if (s->device) rtcReleaseDevice(s->device);
    free(s);
}

void vbl_mesh_data_free(vbl_mesh_data* mesh)
{
    if (!mesh) return;
    free(mesh->positions);
    free(mesh->normals);
    free(mesh->indices);
    memset(mesh, 0, sizeof *mesh);
}

int vbl_surfaces_count(const vbl_surfaces* s) { return s ? s->count : 0; }
size_t vbl_surfaces_triangle_count(const vbl_surfaces* s) { return s ? s->triangles : 0; }

int vbl_surfaces_bounds(const vbl_surfaces* s, vbl_vec3* lo, vbl_vec3* hi)
{
    if (!s || s->triangles == 0) return 0;
    *lo = s->lo;
    *hi = s->hi;
    return 1;
}

static vbl_vec3 vbl_vertex(const double* p, unsigned i) { return vbl_v3(p[3 * i], p[3 * i + 1], p[3 * i + 2]); }

vbl_result vbl_surfaces_add_mesh(vbl_surfaces* s, const vbl_mesh_data* mesh, int material, const vbl_affine* to_scene,
                                 const char* what, size_t* dropped)
{
    if (dropped) *dropped = 0;
    if (!s || !mesh || !what) return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_surfaces_add_mesh: NULL argument");
    if (mesh->vertex_count == 0 || mesh->triangle_count == 0 || !mesh->positions || !mesh->indices)
        return vbl_error(VBL_ERROR_SCENE, "%s: the mesh has no triangles", what);
    if (mesh->vertex_count > 0xffffffffu || mesh->triangle_count > 0x3fffffffu)
        return vbl_error(VBL_ERROR_UNSUPPORTED, "%s: the mesh is too large (%zu vertices, %zu triangles)", what,
                         mesh->vertex_count, mesh->triangle_count);
    vbl_affine M, inv;
    if (to_scene) {
        M = *to_scene;
        if (!vbl_affine_invert(&M, &inv)) return vbl_error(VBL_ERROR_SCENE, "%s: the transform is singular", what);
    } else {
        vbl_affine_set_identity(&M);
        vbl_affine_set_identity(&inv);
    }
    if (s->count == s->cap) {
        int cap = s->cap ? 2 * s->cap : 8;
        vbl_surface_geom* g = realloc(s->geoms, (size_t)cap * sizeof *g);
        if (!g) return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory", what);
        s->geoms = g;
        s->cap = cap;
    }
    const size_t nv = mesh->vertex_count, nt = mesh->triangle_count;
    vbl_surface_geom g;
    memset(&g, 0, sizeof g);
    g.material = material;
    g.vertex_count = nv;
    g.positions = malloc(3 * nv * sizeof(double));
    g.indices = malloc(3 * nt * sizeof(unsigned));
    g.normals = mesh->normals ? malloc(3 * nv * sizeof(double)) : NULL;
    if (!g.positions || !g.indices || (mesh->normals && !g.normals)) {
        free(g.positions);
        free(g.indices);
        free(g.normals);
        return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory", what);
    }
    for (size_t i = 0; i < nv; ++i) {
        vbl_vec3 p = vbl_affine_point(&M, vbl_vertex(mesh->positions, (unsigned)i));
        if (!(isfinite(p.x) && isfinite(p.y) && isfinite(p.z)) || fabs(p.x) > 1e30 || fabs(p.y) > 1e30 ||
            fabs(p.z) > 1e30) {
            free(g.positions);
            free(g.indices);
            free(g.normals);
            return vbl_error(VBL_ERROR_SCENE, "%s: vertex %zu is not finite (or beyond 1e30)", what, i);
        }
        g.positions[3 * i] = p.x;
        g.positions[3 * i + 1] = p.y;
        g.positions[3 * i + 2] = p.z;
        if (g.normals) {
            /* normals map by the inverse transpose; a zero or non-finite normal stays zero and
             * falls back to the geometric normal at hits */
            vbl_vec3 n = vbl_vertex(mesh->normals, (unsigned)i);
            vbl_vec3 m = vbl_v3(inv.m[0][0] * n.x + inv.m[1][0] * n.y + inv.m[2][0] * n.z,
                                inv.m[0][1] * n.x + inv.m[1][1] * n.y + inv.m[2][1] * n.z,
                                inv.m[0][2] * n.x + inv.m[1][2] * n.y + inv.m[2][2] * n.z);
            double len = vbl_v3_length(m);
            m = (len > 0.0 && isfinite(len)) ? vbl_v3_scale(m, 1.0 / len) : vbl_v3(0.0, 0.0, 0.0);
            g.normals[3 * i] = m.x;
            g.normals[3 * i + 1] = m.y;
            g.normals[3 * i + 2] = m.z;
        }
    }
    /* keep triangles with valid, distinct indices and a non-zero area relative to their size */
    size_t kept = 0;
    for (size_t t = 0; t < nt; ++t) {
        unsigned a = mesh->indices[3 * t], b = mesh->indices[3 * t + 1], c = mesh->indices[3 * t + 2];
        if (a >= nv || b >= nv || c >= nv || a == b || b == c || a == c) continue;
        vbl_vec3 pa = vbl_vertex(g.positions, a), pb = vbl_vertex(g.positions, b), pc = vbl_vertex(g.positions, c);
        vbl_vec3 e1 = vbl_v3_sub(pb, pa), e2 = vbl_v3_sub(pc, pa);
        double area2 = vbl_v3_length(vbl_v3_cross(e1, e2));
        double edge2 = fmax(vbl_v3_dot(e1, e1), vbl_v3_dot(e2, e2));
        if (!(area2 > 1e-12 * edge2)) continue; /* zero area or a sliver that float cannot resolve */
        g.indices[3 * kept] = a;
        g.indices[3 * kept + 1] = b;
        g.indices[3 * kept + 2] = c;
        ++kept;
    }
    if (dropped) *dropped = nt - kept;
    if (kept == 0) {
        free(g.positions);
        free(g.indices);
        free(g.normals);
        return vbl_error(VBL_ERROR_SCENE, "%s: all %zu triangles are degenerate (zero area or repeated indices)",
                         what, nt);
    }
    g.triangle_count = kept;

    RTCGeometry geom = rtcNewGeometry(s->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    float* vb = geom ? rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), nv)
                     : NULL;
    unsigned* ib = geom ? rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                  3 * sizeof(unsigned), kept)
                        : NULL;
    vbl_result r = VBL_SUCCESS;
    if (!geom || !vb || !ib) {
        r = vbl_embree_check(s, what);
        if (!r) r = vbl_error(VBL_ERROR_OUT_OF_MEMORY, "%s: Embree could not allocate the mesh", what);
        if (geom) rtcReleaseGeometry(geom);
        free(g.positions);
        free(g.indices);
        free(g.normals);
        return r;
    }
    for (size_t i = 0; i < 3 * nv; ++i) vb[i] = (float)g.positions[i];
    memcpy(ib, g.indices, 3 * kept * sizeof(unsigned));
    rtcCommitGeometry(geom);
    rtcAttachGeometryByID(s->scene, geom, (unsigned)s->count);
    rtcReleaseGeometry(geom);
    rtcCommitScene(s->scene);
    if ((r = vbl_embree_check(s, what))) {
        free(g.positions);
        free(g.indices);
        free(g.normals);
        return r;
    }
    for (size_t i = 0; i < nv; ++i) {
        vbl_vec3 p = vbl_vertex(g.positions, (unsigned)i);
        s->lo = vbl_v3(fmin(s->lo.x, p.x), fmin(s->lo.y, p.y), fmin(s->lo.z, p.z));
        s->hi = vbl_v3(fmax(s->hi.x, p.x), fmax(s->hi.y, p.y), fmax(s->hi.z, p.z));
        s->extent = fmax(s->extent, fmax(fabs(p.x), fmax(fabs(p.y), fabs(p.z))));
    }
    s->geoms[s->count++] = g;
    s->triangles += kept;
    return VBL_SUCCESS;
}

double vbl_surfaces_ray_epsilon(const vbl_surfaces* s, vbl_vec3 p)
{
    /* Embree's single-precision hits are good to a few float ulps of the coordinates' magnitude
     * (2^-23 ~ 1.2e-7 relative): 1e-5 of the larger of the scene's and the point's extent is
     * about a hundred ulps, far above the error and far below any feature worth rendering. */
    double m = fmax(fabs(p.x), fmax(fabs(p.y), fabs(p.z)));
    double scale = fmax(s ? s->extent : 0.0, m);
    return 1e-5 * fmax(scale, 1e-6);
}

static void vbl_fill_ray(struct RTCRay* ray, vbl_vec3 o, vbl_vec3 d, double t_min, double t_max)
{
    ray->org_x = (float)o.x;
    ray->org_y = (float)o.y;
    ray->org_z = (float)o.z;
    ray->dir_x = (float)d.x;
    ray->dir_y = (float)d.y;
    ray->dir_z = (float)d.z;
    ray->tnear = (float)fmax(t_min, 0.0);
    ray->tfar = t_max >= (double)FLT_MAX ? INFINITY : (float)t_max;
    ray->time = 0.0f;
    ray->mask = 0xffffffffu;
    ray->id = 0;
    ray->flags = 0;
}

/* Ray casts of this thread (vbl_surfaces_ray_count). */
static _Thread_local uint64_t vbl_thread_rays;

uint64_t vbl_surfaces_ray_count(void) { return vbl_thread_rays; }

int vbl_surfaces_intersect(const vbl_surfaces* s, vbl_vec3 origin, vbl_vec3 direction, double t_min, double t_max,
                           vbl_surface_hit* hit)
{
    if (!s || s->count == 0 || !(t_max > t_min)) return 0;
    ++vbl_thread_rays;
    struct RTCRayHit rh;
    vbl_fill_ray(&rh.ray, origin, direction, t_min, t_max);
    if (!(rh.ray.tfar > rh.ray.tnear)) return 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    struct RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    rtcIntersect1(s->scene, &context, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID || rh.hit.geomID >= (unsigned)s->count) return 0;
    const vbl_surface_geom* g = &s->geoms[rh.hit.geomID];
    if (rh.hit.primID >= g->triangle_count) return 0;
    const unsigned* tri = g->indices + 3 * (size_t)rh.hit.primID;
    vbl_vec3 p0 = vbl_vertex(g->positions, tri[0]), p1 = vbl_vertex(g->positions, tri[1]),
             p2 = vbl_vertex(g->positions, tri[2]);
    double u = rh.hit.u, v = rh.hit.v, w = 1.0 - u - v;
    vbl_vec3 ng = vbl_v3_normalize(vbl_v3_cross(vbl_v3_sub(p1, p0), vbl_v3_sub(p2, p0)));
    if (vbl_v3_dot(ng, direction) > 0.0) ng = vbl_v3_scale(ng, -1.0);
    vbl_vec3 ns = ng;
    if (g->normals) {
        vbl_vec3 n = vbl_v3_add(vbl_v3_scale(vbl_vertex(g->normals, tri[0]), w),
                                vbl_v3_add(vbl_v3_scale(vbl_vertex(g->normals, tri[1]), u),
                                           vbl_v3_scale(vbl_vertex(g->normals, tri[2]), v)));
        double len = vbl_v3_length(n);
        if (len > 1e-6) {
            n = vbl_v3_scale(n, 1.0 / len);
            ns = vbl_v3_dot(n, ng) < 0.0 ? vbl_v3_scale(n, -1.0) : n;
        }
    }
    hit->t = rh.ray.tfar;
    hit->position = vbl_v3_add(vbl_v3_scale(p0, w), vbl_v3_add(vbl_v3_scale(p1, u), vbl_v3_scale(p2, v)));
    hit->geometric_normal = ng;
    hit->shading_normal = ns;
    hit->surface = (int)rh.hit.geomID;
    hit->material = g->material;
    return 1;
}

int vbl_surfaces_occluded(const vbl_surfaces* s, vbl_vec3 origin, vbl_vec3 direction, double t_min, double t_max)
{
    if (!s || s->count == 0 || !(t_max > t_min)) return 0;
    ++vbl_thread_rays;
    struct RTCRay ray;
    vbl_fill_ray(&ray, origin, direction, t_min, t_max);
    if (!(ray.tfar > ray.tnear)) return 0;
    struct RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    rtcOccluded1(s->scene, &context, &ray);
    return ray.tfar < 0.0f;
}
