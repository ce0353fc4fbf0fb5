#define _POSIX_C_SOURCE 200809L
/* PLY validation before assimp (mesh_ply_check.h). The header grammar is the one of Turk's PLY
 * format (1994): "ply", "format <ascii|binary_little_endian|binary_big_endian> 1.0", then
 * "element <name> <count>" each followed by "property <type> <name>" or
 * "property list <count type> <index type> <name>", "comment"/"obj_info" lines, "end_header". */
#include "geometry/mesh_ply_check.h"

#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "core/memory_limit.h"

#define VBL_PLY_MAX_HEADER 65536
#define VBL_PLY_MAX_ELEMENTS 64
#define VBL_PLY_MAX_PROPERTIES 64
#define VBL_PLY_MAX_FACE_VERTICES 256

typedef struct vbl_ply_property {
    int size;       /* bytes of the value (binary), 0 if unknown */
    int list;       /* a list: `count_size` bytes of count, then `size`-byte items */
    int count_size;
    int is_index;   /* face.vertex_indices / vertex_index */
    int is_float;
} vbl_ply_property;

typedef struct vbl_ply_element {
    char name[32];
    uint64_t count;
    int property_count;
    vbl_ply_property properties[VBL_PLY_MAX_PROPERTIES];
} vbl_ply_element;

static int vbl_ply_type_size(const char* type, int* is_float)
{
    static const struct {
        const char* name;
        int size, is_float;
    } types[] = {{"char", 1, 0},   {"uchar", 1, 0},   {"short", 2, 0},   {"ushort", 2, 0},  {"int", 4, 0},
                 {"uint", 4, 0},   {"float", 4, 1},   {"double", 8, 1},  {"int8", 1, 0},    {"uint8", 1, 0},
                 {"int16", 2, 0},  {"uint16", 2, 0},  {"int32", 4, 0},   {"uint32", 4, 0},  {"float32", 4, 1},
                 {"float64", 8, 1}};
    for (size_t i = 0; i < sizeof types / sizeof types[0]; ++i)
        if (!strcmp(type, types[i].name)) {
            if (is_float) *is_float = types[i].is_float;
            return types[i].size;
        }
    return 0;
}

/* Reads a binary value of `size` bytes as an unsigned count/index (sign-extended values count as huge). */
static int vbl_ply_read_uint(FILE* f, int size, int big_endian, int is_float, uint64_t* out)
{
    unsigned char b[8];
    if (fread(b, 1, (size_t)size, f) != (size_t)size) return 0;
    uint64_t v = 0;
    for (int i = 0; i < size; ++i) v |= (uint64_t)b[big_endian ? size - 1 - i : i] << (8 * i);
    if (is_float) v = UINT64_MAX; /* a float count or index is not a valid one */
    *out = v;
    return 1;
}

/* Walks a binary body: list counts in [1, 256] (face lists), vertex indices < the vertex count,
 * and the file holding every byte. */
static vbl_result vbl_ply_check_binary(FILE* f, const char* path, const vbl_ply_element* elements, int element_count,
                                       int big_endian, uint64_t vertices)
{
    const long body = ftell(f);
    if (body < 0 || fseek(f, 0, SEEK_END) != 0) return vbl_error(VBL_ERROR_CORRUPT_FILE, "%s: cannot seek", path);
    const long long file_size = ftell(f);
    if (fseek(f, body, SEEK_SET) != 0) return vbl_error(VBL_ERROR_CORRUPT_FILE, "%s: cannot seek", path);
    for (int e = 0; e < element_count; ++e) {
        const vbl_ply_element* el = &elements[e];
        for (uint64_t n = 0; n < el->count; ++n)
            for (int p = 0; p < el->property_count; ++p) {
                const vbl_ply_property* pr = &el->properties[p];
                if (!pr->list) {
                    /* fseek succeeds past the end: compare with the file's size (a header claiming
                     * 2^31 vertices of a short file would otherwise loop 2^31 times) */
                    long at = ftell(f);
                    if (at < 0 || (long long)at + pr->size > file_size || fseek(f, pr->size, SEEK_CUR) != 0)
                        return vbl_error(VBL_ERROR_CORRUPT_FILE, "%s: PLY body truncated in element '%s' %llu", path,
                                         el->name, (unsigned long long)n);
                    continue;
                }
                uint64_t items = 0;
                if (!vbl_ply_read_uint(f, pr->count_size, big_endian, 0, &items))
                    return vbl_error(VBL_ERROR_CORRUPT_FILE, "%s: PLY body truncated in element '%s' %llu", path,
                                     el->name, (unsigned long long)n);
                if (items > VBL_PLY_MAX_FACE_VERTICES)
                    return vbl_error(VBL_ERROR_CORRUPT_FILE, "%s: PLY element '%s' %llu has a list of %llu items (at most %d)",
                                     path, el->name, (unsigned long long)n, (unsigned long long)items,
                                     VBL_PLY_MAX_FACE_VERTICES);
                for (uint64_t i = 0; i < items; ++i) {
                    uint64_t index = 0;
                    if (!vbl_ply_read_uint(f, pr->size, big_endian, pr->is_float, &index))
                        return vbl_error(VBL_ERROR_CORRUPT_FILE, "%s: PLY body truncated in element '%s' %llu", path,
                                         el->name, (unsigned long long)n);
                    if (pr->is_index && index >= vertices)
                        return vbl_error(VBL_ERROR_CORRUPT_FILE,
                                         "%s: PLY face %llu uses vertex %llu but the file has %llu vertices", path,
                                         (unsigned long long)n, (unsigned long long)index, (unsigned long long)vertices);
                }
            }
    }
    return VBL_SUCCESS;
}

