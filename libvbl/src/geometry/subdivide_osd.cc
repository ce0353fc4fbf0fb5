// Subdivision surfaces with OpenSubdiv Far (subdivide.h). OpenSubdiv reports problems through
// global callbacks that print by default; they are redirected into a thread-local message here
// so the library never prints, and every exception is turned into a vbl_error.
#include "geometry/subdivide.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <new>
#include <vector>

#include <opensubdiv/far/error.h>
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include "core/error.h"

using namespace OpenSubdiv;

namespace {

thread_local char osd_message[512];

void osd_error(Far::ErrorType, const char* message)
{
    if (!osd_message[0]) std::snprintf(osd_message, sizeof osd_message, "%s", message ? message : "");
}

void osd_warning(const char*) {}

struct Point {
    double p[3];
    void Clear(void* = nullptr) { p[0] = p[1] = p[2] = 0.0; }
    void AddWithWeight(const Point& src, float w)
    {
        for (int k = 0; k < 3; ++k) p[k] += double(w) * src.p[k];
    }
};

vbl_result copy_out(const std::vector<Point>& pos, const std::vector<Point>* normals, const std::vector<unsigned>& tris,
                    const char* what, vbl_mesh_data* out)
{
    std::memset(out, 0, sizeof *out);
    out->positions = static_cast<double*>(std::malloc(3 * pos.size() * sizeof(double)));
    out->indices = static_cast<unsigned*>(std::malloc(tris.size() * sizeof(unsigned)));
    out->normals = normals ? static_cast<double*>(std::malloc(3 * pos.size() * sizeof(double))) : nullptr;
    if (!out->positions || !out->indices || (normals && !out->normals)) {
        vbl_mesh_data_free(out);
        return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory subdividing", what);
    }
    for (size_t i = 0; i < pos.size(); ++i)
        for (int k = 0; k < 3; ++k) {
            out->positions[3 * i + k] = pos[i].p[k];
            if (normals) out->normals[3 * i + k] = (*normals)[i].p[k];
        }
    std::memcpy(out->indices, tris.data(), tris.size() * sizeof(unsigned));
    out->vertex_count = pos.size();
    out->triangle_count = tris.size() / 3;
    return VBL_SUCCESS;
}

vbl_result subdivide(const double* positions, size_t vertex_count, const int* face_sizes, size_t face_count,
                     const int* indices, int level, const char* what, vbl_mesh_data* out)
{
    if (vertex_count == 0 || face_count == 0)
        return vbl_error(VBL_ERROR_SCENE, "%s: the subdivision mesh has no faces", what);
    if (vertex_count > 0x7fffffff || face_count > 0x7fffffff)
        return vbl_error(VBL_ERROR_UNSUPPORTED, "%s: the subdivision mesh is too large", what);
    bool all_triangles = true;
    size_t offset = 0;
    for (size_t f = 0; f < face_count; ++f) {
        int n = face_sizes[f];
        if (n < 3) return vbl_error(VBL_ERROR_SCENE, "%s: face %zu has %d vertices (at least 3)", what, f, n);
        if (n != 3) all_triangles = false;
        for (int i = 0; i < n; ++i) {
            int v = indices[offset + i];
            if (v < 0 || size_t(v) >= vertex_count)
                return vbl_error(VBL_ERROR_SCENE, "%s: face %zu refers to vertex %d of %zu", what, f, v, vertex_count);
            for (int j = 0; j < i; ++j)
                if (indices[offset + j] == v)
                    return vbl_error(VBL_ERROR_SCENE, "%s: face %zu uses vertex %d twice (invalid topology)", what,
                                     f, v);
        }
        offset += size_t(n);
    }
    for (size_t i = 0; i < 3 * vertex_count; ++i)
        if (!std::isfinite(positions[i])) return vbl_error(VBL_ERROR_SCENE, "%s: a vertex is not finite", what);

    std::vector<Point> control(vertex_count);
    for (size_t i = 0; i < vertex_count; ++i)
        for (int k = 0; k < 3; ++k) control[i].p[k] = positions[3 * i + k];

    if (level <= 0) { // the control cage, fan-triangulated
        std::vector<unsigned> tris;
        offset = 0;
        for (size_t f = 0; f < face_count; ++f) {
            for (int i = 1; i + 1 < face_sizes[f]; ++i) {
                tris.push_back(unsigned(indices[offset]));
                tris.push_back(unsigned(indices[offset + i]));
                tris.push_back(unsigned(indices[offset + i + 1]));
            }
            offset += size_t(face_sizes[f]);
        }
        return copy_out(control, nullptr, tris, what, out);
    }

    typedef Far::TopologyDescriptor Descriptor;
    Descriptor desc;
    desc.numVertices = int(vertex_count);
    desc.numFaces = int(face_count);
    desc.numVertsPerFace = face_sizes;
    desc.vertIndicesPerFace = indices;
    Sdc::Options sdc;
    sdc.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER);
    Sdc::SchemeType scheme = all_triangles ? Sdc::SCHEME_LOOP : Sdc::SCHEME_CATMARK;

