// NanoVDB (.nvdb) reader: walks the file's segments (nanovdb::io), expands buffers that hold several
// grids (GridData::mGridCount / mGridSize, as written by NanoVDB >= 32.5), validates the layout of the
// chosen float grid and hands a private 32-byte aligned copy of it to the core.
#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <fstream>

#include <nanovdb/NanoVDB.h>
#include <nanovdb/util/GridChecksum.h>
#include <nanovdb/util/IO.h>

#include "core/alloc.h"
#include "vdb_aligned_buffer.h"
#include "vdb_internal.h"

#pragma GCC visibility push(hidden) // internal to libvbl (see vdb/CMakeLists.txt)

namespace vbl_vdb {
namespace {

using Leaf = nanovdb::NanoLeaf<float>;
using Lower = nanovdb::NanoLower<float>;
using Upper = nanovdb::NanoUpper<float>;
using Root = nanovdb::NanoRoot<float>;
using RootTile = Root::DataType::Tile;
using TreeData = nanovdb::TreeData<3>;

std::string version_string(const nanovdb::Version& v)
{
    return std::to_string(v.getMajor()) + "." + std::to_string(v.getMinor()) + "." + std::to_string(v.getPatch());
}

void check_version(const nanovdb::Version& v, const char* what)
{
    if (v.getMajor() != NANOVDB_MAJOR_VERSION_NUMBER)
        throw Failure(VBL_ERROR_UNSUPPORTED, std::string(what) + " has NanoVDB version " + version_string(v) +
                                                 ", this build reads " + std::to_string(NANOVDB_MAJOR_VERSION_NUMBER) +
                                                 ".x (the major version changes the memory layout)");
}

// Compressed grids larger than this many times their bytes in the file are refused (zlib's deflate
// cannot exceed 1032:1; blosc on NanoVDB nodes stays far below), unless under the floor below.
constexpr uint64_t kMaxExpansion = 1032;
constexpr uint64_t kExpansionFloor = uint64_t(64) << 20; // 64 MiB: tiny tile-only grids compress further

std::string entry_name(std::size_t entry) { return "NanoVDB grid entry " + std::to_string(entry); }

// Checks the segment at `pos` before nanovdb::io reads it: nanovdb::io::GridMetaData::read allocates
// `nameSize` bytes from the file and runs strlen on them (a 156-byte file with an unterminated name
// overread the heap), and Internal::read allocates the grid size and each compressed chunk size it
// reads. Every size is checked against the bytes the file has, the name for its terminating NUL,
// the grid size against its codec, the chunk sizes against the grid's bytes in the file.
void check_segment_sizes(std::istream& is, std::streamoff pos, std::streamoff file_size, std::size_t first_entry)
{
    nanovdb::io::Header header;
    is.seekg(pos);
    is.read(reinterpret_cast<char*>(&header), sizeof header);
    if (!is) throw Failure(VBL_ERROR_CORRUPT_FILE, "truncated NanoVDB segment header");
    std::vector<nanovdb::io::MetaData> metas(header.gridCount);
    for (uint16_t g = 0; g < header.gridCount; ++g) {
        const std::string what = entry_name(first_entry + g);
        nanovdb::io::MetaData& m = metas[g];
        std::streamoff at = is.tellg();
        if (at < 0 || file_size - at < std::streamoff(sizeof m)) throw Failure(VBL_ERROR_CORRUPT_FILE, "truncated NanoVDB metadata of " + what);
        is.read(reinterpret_cast<char*>(&m), sizeof m);
        at += std::streamoff(sizeof m);
        if (m.nameSize == 0 || m.nameSize > uint64_t(file_size - at))
            throw Failure(VBL_ERROR_CORRUPT_FILE, what + ": name size " + std::to_string(m.nameSize) + " exceeds the " +
                                                      std::to_string(file_size - at) + " bytes left in the file");
        std::string name(m.nameSize, '\0');
        is.read(&name[0], std::streamsize(m.nameSize));
        if (!is || name.back() != '\0') throw Failure(VBL_ERROR_CORRUPT_FILE, what + ": grid name is not NUL-terminated");
        if (m.gridSize < sizeof(nanovdb::GridData) || m.fileSize == 0 || m.fileSize > uint64_t(file_size))
            throw Failure(VBL_ERROR_CORRUPT_FILE, what + ": bad grid size " + std::to_string(m.gridSize) + " / file size " +
                                                      std::to_string(m.fileSize) + " in the metadata");
        const bool raw = header.codec != nanovdb::io::Codec::ZIP && header.codec != nanovdb::io::Codec::BLOSC;
        const uint64_t most = raw ? m.fileSize : std::max(kExpansionFloor, m.fileSize * kMaxExpansion);
        if (m.gridSize > most)
            throw Failure(VBL_ERROR_CORRUPT_FILE, what + ": grid size " + std::to_string(m.gridSize) + " bytes cannot come from its " +
                                                      std::to_string(m.fileSize) + " bytes in the file (codec " +
                                                      nanovdb::io::toStr(header.codec) + ")");
        check_memory_limit(m.gridSize, what + " (" + std::to_string(m.gridSize) + " bytes)");
    }
    // The grids' data follow the metadata in order; compressed ones are (int64 size, bytes) chunks:
    // one for ZIP, one per started GB for BLOSC (nanovdb::io::Internal::write).
    std::streamoff data = is.tellg();
    for (uint16_t g = 0; g < header.gridCount; ++g) {
        const nanovdb::io::MetaData& m = metas[g];
        if (data < 0 || m.fileSize > uint64_t(file_size - data)) break; // the caller reports the truncation
        if (header.codec == nanovdb::io::Codec::ZIP || header.codec == nanovdb::io::Codec::BLOSC) {
            const uint64_t chunks = header.codec == nanovdb::io::Codec::ZIP ? 1 : (m.gridSize + (uint64_t(1) << 30) - 1) >> 30;
            uint64_t used = 0;
            is.seekg(data);
            for (uint64_t c = 0; c < chunks; ++c) {
                uint64_t size = 0;
                if (m.fileSize - used < sizeof size) throw Failure(VBL_ERROR_CORRUPT_FILE, entry_name(first_entry + g) + ": truncated compressed chunk");
                is.read(reinterpret_cast<char*>(&size), sizeof size);
                used += sizeof size;
                if (!is || size > m.fileSize - used)
                    throw Failure(VBL_ERROR_CORRUPT_FILE, entry_name(first_entry + g) + ": compressed chunk of " + std::to_string(size) +
                                                              " bytes exceeds the grid's " + std::to_string(m.fileSize) + " bytes in the file");
                used += size;
                is.seekg(std::streamoff(size), std::ios::cur);
            }
        }
        data += std::streamoff(m.fileSize);
    }
    is.clear();
}

// The segment entries of the file in order; checks headers and that the file holds every grid's bytes.
std::vector<nanovdb::io::GridMetaData> read_segments(const std::string& path)
{
    std::ifstream is(path, std::ios::in | std::ios::binary | std::ios::ate);
    if (!is) throw Failure(VBL_ERROR_FILE_NOT_FOUND, "cannot open");
    const std::streamoff file_size = is.tellg();
    is.seekg(0);
    std::vector<nanovdb::io::GridMetaData> entries;
    std::streamoff pos = 0;
    while (pos < file_size) {
        nanovdb::io::Header header;
        if (file_size - pos < std::streamoff(sizeof header)) throw Failure(VBL_ERROR_CORRUPT_FILE, "truncated NanoVDB segment header");
        is.read(reinterpret_cast<char*>(&header), sizeof header);
        if (header.magic != NANOVDB_MAGIC_NUMBER) throw Failure(VBL_ERROR_CORRUPT_FILE, "bad NanoVDB segment magic number");
        check_version(header.version, "the file");
        check_segment_sizes(is, pos, file_size, entries.size());
        is.seekg(pos);
        nanovdb::io::Segment segment;
        if (!segment.read(is)) break;
        std::streamoff data = 0;
        for (const auto& meta : segment.meta) {
            data += std::streamoff(meta.fileSize);
            entries.push_back(meta);
        }
        pos = is.tellg();
        if (pos < 0 || data < 0 || pos + data > file_size)
            throw Failure(VBL_ERROR_CORRUPT_FILE, "truncated NanoVDB file (a grid needs " + std::to_string(data) +
                                                      " bytes past offset " + std::to_string(pos) + ", the file has " +
                                                      std::to_string(file_size) + ")");
        pos += data;
        is.seekg(pos);
    }
    if (entries.empty()) throw Failure(VBL_ERROR_CORRUPT_FILE, "NanoVDB file without grids");
    return entries;
}

const nanovdb::GridData* grid_at(const uint8_t* base, uint64_t size, uint64_t offset)
{
    if (offset + sizeof(nanovdb::GridData) > size) throw Failure(VBL_ERROR_CORRUPT_FILE, "NanoVDB buffer shorter than its grids");
    auto* grid = reinterpret_cast<const nanovdb::GridData*>(base + offset);
    if (grid->mMagic != NANOVDB_MAGIC_NUMBER) throw Failure(VBL_ERROR_CORRUPT_FILE, "bad NanoVDB grid magic number");
    check_version(grid->mVersion, "a grid");
    if (grid->mGridSize < sizeof(nanovdb::GridData) || grid->mGridSize > size - offset || grid->mGridSize % NANOVDB_DATA_ALIGNMENT)
        throw Failure(VBL_ERROR_CORRUPT_FILE, "bad NanoVDB grid size");
    return grid;
}

std::string grid_type_name(nanovdb::GridType type)
{
    return type < nanovdb::GridType::End ? nanovdb::toStr(type) : "unknown";
}

// Walks the grids of one decoded segment entry (one or, since 32.5, several per buffer).
template<typename F>
void for_each_grid(const nanovdb::GridHandle<AlignedBuffer>& handle, F&& f)
{
    const uint8_t* base = handle.data();
    const uint64_t size = handle.size();
    if (!base) throw Failure(VBL_ERROR_CORRUPT_FILE, "empty NanoVDB grid buffer");
    const nanovdb::GridData* first = grid_at(base, size, 0);
    const uint32_t count = first->mGridCount ? first->mGridCount : 1;
    uint64_t offset = 0;
    for (uint32_t i = 0; i < count; ++i) {
        const nanovdb::GridData* grid = grid_at(base, size, offset);
        f(i, grid, offset);
        offset += grid->mGridSize;
    }
}

nanovdb::GridHandle<AlignedBuffer> read_entry(const std::string& path, std::size_t entry)
{
    return nanovdb::io::readGrid<AlignedBuffer>(path, entry);
}

} // namespace

std::vector<GridEntry> nanovdb_list(const std::string& path)
{
    std::vector<nanovdb::io::GridMetaData> metas = read_segments(path);
    std::vector<GridEntry> entries;
    for (std::size_t n = 0; n < metas.size(); ++n) {
        auto handle = read_entry(path, n);
        for_each_grid(handle, [&](uint32_t i, const nanovdb::GridData* grid, uint64_t offset) {
            GridEntry e;
            std::memset(&e.desc, 0, sizeof e.desc);
            e.segment_entry = n;
            e.sub_grid = i;
            std::string name(grid->mGridName, strnlen(grid->mGridName, nanovdb::GridData::MaxNameSize));
            set_string(e.desc.name, sizeof e.desc.name, name);
            set_string(e.desc.type, sizeof e.desc.type, grid_type_name(grid->mGridType));
            e.desc.is_float = grid->mGridType == nanovdb::GridType::Float;
            set_string(e.desc.codec, sizeof e.desc.codec, std::string("nanovdb ") + nanovdb::io::toStr(metas[n].codec));
            for (int a = 0; a < 3; ++a) e.desc.voxel_size[a] = grid->mVoxelSize[a];
            if (e.desc.is_float) {
                validate_nanovdb_float_grid(handle.data() + offset, grid->mGridSize);
                auto* nano = reinterpret_cast<const nanovdb::NanoGrid<float>*>(grid);
                e.desc.active_voxels = nano->activeVoxelCount();
                const nanovdb::CoordBBox& bbox = nano->tree().root().bbox();
                for (int a = 0; a < 3; ++a) {
                    e.desc.index_bbox_min[a] = e.desc.active_voxels ? bbox.min()[a] : 0;
                    e.desc.index_bbox_max[a] = e.desc.active_voxels ? bbox.max()[a] : -1;
                }
                e.described = true;
            }
            entries.push_back(e);
        });
    }
    return entries;
}

void nanovdb_read_float(const std::string& path, const GridEntry& entry, void** buffer, std::size_t* size)
{
    auto handle = read_entry(path, entry.segment_entry);
    for_each_grid(handle, [&](uint32_t i, const nanovdb::GridData* grid, uint64_t offset) {
        if (i != entry.sub_grid) return;
        if (grid->mGridType != nanovdb::GridType::Float)
            throw Failure(VBL_ERROR_GRID_TYPE, "grid '" + std::string(entry.desc.name) + "' is " + grid_type_name(grid->mGridType) + ", not a float grid");
        // The only grid of its buffer (the usual case) is handed over as it is; a grid of a
        // multi-grid buffer is copied out (the buffer is freed on return).
        const bool whole = offset == 0 && grid->mGridCount <= 1 && grid->mGridSize == handle.size();
        void* copy = whole ? handle.buffer().release() : copy_aligned(handle.data() + offset, grid->mGridSize);
        try {
            validate_nanovdb_float_grid(copy, grid->mGridSize);
            auto* data = static_cast<nanovdb::GridData*>(copy);
            // The checksum algorithm is tied to the exact version; a newer minor version (same
            // layout) is loaded without checking it.
            if (data->mVersion == nanovdb::Version() &&
                !nanovdb::validateChecksum(*reinterpret_cast<const nanovdb::NanoGrid<float>*>(copy), nanovdb::ChecksumMode::Full))
                throw Failure(VBL_ERROR_CORRUPT_FILE, "grid '" + std::string(entry.desc.name) + "' fails its NanoVDB checksum");
            data->mGridIndex = 0; // the copy is a buffer of its own
            data->mGridCount = 1;
        } catch (...) {
            vbl_aligned_free(copy);
            throw;
        }
        *buffer = copy;
        *size = grid->mGridSize;
    });
    if (!*buffer) throw Failure(VBL_ERROR_GRID_NOT_FOUND, "grid vanished while reading");
}

void validate_nanovdb_float_grid(const void* data, uint64_t size)
{
    const auto* base = static_cast<const uint8_t*>(data);
    auto bad = [](const std::string& what) { return Failure(VBL_ERROR_CORRUPT_FILE, "malformed NanoVDB grid: " + what); };
    if (reinterpret_cast<uintptr_t>(base) % NANOVDB_DATA_ALIGNMENT) throw bad("buffer not 32-byte aligned");
    const nanovdb::GridData* grid = grid_at(base, size, 0);
    if (grid->mGridType != nanovdb::GridType::Float) throw Failure(VBL_ERROR_GRID_TYPE, "not a float grid");
    const uint64_t gsize = grid->mGridSize;
    const uint64_t tree_off = sizeof(nanovdb::GridData);
    if (tree_off + sizeof(TreeData) > gsize) throw bad("no tree");
    const auto* tree = reinterpret_cast<const TreeData*>(base + tree_off);
    struct Level { uint64_t begin, count, stride; };
    const uint64_t strides[3] = {sizeof(Leaf), sizeof(Lower), sizeof(Upper)};
    Level level[3];
    for (int l = 0; l < 3; ++l) {
        level[l] = {tree_off + tree->mNodeOffset[l], tree->mNodeCount[l], strides[l]};
        if (level[l].count == 0) continue;
        // The bound is on the array's start in the buffer (tree offset included): with only the
        // node offset checked, gsize - begin could wrap and any count pass.
        if (tree->mNodeOffset[l] > gsize || level[l].begin > gsize || level[l].begin % NANOVDB_DATA_ALIGNMENT ||
            level[l].count > (gsize - level[l].begin) / level[l].stride)
            throw bad("node array " + std::to_string(l) + " outside the buffer");
    }
    const uint64_t root_off = tree_off + tree->mNodeOffset[3];
    if (tree->mNodeOffset[3] > gsize || root_off % NANOVDB_DATA_ALIGNMENT || root_off + sizeof(Root) > gsize) throw bad("root outside the buffer");
    const auto* root = reinterpret_cast<const Root::DataType*>(base + root_off);
    if (root->mTableSize > (gsize - root_off - sizeof(Root)) / sizeof(RootTile)) throw bad("root tile table outside the buffer");
    uint64_t references[3] = {0, 0, 0};
    auto check_child = [&](uint64_t parent, int64_t offset, int l) {
        const uint64_t child = parent + uint64_t(offset);
        const Level& lv = level[l];
        if (child < lv.begin || child >= lv.begin + lv.count * lv.stride || (child - lv.begin) % lv.stride)
            throw bad("child pointer outside the level-" + std::to_string(l) + " node array");
        ++references[l];
    };
    for (uint32_t t = 0; t < root->mTableSize; ++t) {
        const RootTile* tile = reinterpret_cast<const RootTile*>(base + root_off + sizeof(Root)) + t;
        if (tile->child) check_child(root_off, tile->child, 2);
    }
    for (uint64_t n = 0; n < level[2].count; ++n) {
        const uint64_t node = level[2].begin + n * level[2].stride;
        const auto* d = reinterpret_cast<const Upper::DataType*>(base + node);
        for (auto it = d->mChildMask.beginOn(); it; ++it) check_child(node, d->mTable[*it].child, 1);
    }
    for (uint64_t n = 0; n < level[1].count; ++n) {
        const uint64_t node = level[1].begin + n * level[1].stride;
        const auto* d = reinterpret_cast<const Lower::DataType*>(base + node);
        for (auto it = d->mChildMask.beginOn(); it; ++it) check_child(node, d->mTable[*it].child, 0);
    }
    for (int l = 0; l < 3; ++l)
        if (references[l] != level[l].count) throw bad("level-" + std::to_string(l) + " nodes not referenced exactly once");
}

} // namespace vbl_vdb

#pragma GCC visibility pop
