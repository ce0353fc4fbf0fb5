// Size pre-checks for the OpenVDB (.vdb) reader: every length OpenVDB reads from the file before
// allocating (io::readString's uint32 length, Metadata's uint32 byte count) is compared with the
// bytes left in the file first. OpenVDB 10 allocates and fills a std::string of the stated length
// (GridDescriptor::read, MetaMap::readMeta, Transform::read), so a 40 KB file with a 4 GB name per
// grid descriptor took 24 GB before failing (fuzzing, issue 18). Each check reads ahead and puts
// the stream back where it was, so OpenVDB then reads the same bytes itself.
#include <cstdint>
#include <istream>
#include <string>

#include <openvdb/openvdb.h>
#include <openvdb/Metadata.h>
#include <openvdb/math/Maps.h>

#include "vdb_internal.h"

#pragma GCC visibility push(hidden) // internal to libvbl (see vdb/CMakeLists.txt)

namespace vbl_vdb {
namespace {

struct Cursor {
    std::istream& is;
    std::streamoff file_size;

    std::streamoff left()
    {
        std::streamoff pos = is.tellg();
        if (pos < 0 || pos > file_size) throw Failure(VBL_ERROR_CORRUPT_FILE, "truncated file");
        return file_size - pos;
    }
    // Skips `n` bytes that must lie inside the file; `what` names the field for the message.
    void skip(uint64_t n, const std::string& what)
    {
        if (n > uint64_t(left()))
            throw Failure(VBL_ERROR_CORRUPT_FILE, what + " says " + std::to_string(n) + " bytes but the file has " +
                                                      std::to_string(left()) + " bytes left");
        is.seekg(std::streamoff(n), std::ios::cur);
    }
    uint32_t u32(const std::string& what)
    {
        if (left() < 4) throw Failure(VBL_ERROR_CORRUPT_FILE, "truncated file in " + what);
        uint32_t v = 0;
        is.read(reinterpret_cast<char*>(&v), sizeof v);
        if (!is) throw Failure(VBL_ERROR_CORRUPT_FILE, "truncated file in " + what);
        return v;
    }
    // io::readString: uint32 length + bytes. Returns the string (its length is now known to fit).
    std::string string(const std::string& what)
    {
        uint32_t n = u32(what);
        if (n > uint64_t(left()))
            throw Failure(VBL_ERROR_CORRUPT_FILE, what + " length " + std::to_string(n) + " exceeds the " +
                                                      std::to_string(left()) + " bytes left in the file");
        std::string s(n, '\0');
        if (n) is.read(&s[0], n);
        return s;
    }
};

struct Rewind {
    std::istream& is;
    std::streamoff pos;
    explicit Rewind(std::istream& s) : is(s), pos(s.tellg()) {}
    ~Rewind()
    {
        is.clear();
        is.seekg(pos);
    }
};

// Checks the MetaMap at the cursor (MetaMap::readMeta's layout) and steps over it.
void skip_meta_map(Cursor& c, const std::string& what)
{
    const uint32_t count = c.u32(what + " metadata count");
    // Each entry needs at least its two 4-byte string lengths and its 4-byte value size.
    if (count > uint64_t(c.left()) / 12)
        throw Failure(VBL_ERROR_CORRUPT_FILE, what + " metadata count " + std::to_string(count) + " exceeds what the " +
                                                  std::to_string(c.left()) + " bytes left in the file can hold");
    for (uint32_t i = 0; i < count; ++i) {
        const std::string item = what + " metadata item " + std::to_string(i);
        c.string(item + " name");
        const std::string type = c.string(item + " type name");
        const uint32_t bytes = c.u32(item + " size");
        // MetaMap::readMeta: TypedMetadata<T> reads sizeof(T) whatever `bytes` says (a default
        // value's size() is that, > 0); strings, unknown types and variable-size ones
        // (__delayedload, size() 0 when empty) read `bytes`.
        uint64_t read = bytes;
        if (openvdb::Metadata::isRegisteredType(type)) {
            const uint64_t fixed = openvdb::Metadata::createMetadata(type)->size();
            if (fixed > 0) read = fixed;
        }
        c.skip(read, item + " value");
    }
}

} // namespace

void check_meta_map_sizes(std::istream& is, std::streamoff file_size, const std::string& what)
{
    Rewind rewind(is);
    Cursor c{is, file_size};
    skip_meta_map(c, what);
}

void check_descriptor_sizes(std::istream& is, std::streamoff file_size, uint32_t file_version, int32_t index)
{
    Rewind rewind(is);
    Cursor c{is, file_size};
    const std::string what = "grid descriptor " + std::to_string(index);
    c.string(what + " name");
    c.string(what + " type name");
    if (file_version >= openvdb::OPENVDB_FILE_VERSION_GRID_INSTANCING) c.string(what + " instance parent name");
    c.skip(3 * sizeof(int64_t), what + " offsets");
}

namespace {

// Bytes of one value of a standard tree type ("Tree_float_5_4_3" -> 4); 0 for other layouts.
uint64_t root_value_bytes(const std::string& tree_type)
{
    static const struct { const char* type; uint64_t bytes; } types[] = {
        {"Tree_float_5_4_3", 4}, {"Tree_double_5_4_3", 8}, {"Tree_int32_5_4_3", 4}, {"Tree_int64_5_4_3", 8},
        {"Tree_bool_5_4_3", 1},  {"Tree_vec3s_5_4_3", 12}, {"Tree_vec3d_5_4_3", 24}, {"Tree_vec3i_5_4_3", 12},
    };
    for (const auto& t : types)
        if (tree_type == t.type) return t.bytes;
    return 0;
}

// RootNode::readTopology reads uint32 tile and child counts and loops over them: each tile is
// (3 x int32 origin, value, bool), each child its origin then an upper node's child and value
// masks (2 x 4096 bytes for 5_4_3 trees) at least. With the stream at its end the loops go on
// reading nothing: 2^32 tiles took minutes, and 2^32 children allocated a 264 KB upper node each
// (one map slot, each overwriting and leaking the last). The counts must fit the grid's bytes.
void check_root_counts(Cursor& c, uint64_t value_bytes, std::streamoff grid_end, const std::string& what, uint64_t* tiles_out,
                       uint64_t* children_out)
{
    c.u32(what + " tree buffer count");
    c.skip(value_bytes, what + " background value");
    const uint64_t tiles = c.u32(what + " root tile count"), children = c.u32(what + " root child count");
    const std::streamoff pos = c.is.tellg();
    const uint64_t left = pos >= 0 && grid_end > pos ? uint64_t(grid_end - pos) : 0;
    const uint64_t needs = tiles * (12 + value_bytes + 1) + children * (12 + 2 * 4096);
    if (needs > left)
        throw Failure(VBL_ERROR_CORRUPT_FILE, what + " root tile count " + std::to_string(tiles) + " and child count " +
                                                  std::to_string(children) + " need at least " + std::to_string(needs) +
                                                  " bytes but the grid has " + std::to_string(left) + " bytes left");
    *tiles_out = tiles;
    *children_out = children;
}

} // namespace

void check_grid_header_sizes(std::istream& is, std::streamoff file_size, uint32_t file_version, const std::string& grid,
                             const std::string& tree_type, std::streamoff grid_end, uint32_t compression, bool half)
{
    Rewind rewind(is);
    Cursor c{is, file_size};
    const std::string what = "grid '" + grid + "'";
    skip_meta_map(c, what);
    if (file_version < openvdb::OPENVDB_FILE_VERSION_NEW_TRANSFORM) return;
    const std::string map_type = c.string(what + " transform map type");
    // The map's own fields have fixed sizes (Maps.h): read them with the map type's reader.
    const uint64_t value_bytes = root_value_bytes(tree_type);
    // Since format 221 the transform comes before the topology (io::Archive::readGrid).
    if (!value_bytes || file_version < openvdb::OPENVDB_FILE_VERSION_GRID_INSTANCING || !openvdb::math::MapRegistry::isRegistered(map_type)) return;
    openvdb::math::MapRegistry::createMap(map_type)->read(is);
    if (!is) throw Failure(VBL_ERROR_CORRUPT_FILE, "truncated file in " + what + " transform");
    const std::streamoff end = grid_end < file_size ? grid_end : file_size;
    uint64_t tiles = 0, children = 0;
    check_root_counts(c, value_bytes, end, what, &tiles, &children);
    // Float trees (the ones rendered) get the whole topology walked, in the format since 222.
    if (tree_type == "Tree_float_5_4_3" && file_version >= openvdb::OPENVDB_FILE_VERSION_NODE_MASK_COMPRESSION)
        check_float_topology(is, end, compression, half, tiles, children, what);
}

} // namespace vbl_vdb

#pragma GCC visibility pop