    Far::SetErrorCallback(osd_error);
    Far::SetWarningCallback(osd_warning);
    osd_message[0] = '\0';
    std::unique_ptr<Far::TopologyRefiner> refiner(Far::TopologyRefinerFactory<Descriptor>::Create(
        desc, Far::TopologyRefinerFactory<Descriptor>::Options(scheme, sdc)));
    if (!refiner)
        return vbl_error(VBL_ERROR_SCENE, "%s: OpenSubdiv rejected the topology (%s)", what,
                         osd_message[0] ? osd_message : "invalid mesh");
    Far::TopologyRefiner::UniformOptions uniform(level);
    uniform.fullTopologyInLastLevel = true; // Limit() needs the last level's full topology
    refiner->RefineUniform(uniform);
    if (refiner->GetMaxLevel() != level)
        return vbl_error(VBL_ERROR_SCENE, "%s: OpenSubdiv could not refine to level %d (%s)", what, level,
                         osd_message[0] ? osd_message : "unknown reason");

    // refined positions level by level, then the last level's vertices onto the limit surface
    std::vector<Point> current = control, next;
    Far::PrimvarRefiner primvar(*refiner);
    for (int l = 1; l <= level; ++l) {
        next.assign(size_t(refiner->GetLevel(l).GetNumVertices()), Point());
        primvar.Interpolate(l, current, next);
        current.swap(next);
    }
    const Far::TopologyLevel& last = refiner->GetLevel(level);
    const size_t nv = size_t(last.GetNumVertices());
    std::vector<Point> limit(nv), du(nv), dv(nv), normals(nv);
    primvar.Limit(current, limit, du, dv);
    if (osd_message[0]) return vbl_error(VBL_ERROR_SCENE, "%s: OpenSubdiv: %s", what, osd_message);
    for (size_t i = 0; i < nv; ++i) {
        const double* a = du[i].p;
        const double* b = dv[i].p;
        double n[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
        double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        for (int k = 0; k < 3; ++k) normals[i].p[k] = (len > 0.0 && std::isfinite(len)) ? n[k] / len : 0.0;
        for (int k = 0; k < 3; ++k)
            if (!std::isfinite(limit[i].p[k]))
                return vbl_error(VBL_ERROR_INTERNAL, "%s: OpenSubdiv produced a non-finite limit point", what);
    }
    std::vector<unsigned> tris;
    tris.reserve(size_t(last.GetNumFaces()) * 6);
    for (int f = 0; f < last.GetNumFaces(); ++f) {
        Far::ConstIndexArray fv = last.GetFaceVertices(f);
        for (int i = 1; i + 1 < fv.size(); ++i) {
            tris.push_back(unsigned(fv[0]));
            tris.push_back(unsigned(fv[i]));
            tris.push_back(unsigned(fv[i + 1]));
        }
    }
    return copy_out(limit, &normals, tris, what, out);
}

} // namespace

extern "C" vbl_result vbl_subdivide(const double* positions, size_t vertex_count, const int* face_sizes,
                                    size_t face_count, const int* indices, int level, const char* what,
                                    vbl_mesh_data* out)
{
    std::memset(out, 0, sizeof *out);
    if (!positions || !face_sizes || !indices || !what)
        return vbl_error(VBL_ERROR_INVALID_ARGUMENT, "vbl_subdivide: NULL argument");
    if (level < 0 || level > VBL_SUBDIVISION_MAX_LEVEL)
        return vbl_error(VBL_ERROR_SCENE, "%s: subdivision level %d is outside [0, %d]", what, level,
                         VBL_SUBDIVISION_MAX_LEVEL);
    try {
        return subdivide(positions, vertex_count, face_sizes, face_count, indices, level, what, out);
    } catch (const std::bad_alloc&) {
        vbl_mesh_data_free(out);
        return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory subdividing", what);
    } catch (...) {
        vbl_mesh_data_free(out);
        return vbl_error(VBL_ERROR_INTERNAL, "%s: OpenSubdiv failed", what);
    }
}