/* ASCII body: each element line must exist, list counts in [0, 256], indices < the vertex count. */
static vbl_result vbl_ply_check_ascii(FILE* f, const char* path, const vbl_ply_element* elements, int element_count,
                                      uint64_t vertices)
{
    char* line = NULL;
    size_t cap = 0;
    vbl_result r = VBL_SUCCESS;
    for (int e = 0; e < element_count && !r; ++e) {
        const vbl_ply_element* el = &elements[e];
        for (uint64_t n = 0; n < el->count && !r; ++n) {
            if (getline(&line, &cap, f) < 0) {
                r = vbl_error(VBL_ERROR_CORRUPT_FILE, "%s: PLY body ends before element '%s' %llu of %llu", path,
                              el->name, (unsigned long long)n, (unsigned long long)el->count);
                break;
            }
            char* cursor = line;
            for (int p = 0; p < el->property_count && !r; ++p) {
                const vbl_ply_property* pr = &el->properties[p];
                char* end = NULL;
                errno = 0;
                double v = strtod(cursor, &end);
                if (end == cursor) {
                    r = vbl_error(VBL_ERROR_CORRUPT_FILE, "%s: PLY element '%s' %llu: missing or non-numeric value %d",
                                  path, el->name, (unsigned long long)n, p);
                    break;
                }
                cursor = end;
                if (!pr->list) continue;
                if (!(v >= 0.0 && v <= VBL_PLY_MAX_FACE_VERTICES) || v != (double)(int)v) {
                    r = vbl_error(VBL_ERROR_CORRUPT_FILE, "%s: PLY element '%s' %llu has a list count of %g (0 to %d)", path,
                                  el->name, (unsigned long long)n, v, VBL_PLY_MAX_FACE_VERTICES);
                    break;
                }
                for (int i = 0; i < (int)v && !r; ++i) {
                    double index = strtod(cursor, &end);
                    if (end == cursor) {
                        r = vbl_error(VBL_ERROR_CORRUPT_FILE, "%s: PLY element '%s' %llu: list shorter than its count",
                                      path, el->name, (unsigned long long)n);
                        break;
                    }
                    cursor = end;
                    if (pr->is_index && !(index >= 0.0 && index < (double)vertices && index == (double)(uint64_t)index))
                        r = vbl_error(VBL_ERROR_CORRUPT_FILE,
                                      "%s: PLY face %llu uses vertex %g but the file has %llu vertices", path,
                                      (unsigned long long)n, index, (unsigned long long)vertices);
                }
            }
        }
    }
    free(line);
    return r;
}

