// Internal C++ side of the OpenVDB/NanoVDB adapter: the grid list both readers produce, the
// failure type every reader throws, and the helpers shared by vdb_adapter.cc and the readers.
#ifndef VBL_VDB_INTERNAL_H
#define VBL_VDB_INTERNAL_H

#include <cstdint>
#include <istream>
#include <stdexcept>
#include <string>
#include <vector>

#include "vbl_vdb_adapter.h"

namespace vbl_vdb {

// A failure with its vbl_result; the message does not name the file (the C entry point adds it).
struct Failure : std::runtime_error {
    vbl_result code;
    Failure(vbl_result c, const std::string& what) : std::runtime_error(what), code(c) {}
};

// One grid of a file in file order, as both readers describe it.
struct GridEntry {
    vbl_vdb_grid_desc desc;    // name, type, is_float, codec (+ counts/bbox when `described`)
    bool described = false;    // active_voxels/index bbox/voxel size are filled in
    std::string open_name;     // OpenVDB: unique name for io::File::readGrid ("density[1]")
    std::size_t segment_entry = 0; // NanoVDB: entry in the file's segment metadata (file order)
    std::uint32_t sub_grid = 0;    // NanoVDB: grid inside that entry's buffer
    std::uint64_t mem_bytes = 0;   // OpenVDB: the tree's in-memory bytes as the file states them (file_mem_bytes), 0 if absent
};

enum class FileKind { OpenVdb, NanoVdb };

// Detects the file kind from its magic number; throws Failure (not found, not a VDB, too short).
FileKind sniff_file(const std::string& path);

// OpenVDB (.vdb): every grid in file order; `describe` reads the trees for counts and bboxes.
std::vector<GridEntry> openvdb_list(const std::string& path, bool describe);
// Reads entry `entry` (a float grid) and converts it to a NanoVDB buffer (vbl_aligned_alloc).
void openvdb_read_float(const std::string& path, const GridEntry& entry, void** buffer, std::size_t* size);

// Reads entry `entry` (a vec3s or vec3d grid) and converts component `component` to a NanoVDB
// float buffer (vdb_openvdb_read.cc).
void openvdb_read_vec3_component(const std::string& path, const GridEntry& entry, int component, void** buffer,
                                 std::size_t* size);
// The entry's type is a 3-vector of floats or doubles ("vec3s", "vec3d", "half vec3s").
bool is_vec3_type(const GridEntry& entry);

// Size pre-checks before OpenVDB reads (vdb_openvdb_sizes.cc): each reads ahead from the stream's
// position, throws Failure(VBL_ERROR_CORRUPT_FILE) naming the field when a stated length exceeds
// the bytes left in the file, and restores the position.
void check_meta_map_sizes(std::istream& is, std::streamoff file_size, const std::string& what);
void check_descriptor_sizes(std::istream& is, std::streamoff file_size, uint32_t file_version, int32_t index);
// The grid's metadata, transform type name and (standard trees) root tile/child counts, at the
// position after its compression flags; `tree_type` is the descriptor's ("Tree_float_5_4_3"),
// `grid_end` where the grid's bytes end.
void check_grid_header_sizes(std::istream& is, std::streamoff file_size, uint32_t file_version, const std::string& grid,
                             const std::string& tree_type, std::streamoff grid_end, uint32_t compression, bool half);

// Walks a float tree's topology (vdb_openvdb_topology.cc) from its first root tile to its last
// leaf mask, decoding the internal nodes' compressed values; throws Failure(VBL_ERROR_CORRUPT_FILE)
// on what would make OpenVDB's readTopology throw (and leak) or on repeated root child origins.
void check_float_topology(std::istream& is, std::streamoff grid_end, uint32_t compression, bool half, uint64_t tiles,
                          uint64_t children, const std::string& what);

// NanoVDB (.nvdb): every grid in file order (multi-grid buffers expanded); reads the buffers.
std::vector<GridEntry> nanovdb_list(const std::string& path);
void nanovdb_read_float(const std::string& path, const GridEntry& entry, void** buffer, std::size_t* size);

// Checks that `size` bytes at `data` (32-byte aligned) hold one well-formed NanoVDB float grid whose
// nodes are stored level by level (the layout the core's scans rely on). Throws Failure.
void validate_nanovdb_float_grid(const void* data, std::uint64_t size);

// Throws Failure(VBL_ERROR_UNSUPPORTED) naming `what` when `bytes` exceed vbl_memory_limit().
void check_memory_limit(std::uint64_t bytes, const std::string& what);

// Copies `size` bytes into a new 32-byte aligned buffer (throws Failure on out of memory).
void* copy_aligned(const void* data, std::size_t size);

// `text` with every byte outside printable ASCII written as \xNN and at most `keep` bytes kept
// (names read from a file go into messages this way, never raw).
std::string printable(const std::string& text, std::size_t keep = 80);

void set_string(char* dst, std::size_t capacity, const std::string& src);

} // namespace vbl_vdb

#endif
