/* Mesh files through assimp's C API (mesh_load.h). */
#include "geometry/mesh_load.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <assimp/cimport.h>
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include "core/error.h"
#include "geometry/mesh_ply_check.h"

static vbl_result vbl_mesh_open(const char* path, int polygons, const struct aiScene** out)
{
    *out = NULL;
    FILE* f = fopen(path, "rb");
    if (!f) return vbl_error(VBL_ERROR_FILE_NOT_FOUND, "%s: cannot open mesh file (%s)", path, strerror(errno));
    fclose(f);
    if (vbl_mesh_is_ply(path)) {
        vbl_result checked = vbl_mesh_check_ply(path);
        if (checked) return checked;
    }
    /* PreTransformVertices bakes the node hierarchy into scene space and merges meshes per
     * material; SortByPType separates points/lines (degenerate faces turned into lines/points by
     * FindDegenerates) so they can be dropped. */
    unsigned flags = aiProcess_JoinIdenticalVertices | aiProcess_FindDegenerates | aiProcess_SortByPType |
                     aiProcess_PreTransformVertices | aiProcess_ValidateDataStructure | aiProcess_FindInvalidData;
    struct aiPropertyStore* props = aiCreatePropertyStore();
    if (!props) return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory (assimp)", path);
    if (polygons) {
        /* subdivision input: keep polygons, join vertices by position alone */
        flags |= aiProcess_RemoveComponent;
        aiSetImportPropertyInteger(props, AI_CONFIG_PP_RVC_FLAGS,
                                   aiComponent_NORMALS | aiComponent_TANGENTS_AND_BITANGENTS | aiComponent_COLORS |
                                       aiComponent_TEXCOORDS | aiComponent_BONEWEIGHTS | aiComponent_ANIMATIONS |
                                       aiComponent_TEXTURES | aiComponent_LIGHTS | aiComponent_CAMERAS |
                                       aiComponent_MATERIALS);
    } else {
        flags |= aiProcess_Triangulate;
    }
    const struct aiScene* scene = aiImportFileExWithProperties(path, flags, NULL, props);
    aiReleasePropertyStore(props);
    if (!scene) {
        /* assimp's messages can quote the file's bytes: only printable ASCII goes into ours */
        const char* msg = aiGetErrorString();
        char quoted[256];
        size_t n = 0;
        for (const char* c = msg && msg[0] ? msg : "unknown error"; *c && n + 1 < sizeof quoted; ++c)
            quoted[n++] = (*c >= 0x20 && *c < 0x7f) ? *c : '?';
        quoted[n] = '\0';
        return vbl_error(VBL_ERROR_CORRUPT_FILE, "%s: cannot read the mesh (assimp: %s)", path, quoted);
    }
    if (scene->mNumMeshes == 0) {
        aiReleaseImport(scene);
        return vbl_error(VBL_ERROR_SCENE, "%s: the file contains no mesh", path);
    }
    *out = scene;
    return VBL_SUCCESS;
}

vbl_result vbl_mesh_load(const char* path, vbl_mesh_data* out, size_t* dropped)
{
    memset(out, 0, sizeof *out);
    if (dropped) *dropped = 0;
    const struct aiScene* scene = NULL;
    vbl_result r = vbl_mesh_open(path, 0, &scene);
    if (r) return r;
    size_t nv = 0, nt = 0, skipped = 0;
    int all_normals = 1;
    for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
        const struct aiMesh* mesh = scene->mMeshes[m];
        if (!mesh || !(mesh->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) {
            skipped += mesh ? mesh->mNumFaces : 0;
            continue;
        }
        nv += mesh->mNumVertices;
        for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
            if (mesh->mFaces[f].mNumIndices == 3) ++nt;
            else ++skipped;
        }
        if (!mesh->mNormals) all_normals = 0;
    }
    if (dropped) *dropped = skipped;
    if (nt == 0 || nv == 0) {
        aiReleaseImport(scene);
        return vbl_error(VBL_ERROR_SCENE, "%s: the mesh has no triangles (%zu faces dropped as points, lines or "
                                          "degenerate)", path, skipped);
    }
    if (nv > 0xffffffffu) {
        aiReleaseImport(scene);
        return vbl_error(VBL_ERROR_UNSUPPORTED, "%s: too many vertices (%zu)", path, nv);
    }
    out->positions = malloc(3 * nv * sizeof(double));
    out->indices = malloc(3 * nt * sizeof(unsigned));
    out->normals = all_normals ? malloc(3 * nv * sizeof(double)) : NULL;
    if (!out->positions || !out->indices || (all_normals && !out->normals)) {
        aiReleaseImport(scene);
        vbl_mesh_data_free(out);
        return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory loading the mesh", path);
    }
    size_t base = 0, t = 0;
    for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
        const struct aiMesh* mesh = scene->mMeshes[m];
        if (!mesh || !(mesh->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
        for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
            out->positions[3 * (base + v)] = mesh->mVertices[v].x;
            out->positions[3 * (base + v) + 1] = mesh->mVertices[v].y;
            out->positions[3 * (base + v) + 2] = mesh->mVertices[v].z;
            if (out->normals) {
                out->normals[3 * (base + v)] = mesh->mNormals[v].x;
                out->normals[3 * (base + v) + 1] = mesh->mNormals[v].y;
                out->normals[3 * (base + v) + 2] = mesh->mNormals[v].z;
            }
        }
        for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
            const struct aiFace* face = &mesh->mFaces[f];
            if (face->mNumIndices != 3) continue;
            for (int k = 0; k < 3; ++k) out->indices[3 * t + k] = (unsigned)(base + face->mIndices[k]);
            ++t;
        }
        base += mesh->mNumVertices;
    }
    out->vertex_count = nv;
    out->triangle_count = nt;
    aiReleaseImport(scene);
    return VBL_SUCCESS;
}