vbl_result vbl_mesh_check_ply(const char* path)
{
    FILE* f = fopen(path, "rb");
    if (!f) return vbl_error(VBL_ERROR_FILE_NOT_FOUND, "%s: cannot open mesh file (%s)", path, strerror(errno));
    vbl_ply_element* elements = calloc(VBL_PLY_MAX_ELEMENTS, sizeof *elements);
    if (!elements) {
        fclose(f);
        return vbl_error(VBL_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    }
    char line[512];
    int element_count = 0, format = -1, ended = 0, line_no = 0;
    long header_bytes = 0;
    vbl_result r = VBL_SUCCESS;
    while (!r && !ended && fgets(line, sizeof line, f)) {
        ++line_no;
        header_bytes += (long)strlen(line);
        size_t len = strlen(line);
        if (len == sizeof line - 1 && line[len - 1] != '\n') {
            r = vbl_error(VBL_ERROR_CORRUPT_FILE, "%s: PLY header line %d is longer than %d bytes", path, line_no,
                          (int)sizeof line - 2);
            break;
        }
        if (header_bytes > VBL_PLY_MAX_HEADER) {
            r = vbl_error(VBL_ERROR_CORRUPT_FILE, "%s: PLY header longer than %d bytes", path, VBL_PLY_MAX_HEADER);
            break;
        }
        char word[5][64] = {{0}};
        int words = sscanf(line, "%63s %63s %63s %63s %63s", word[0], word[1], word[2], word[3], word[4]);
        if (words <= 0) continue;
        if (line_no == 1) {
            if (strcmp(word[0], "ply")) r = vbl_error(VBL_ERROR_CORRUPT_FILE, "%s: not a PLY file (no 'ply' line)", path);
        } else if (!strcmp(word[0], "format")) {
            if (words < 3 || strcmp(word[2], "1.0")) {
                r = vbl_error(VBL_ERROR_CORRUPT_FILE, "%s: PLY header line %d: unknown format version", path, line_no);
            } else if (!strcmp(word[1], "ascii")) format = 0;
            else if (!strcmp(word[1], "binary_little_endian")) format = 1;
            else if (!strcmp(word[1], "binary_big_endian")) format = 2;
            else r = vbl_error(VBL_ERROR_CORRUPT_FILE, "%s: PLY header line %d: unknown format", path, line_no);
        } else if (!strcmp(word[0], "element")) {
            char* end = NULL;
            errno = 0;
            unsigned long long count = words >= 3 && word[2][0] != '-' ? strtoull(word[2], &end, 10) : 0;
            if (words < 3 || !end || *end || errno || count > INT32_MAX) {
                r = vbl_error(VBL_ERROR_CORRUPT_FILE, "%s: PLY header line %d: element count is not in [0, 2^31)", path,
                              line_no);
            } else if (element_count == VBL_PLY_MAX_ELEMENTS) {
                r = vbl_error(VBL_ERROR_CORRUPT_FILE, "%s: PLY header has more than %d elements", path, VBL_PLY_MAX_ELEMENTS);
            } else {
                vbl_ply_element* el = &elements[element_count++];
                /* Only names of letters, digits and '_' are quoted in messages. */
                const char* ok_chars = "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_";
                const int plain = strlen(word[1]) < sizeof el->name && strspn(word[1], ok_chars) == strlen(word[1]);
                snprintf(el->name, sizeof el->name, "%.31s", plain ? word[1] : "?");
                el->count = count;
            }
        } else if (!strcmp(word[0], "property")) {
            vbl_ply_element* el = element_count ? &elements[element_count - 1] : NULL;
            vbl_ply_property pr = {0};
            int ok = words >= 3;
            const char* name = word[2];
            if (ok && !strcmp(word[1], "list")) {
                int count_is_float = 0;
                pr.list = 1;
                pr.count_size = vbl_ply_type_size(word[2], &count_is_float);
                pr.size = vbl_ply_type_size(word[3], &pr.is_float);
                ok = words == 5 && pr.count_size && !count_is_float && pr.size;
                name = word[4];
            } else if (ok) {
                pr.size = vbl_ply_type_size(word[1], &pr.is_float);
                ok = pr.size != 0;
            }
            if (!el || !ok) {
                r = vbl_error(VBL_ERROR_CORRUPT_FILE, "%s: PLY header line %d: malformed property%s", path, line_no,
                              el ? "" : " before any element");
            } else if (el->property_count == VBL_PLY_MAX_PROPERTIES) {
                r = vbl_error(VBL_ERROR_CORRUPT_FILE, "%s: PLY element '%s' has more than %d properties", path, el->name,
                              VBL_PLY_MAX_PROPERTIES);
            } else {
                pr.is_index = pr.list && !strcmp(el->name, "face") &&
                              (!strcmp(name, "vertex_indices") || !strcmp(name, "vertex_index"));
                el->properties[el->property_count++] = pr;
            }
        } else if (!strcmp(word[0], "end_header")) {
            ended = 1;
        } else if (strcmp(word[0], "comment") && strcmp(word[0], "obj_info")) {
            r = vbl_error(VBL_ERROR_CORRUPT_FILE, "%s: PLY header line %d: unknown keyword", path, line_no);
        }
    }
    if (!r && !ended) r = vbl_error(VBL_ERROR_CORRUPT_FILE, "%s: PLY header without end_header", path);
    if (!r && format < 0) r = vbl_error(VBL_ERROR_CORRUPT_FILE, "%s: PLY header without a format line", path);
    uint64_t vertices = 0;
    for (int e = 0; !r && e < element_count; ++e)
        if (!strcmp(elements[e].name, "vertex")) vertices = elements[e].count;
    if (!r) {
        r = format == 0 ? vbl_ply_check_ascii(f, path, elements, element_count, vertices)
                        : vbl_ply_check_binary(f, path, elements, element_count, format == 2, vertices);
    }
    /* Counts that fit the file still go against the memory limit: assimp's PLY reader keeps every
     * element with its properties (a value and a vector per property, about 64 + 32 bytes each)
     * before building the mesh. */
    uint64_t import_bytes = 0;
    for (int e = 0; !r && e < element_count; ++e)
        import_bytes += elements[e].count * (64u + 32u * (uint64_t)elements[e].property_count);
    if (!r) r = vbl_memory_check(import_bytes, path, "importing the PLY elements (estimated)");
    free(elements);
    fclose(f);
    return r;
}

int vbl_mesh_is_ply(const char* path)
{
    FILE* f = fopen(path, "rb");
    if (!f) return 0;
    char magic[4] = {0};
    size_t n = fread(magic, 1, 4, f);
    fclose(f);
    return n == 4 && !memcmp(magic, "ply", 3) && (magic[3] == '\n' || magic[3] == '\r');
}
