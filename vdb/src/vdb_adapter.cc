// C entry points of the adapter: file kind detection, grid selection rules, and the one place
// where every C++ exception becomes a vbl_result plus a one-line message naming the file.
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <new>
#include <sstream>

#include <nanovdb/NanoVDB.h>

#include "core/alloc.h"
#include "core/memory_limit.h"
#include "vdb_internal.h"

#pragma GCC visibility push(hidden) // internal to libvbl (see vdb/CMakeLists.txt)

namespace vbl_vdb {

void set_string(char* dst, std::size_t capacity, const std::string& src)
{
    if (!dst || capacity == 0) return;
    std::size_t n = src.size() < capacity - 1 ? src.size() : capacity - 1;
    std::memcpy(dst, src.data(), n);
    dst[n] = '\0';
}

std::string printable(const std::string& text, std::size_t keep)
{
    static const char hex[] = "0123456789abcdef";
    std::string out;
    for (std::size_t i = 0; i < text.size(); ++i) {
        if (i == keep) {
            out += "...";
            break;
        }
        const unsigned char c = static_cast<unsigned char>(text[i]);
        if (c >= 0x20 && c < 0x7f && c != '\\') {
            out += char(c);
        } else {
            out += "\\x";
            out += hex[c >> 4];
            out += hex[c & 15];
        }
    }
    return out;
}

void check_memory_limit(std::uint64_t bytes, const std::string& what)
{
    if (bytes <= vbl_memory_limit()) return;
    char text[512];
    vbl_memory_limit_message(text, sizeof text, bytes, what.c_str());
    throw Failure(VBL_ERROR_UNSUPPORTED, text);
}

void* copy_aligned(const void* data, std::size_t size)
{
    void* buffer = vbl_aligned_alloc(32, size);
    if (!buffer) throw Failure(VBL_ERROR_OUT_OF_MEMORY, "out of memory allocating " + std::to_string(size) + " bytes");
    std::memcpy(buffer, data, size);
    return buffer;
}

FileKind sniff_file(const std::string& path)
{
    std::ifstream is(path, std::ios::in | std::ios::binary);
    if (!is.is_open()) {
        int err = errno;
        throw Failure(VBL_ERROR_FILE_NOT_FOUND, std::string("cannot open: ") + std::strerror(err ? err : ENOENT));
    }
    unsigned char magic[8] = {0};
    is.read(reinterpret_cast<char*>(magic), sizeof magic);
    if (is.gcount() < 8) throw Failure(VBL_ERROR_CORRUPT_FILE, "not a VDB or NanoVDB file (only " + std::to_string(is.gcount()) + " bytes)");
    // OpenVDB: int64 0x56444220 ("VDB " little-endian); NanoVDB: "NanoVDB0" (grid/segment magic),
    // "NanoVDB1" is the file magic of NanoVDB >= 32.6 (a newer container this build cannot read).
    static const unsigned char vdb[8] = {0x20, 0x42, 0x44, 0x56, 0, 0, 0, 0};
    if (!std::memcmp(magic, vdb, 8)) return FileKind::OpenVdb;
    if (!std::memcmp(magic, "NanoVDB0", 8)) return FileKind::NanoVdb;
    if (!std::memcmp(magic, "NanoVDB", 7))
        throw Failure(VBL_ERROR_UNSUPPORTED, std::string("NanoVDB file container '") + printable(std::string(reinterpret_cast<char*>(magic), 8)) +
                                                 "' is newer than this build's NanoVDB " + std::to_string(NANOVDB_MAJOR_VERSION_NUMBER) + ".x reader");
    throw Failure(VBL_ERROR_CORRUPT_FILE, "not a VDB or NanoVDB file (bad magic number)");
}

} // namespace vbl_vdb

using namespace vbl_vdb;

namespace {

std::vector<GridEntry> list_entries(const std::string& path, bool describe)
{
    return sniff_file(path) == FileKind::OpenVdb ? openvdb_list(path, describe) : nanovdb_list(path);
}

std::string describe_grids(const std::vector<GridEntry>& grids)
{
    std::ostringstream ss;
    ss << "grids in file:";
    if (grids.empty()) ss << " none";
    for (std::size_t i = 0; i < grids.size(); ++i)
        ss << (i ? ", " : " ") << "[" << i << "] '" << printable(grids[i].desc.name) << "' " << grids[i].desc.type;
    return ss.str();
}

// Grid selection (see docs/readme/vdb.md): by name (default "density", then the only float
// grid), grid_index picks among same-named grids, or among all grids when no name is given.
std::size_t select_grid(const std::vector<GridEntry>& grids, const char* grid_name, int grid_index)
{
    std::vector<std::size_t> matches;
    std::string wanted = grid_name ? grid_name : "density";
    if (!grid_name && grid_index >= 0) {
        if (std::size_t(grid_index) >= grids.size())
            throw Failure(VBL_ERROR_GRID_NOT_FOUND, "no grid at index " + std::to_string(grid_index) + "; " + describe_grids(grids));
        return std::size_t(grid_index);
    }
    for (std::size_t i = 0; i < grids.size(); ++i)
        if (wanted == grids[i].desc.name) matches.push_back(i);
    if (matches.empty() && !grid_name) {
        std::vector<std::size_t> floats;
        for (std::size_t i = 0; i < grids.size(); ++i)
            if (grids[i].desc.is_float) floats.push_back(i);
        if (floats.size() == 1) return floats[0];
        throw Failure(VBL_ERROR_GRID_NOT_FOUND, "no grid named 'density' and " +
                                                    std::string(floats.empty() ? "no float grid" : "more than one float grid") +
                                                    " (pick one with a grid name or index); " + describe_grids(grids));
    }
    if (matches.empty())
        throw Failure(VBL_ERROR_GRID_NOT_FOUND, "no grid named '" + wanted + "'; " + describe_grids(grids));
    std::size_t pick = grid_index < 0 ? 0 : std::size_t(grid_index);
    if (pick >= matches.size())
        throw Failure(VBL_ERROR_GRID_NOT_FOUND, "grid index " + std::to_string(grid_index) + " out of range: " +
                                                    std::to_string(matches.size()) + " grid(s) named '" + wanted + "'; " +
                                                    describe_grids(grids));
    return matches[pick];
}

vbl_result fail(char* message, std::size_t message_size, const char* path, vbl_result code, const std::string& what)
{
    std::string text = std::string(path ? path : "(null)") + ": " + what;
    for (char& c : text)
        if (c == '\n' || c == '\r' || c == '\t') c = ' ';
    set_string(message, message_size, text);
    return code;
}

template<typename F>
vbl_result guarded(const char* path, char* message, std::size_t message_size, F&& body)
{
    try {
        body();
        return VBL_SUCCESS;
    } catch (const Failure& f) {
        return fail(message, message_size, path, f.code, f.what());
    } catch (const std::bad_alloc&) {
        return fail(message, message_size, path, VBL_ERROR_OUT_OF_MEMORY, "out of memory while reading");
    } catch (const std::exception& e) {
        // OpenVDB/NanoVDB/blosc/zlib errors while decoding: the file is damaged or truncated.
        return fail(message, message_size, path, VBL_ERROR_CORRUPT_FILE, std::string("cannot read (corrupt or truncated file): ") + printable(e.what(), 240));
    } catch (...) {
        return fail(message, message_size, path, VBL_ERROR_CORRUPT_FILE, "cannot read (corrupt or truncated file)");
    }
}

} // namespace