void vbl_poly_mesh_free(vbl_poly_mesh* mesh)
{
    if (!mesh) return;
    free(mesh->positions);
    free(mesh->face_sizes);
    free(mesh->indices);
    memset(mesh, 0, sizeof *mesh);
}

vbl_result vbl_mesh_load_polygons(const char* path, vbl_poly_mesh* out)
{
    memset(out, 0, sizeof *out);
    const struct aiScene* scene = NULL;
    vbl_result r = vbl_mesh_open(path, 1, &scene);
    if (r) return r;
    size_t nv = 0, nf = 0, ni = 0;
    for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
        const struct aiMesh* mesh = scene->mMeshes[m];
        if (!mesh || !(mesh->mPrimitiveTypes & (aiPrimitiveType_TRIANGLE | aiPrimitiveType_POLYGON))) continue;
        nv += mesh->mNumVertices;
        for (unsigned f = 0; f < mesh->mNumFaces; ++f)
            if (mesh->mFaces[f].mNumIndices >= 3) {
                ++nf;
                ni += mesh->mFaces[f].mNumIndices;
            }
    }
    if (nf == 0 || nv == 0) {
        aiReleaseImport(scene);
        return vbl_error(VBL_ERROR_SCENE, "%s: the mesh has no polygons", path);
    }
    if (nv > 0x7fffffff || ni > 0x7fffffff) {
        aiReleaseImport(scene);
        return vbl_error(VBL_ERROR_UNSUPPORTED, "%s: the mesh is too large to subdivide", path);
    }
    out->positions = malloc(3 * nv * sizeof(double));
    out->face_sizes = malloc(nf * sizeof(int));
    out->indices = malloc(ni * sizeof(int));
    if (!out->positions || !out->face_sizes || !out->indices) {
        aiReleaseImport(scene);
        vbl_poly_mesh_free(out);
        return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory loading the mesh", path);
    }
    size_t base = 0, f_out = 0, i_out = 0;
    for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
        const struct aiMesh* mesh = scene->mMeshes[m];
        if (!mesh || !(mesh->mPrimitiveTypes & (aiPrimitiveType_TRIANGLE | aiPrimitiveType_POLYGON))) continue;
        for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
            out->positions[3 * (base + v)] = mesh->mVertices[v].x;
            out->positions[3 * (base + v) + 1] = mesh->mVertices[v].y;
            out->positions[3 * (base + v) + 2] = mesh->mVertices[v].z;
        }
        for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
            const struct aiFace* face = &mesh->mFaces[f];
            if (face->mNumIndices < 3) continue;
            out->face_sizes[f_out++] = (int)face->mNumIndices;
            for (unsigned k = 0; k < face->mNumIndices; ++k) out->indices[i_out++] = (int)(base + face->mIndices[k]);
        }
        base += mesh->mNumVertices;
    }
    out->vertex_count = nv;
    out->face_count = nf;
    out->index_count = ni;
    aiReleaseImport(scene);
    return VBL_SUCCESS;
}
