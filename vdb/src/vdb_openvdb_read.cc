// OpenVDB (.vdb) reader: lists grids in file order (any file format version, half-float storage,
// blosc/zip/active-mask codecs) and converts float grids to NanoVDB with nanovdb::openToNanoVDB.
#include <cstring>
#include <fstream>
#include <mutex>

#include <openvdb/openvdb.h>
#include <openvdb/io/Archive.h>
#include <openvdb/io/Compression.h>
#include <openvdb/io/File.h>
#include <openvdb/io/GridDescriptor.h>
#include <nanovdb/util/OpenToNanoVDB.h>

#include "core/alloc.h"
#include "vdb_aligned_buffer.h"
#include "vdb_internal.h"

#pragma GCC visibility push(hidden) // internal to libvbl (see vdb/CMakeLists.txt)

namespace vbl_vdb {
namespace {

void initialize_openvdb()
{
    // Once per process, from whichever thread loads first (openvdb::initialize is itself guarded too).
    static std::once_flag once;
    std::call_once(once, [] { openvdb::initialize(); });
}

// Reads the grid descriptors in file order (io::File keeps them in a name-sorted map). This follows
// the file layout io::File::open reads: header, file metadata, grid count, then one descriptor per
// grid with the offsets of its data.
class DescriptorScanner : public openvdb::io::Archive {
public:
    struct Item {
        std::string unique_name, grid_type;
        bool half = false;
        uint32_t compression = 0;
        bool compression_known = false;
    };
    std::streamoff file_bytes = 0; // set by scan()
    std::vector<Item> scan(const std::string& path)
    {
        std::ifstream is(path, std::ios::in | std::ios::binary | std::ios::ate);
        if (!is) throw Failure(VBL_ERROR_FILE_NOT_FOUND, "cannot open");
        const std::streamoff file_size = is.tellg();
        is.seekg(0);
        readHeader(is);
        setFormatVersion(is);
        setLibraryVersion(is);
        setDataCompression(is);
        file_bytes = file_size;
        check_meta_map_sizes(is, file_size, "file");
        openvdb::MetaMap file_meta;
        file_meta.readMeta(is);
        std::vector<Item> items;
        if (!inputHasGridOffsets()) return items; // pre-2.0 files: caller falls back to io::File order
        const int32_t count = readGridCount(is);
        if (count < 0 || !is) throw Failure(VBL_ERROR_CORRUPT_FILE, "bad grid count");
        for (int32_t i = 0; i < count; ++i) {
            check_descriptor_sizes(is, file_size, fileVersion(), i);
            openvdb::io::GridDescriptor gd;
            gd.read(is);
            Item item;
            item.unique_name = gd.uniqueName();
            item.grid_type = gd.gridType();
            item.half = gd.saveFloatAsHalf();
            const std::string name = printable(openvdb::io::GridDescriptor::nameAsString(item.unique_name));
            // A truncated file is caught here, before OpenVDB reads the tree: OpenVDB 10 leaks the node
            // it was reading when a tree read throws.
            if (gd.getGridPos() < 0 || gd.getEndPos() < gd.getGridPos() || gd.getEndPos() > file_size)
                throw Failure(VBL_ERROR_CORRUPT_FILE, "truncated file: grid '" + name + "' spans bytes " +
                                                          std::to_string(gd.getGridPos()) + " to " + std::to_string(gd.getEndPos()) +
                                                          " but the file has " + std::to_string(file_size) + " bytes");
            if (!gd.isInstance()) {
                // Since format 222 each grid starts with its own compression flags.
                gd.seekToGrid(is);
                if (fileVersion() >= openvdb::OPENVDB_FILE_VERSION_NODE_MASK_COMPRESSION) {
                    uint32_t flags = 0;
                    if (is.read(reinterpret_cast<char*>(&flags), sizeof flags)) {
                        item.compression = flags;
                        item.compression_known = true;
                    }
                }
                if (is) check_grid_header_sizes(is, file_size, fileVersion(), name, item.grid_type, gd.getEndPos(),
                                                     item.compression_known ? item.compression : compression(), item.half);
                is.clear();
            }
            if (!item.compression_known) {
                item.compression = compression();
                item.compression_known = true;
            }
            items.push_back(item);
            gd.seekToEnd(is);
            if (!is) throw Failure(VBL_ERROR_CORRUPT_FILE, "truncated grid descriptor table");
        }
        return items;
    }
};

std::string type_name(const openvdb::GridBase& grid, bool half)
{
    std::string t = grid.valueType();
    if (half && (t == "float" || t == "vec3s")) t = "half " + t;
    return t;
}

std::string codec_name(uint32_t flags, bool known)
{
    if (!known) return "unknown";
    std::string s;
    if (flags & openvdb::io::COMPRESS_BLOSC) s = "blosc";
    else if (flags & openvdb::io::COMPRESS_ZIP) s = "zip";
    if (flags & openvdb::io::COMPRESS_ACTIVE_MASK) s += s.empty() ? "active mask" : " + active mask";
    return s.empty() ? "none" : s;
}

void describe_tree(const openvdb::GridBase& grid, vbl_vdb_grid_desc& desc)
{
    desc.active_voxels = grid.activeVoxelCount();
    openvdb::CoordBBox bbox = grid.evalActiveVoxelBoundingBox();
    if (desc.active_voxels == 0) bbox = openvdb::CoordBBox(openvdb::Coord(0), openvdb::Coord(-1));
    for (int a = 0; a < 3; ++a) {
        desc.index_bbox_min[a] = bbox.min()[a];
        desc.index_bbox_max[a] = bbox.max()[a];
    }
}

// Reads a grid through OpenVDB. OpenVDB allocates the compressed chunk sizes it reads from the file
// (io::bloscFromStream / zipFromStream: new char[int64 from the file]) before reading them: a size
// no machine can grant (0x4000000040004 bytes in a fuzzed blosc chunk) is a corrupt file, exit 3.
template<typename F>
auto read_guarded(const std::string& name, std::streamoff file_size, F&& read) -> decltype(read())
{
    try {
        return read();
    } catch (const std::bad_alloc&) {
        throw Failure(VBL_ERROR_CORRUPT_FILE, "grid '" + printable(name) + "': a size field asks for more memory than this machine grants "
                                              "(the file has " + std::to_string(file_size) + " bytes): corrupt file");
    }
}

} // namespace

std::vector<GridEntry> openvdb_list(const std::string& path, bool describe)
{
    initialize_openvdb();
    DescriptorScanner scanner;
    std::vector<DescriptorScanner::Item> order = scanner.scan(path);
    const std::streamoff file_size = scanner.file_bytes;
    openvdb::io::File file(path);
    file.open(false); // no delayed loading: read now, so damaged files fail here, not later
    if (order.empty()) { // no grid offsets (very old files): io::File's order
        for (auto it = file.beginName(); it != file.endName(); ++it) {
            DescriptorScanner::Item item;
            item.unique_name = openvdb::io::GridDescriptor::stringAsUniqueName(it.gridName());
            item.compression = file.compression();
            item.compression_known = true;
            order.push_back(item);
        }
    }
    std::vector<GridEntry> entries;
    for (const auto& item : order) {
        GridEntry e;
        std::memset(&e.desc, 0, sizeof e.desc);
        e.open_name = openvdb::io::GridDescriptor::nameAsString(item.unique_name);
        openvdb::GridBase::Ptr grid = read_guarded(e.open_name, file_size, [&] {
            return describe ? file.readGrid(e.open_name) : file.readGridMetadata(e.open_name);
        });
        const bool half = item.half || grid->saveFloatAsHalf();
        set_string(e.desc.name, sizeof e.desc.name, grid->getName());
        set_string(e.desc.type, sizeof e.desc.type, type_name(*grid, half));
        e.desc.is_float = grid->isType<openvdb::FloatGrid>();
        set_string(e.desc.codec, sizeof e.desc.codec, codec_name(item.compression, item.compression_known));
        if (auto mem = grid->getMetadata<openvdb::Int64Metadata>(openvdb::GridBase::META_FILE_MEM_BYTES))
            e.mem_bytes = mem->value() > 0 ? uint64_t(mem->value()) : 0;
        openvdb::Vec3d voxel = grid->voxelSize();
        for (int a = 0; a < 3; ++a) e.desc.voxel_size[a] = voxel[a];
        if (describe) {
            describe_tree(*grid, e.desc);
            e.described = true;
        }
        entries.push_back(e);
    }
    return entries;
}

void openvdb_read_float(const std::string& path, const GridEntry& entry, void** buffer, std::size_t* size)
{
    initialize_openvdb();
    openvdb::io::File file(path);
    file.open(false);
    std::ifstream probe(path, std::ios::in | std::ios::binary | std::ios::ate);
    const std::streamoff file_size = probe ? std::streamoff(probe.tellg()) : 0;
    // The tree and its NanoVDB copy (about the tree's size) are in memory together while converting.
    if (entry.mem_bytes)
        check_memory_limit(2 * entry.mem_bytes, "grid '" + printable(entry.desc.name) + "' (its tree of " + std::to_string(entry.mem_bytes) +
                                                    " bytes in file_mem_bytes, and its NanoVDB copy)");
    openvdb::FloatGrid::Ptr grid =
        openvdb::gridPtrCast<openvdb::FloatGrid>(read_guarded(entry.open_name, file_size, [&] { return file.readGrid(entry.open_name); }));
    if (!grid) throw Failure(VBL_ERROR_GRID_TYPE, "grid '" + std::string(entry.desc.name) + "' is not a float grid");
    if (!grid->transform().baseMap()->isLinear())
        throw Failure(VBL_ERROR_UNSUPPORTED, "grid '" + std::string(entry.desc.name) + "' has a non-affine (" +
                                                 grid->transform().baseMap()->type() + ") transform");
    nanovdb::GridHandle<AlignedBuffer> handle = nanovdb::openToNanoVDB<AlignedBuffer, openvdb::FloatTree>(*grid);
    if (!handle.data() || handle.size() == 0) throw Failure(VBL_ERROR_INTERNAL, "NanoVDB conversion produced no grid");
    *size = handle.size();
    *buffer = handle.buffer().release();
}

bool is_vec3_type(const GridEntry& entry)
{
    std::string t = entry.desc.type;
    if (t.rfind("half ", 0) == 0) t = t.substr(5);
    return t == "vec3s" || t == "vec3d" || t == "Vec3f" || t == "Vec3d";
}

namespace {

// One component of a vector grid as a float grid of the same topology: the float tree is a
// topology copy (same leaves and tiles, same active states), then both trees are walked in
// lockstep over every stored value (leaf voxels, tiles at every level), which visit identical
// positions in identical order because the topologies are equal.
template<typename VecGridT>
openvdb::FloatGrid::Ptr component_grid(const VecGridT& vec, int component)
{
    using VecT = typename VecGridT::ValueType;
    const VecT bg = vec.background();
    auto out = openvdb::FloatGrid::create(float(bg[component]));
    out->setTransform(vec.transform().copy());
    out->setName(vec.getName() + (component == 0 ? ".x" : component == 1 ? ".y" : ".z"));
    out->setTree(std::make_shared<openvdb::FloatTree>(vec.tree(), float(bg[component]), openvdb::TopologyCopy()));
    auto src = vec.tree().cbeginValueAll();
    auto dst = out->tree().beginValueAll();
    for (; src && dst; ++src, ++dst) {
        if (src.getCoord() != dst.getCoord() || src.getDepth() != dst.getDepth())
            throw Failure(VBL_ERROR_INTERNAL, "vector grid '" + printable(vec.getName()) + "': topology copy out of step");
        dst.setValue(float((*src)[component]));
    }
    if (bool(src) != bool(dst))
        throw Failure(VBL_ERROR_INTERNAL, "vector grid '" + printable(vec.getName()) + "': topology copy sizes differ");
    return out;
}

} // namespace

void openvdb_read_vec3_component(const std::string& path, const GridEntry& entry, int component, void** buffer,
                                 std::size_t* size)
{
    initialize_openvdb();
    openvdb::io::File file(path);
    file.open(false);
    std::ifstream probe(path, std::ios::in | std::ios::binary | std::ios::ate);
    const std::streamoff file_size = probe ? std::streamoff(probe.tellg()) : 0;
    openvdb::GridBase::Ptr base = read_guarded(entry.open_name, file_size, [&] { return file.readGrid(entry.open_name); });
    if (!base->transform().baseMap()->isLinear())
        throw Failure(VBL_ERROR_UNSUPPORTED, "grid '" + std::string(entry.desc.name) + "' has a non-affine (" +
                                                 base->transform().baseMap()->type() + ") transform");
    openvdb::FloatGrid::Ptr grid;
    if (auto vs = openvdb::gridPtrCast<openvdb::Vec3SGrid>(base)) grid = component_grid(*vs, component);
    else if (auto vd = openvdb::gridPtrCast<openvdb::Vec3DGrid>(base)) grid = component_grid(*vd, component);
    else throw Failure(VBL_ERROR_GRID_TYPE, "grid '" + std::string(entry.desc.name) + "' is not a vec3s/vec3d grid");
    nanovdb::GridHandle<AlignedBuffer> handle = nanovdb::openToNanoVDB<AlignedBuffer, openvdb::FloatTree>(*grid);
    if (!handle.data() || handle.size() == 0) throw Failure(VBL_ERROR_INTERNAL, "NanoVDB conversion produced no grid");
    *size = handle.size();
    *buffer = handle.buffer().release();
}

} // namespace vbl_vdb

#pragma GCC visibility pop