extern "C" vbl_result vbl_vdb_read_float_grid(const char* path, const char* grid_name, int grid_index, void** out_buffer,
                                              size_t* out_size, int* out_file_grid_index, char* message,
                                              size_t message_size)
{
    if (message && message_size) message[0] = '\0';
    if (!path || !out_buffer || !out_size)
        return fail(message, message_size, path, VBL_ERROR_INVALID_ARGUMENT, "vbl_vdb_read_float_grid: NULL argument");
    *out_buffer = nullptr;
    *out_size = 0;
    return guarded(path, message, message_size, [&] {
        FileKind kind = sniff_file(path);
        std::vector<GridEntry> grids = kind == FileKind::OpenVdb ? openvdb_list(path, false) : nanovdb_list(path);
        std::size_t index = select_grid(grids, grid_name, grid_index);
        const GridEntry& entry = grids[index];
        if (!entry.desc.is_float)
            throw Failure(VBL_ERROR_GRID_TYPE, "grid [" + std::to_string(index) + "] '" + printable(entry.desc.name) + "' is " +
                                                   entry.desc.type + ", not a float grid");
        if (kind == FileKind::OpenVdb)
            openvdb_read_float(path, entry, out_buffer, out_size);
        else
            nanovdb_read_float(path, entry, out_buffer, out_size);
        if (out_file_grid_index) *out_file_grid_index = int(index);
    });
}

extern "C" vbl_result vbl_vdb_read_vec3_component(const char* path, const char* grid_name, int grid_index, int component,
                                                 void** out_buffer, size_t* out_size, int* out_file_grid_index,
                                                 char* message, size_t message_size)
{
    if (message && message_size) message[0] = '\0';
    if (!path || !out_buffer || !out_size || component < 0 || component > 2)
        return fail(message, message_size, path, VBL_ERROR_INVALID_ARGUMENT, "vbl_vdb_read_vec3_component: bad argument");
    *out_buffer = nullptr;
    *out_size = 0;
    return guarded(path, message, message_size, [&] {
        FileKind kind = sniff_file(path);
        std::vector<GridEntry> grids = kind == FileKind::OpenVdb ? openvdb_list(path, false) : nanovdb_list(path);
        std::size_t index = select_grid(grids, grid_name, grid_index);
        const GridEntry& entry = grids[index];
        if (!is_vec3_type(entry))
            throw Failure(VBL_ERROR_GRID_TYPE, "grid [" + std::to_string(index) + "] '" + printable(entry.desc.name) + "' is " +
                                                   entry.desc.type + ", not a vec3s/vec3d grid");
        if (kind != FileKind::OpenVdb)
            throw Failure(VBL_ERROR_UNSUPPORTED, "grid '" + printable(entry.desc.name) +
                                                     "': vector grids are read from OpenVDB (.vdb) files only, not NanoVDB");
        openvdb_read_vec3_component(path, entry, component, out_buffer, out_size);
        if (out_file_grid_index) *out_file_grid_index = int(index);
    });
}

extern "C" vbl_result vbl_vdb_list_grids(const char* path, vbl_vdb_grid_desc** out_grids, size_t* out_count,
                                         char* message, size_t message_size)
{
    if (message && message_size) message[0] = '\0';
    if (!path || !out_grids || !out_count)
        return fail(message, message_size, path, VBL_ERROR_INVALID_ARGUMENT, "vbl_vdb_list_grids: NULL argument");
    *out_grids = nullptr;
    *out_count = 0;
    return guarded(path, message, message_size, [&] {
        std::vector<GridEntry> grids = list_entries(path, true);
        auto* descs = static_cast<vbl_vdb_grid_desc*>(std::calloc(grids.empty() ? 1 : grids.size(), sizeof(vbl_vdb_grid_desc)));
        if (!descs) throw std::bad_alloc();
        for (std::size_t i = 0; i < grids.size(); ++i) descs[i] = grids[i].desc;
        *out_grids = descs;
        *out_count = grids.size();
    });
}

#pragma GCC visibility pop
