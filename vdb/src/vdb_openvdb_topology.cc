// Pre-parse of a float tree's topology (Tree_float_5_4_3) before OpenVDB reads it. OpenVDB 10's
// RootNode/InternalNode::readTopology allocate each child node before reading it and do not free
// it when the read throws (a corrupt compressed value chunk: 0.3-1.3 MB leaked per failed load,
// issue 18), and a root child whose origin repeats an earlier one overwrites and leaks it. This
// walk reads the same bytes in the same order (RootNode.h, InternalNode.h, LeafNode.h and
// io::readCompressedValues in Compression.h), decodes every compressed chunk of the internal
// nodes' values into a scratch buffer with OpenVDB's own io::bloscFromStream/unzipFromStream, and
// throws Failure(VBL_ERROR_CORRUPT_FILE) naming the node on anything OpenVDB would fail on, so the
// real read then cannot throw inside the topology. Leaf buffers (read after the topology, into a
// tree the grid already owns) are not walked.
#include <cstdint>
#include <istream>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include <openvdb/openvdb.h>
#include <openvdb/io/Compression.h>

#include "vdb_internal.h"

#pragma GCC visibility push(hidden) // internal to libvbl (see vdb/CMakeLists.txt)

namespace vbl_vdb {
namespace {

struct Walk {
    std::istream& is;
    std::streamoff end;
    uint32_t compression;
    bool half;
    std::string what;
    std::vector<char> scratch;

    [[noreturn]] void fail(const std::string& why) const { throw Failure(VBL_ERROR_CORRUPT_FILE, what + " topology: " + why); }
    uint64_t left() const
    {
        const std::streamoff pos = is.tellg();
        return pos >= 0 && pos <= end ? uint64_t(end - pos) : 0;
    }
    void read(void* dst, uint64_t n, const char* field)
    {
        if (n > left()) fail(std::string(field) + " past the grid's end");
        is.read(static_cast<char*>(dst), std::streamsize(n));
        if (!is) fail(std::string(field) + " truncated");
    }
    void skip(uint64_t n, const char* field)
    {
        if (n > left()) fail(std::string(field) + " past the grid's end");
        is.seekg(std::streamoff(n), std::ios::cur);
    }

    // io::readData / HalfReader: `bytes` of values, raw or as one (int64 size, data) chunk.
    void values(uint64_t bytes, const std::string& node)
    {
        if (!(compression & (openvdb::io::COMPRESS_BLOSC | openvdb::io::COMPRESS_ZIP))) return skip(bytes, "values");
        int64_t stored = 0;
        const std::streamoff at = is.tellg();
        read(&stored, sizeof stored, "compressed size");
        const uint64_t magnitude = stored < 0 ? uint64_t(0) - uint64_t(stored) : uint64_t(stored);
        if (magnitude > left())
            fail(node + ": compressed chunk of " + std::to_string(stored) + " bytes exceeds the " + std::to_string(left()) +
                 " bytes left in the grid");
        if (stored <= 0 && magnitude != bytes)
            fail(node + ": uncompressed chunk of " + std::to_string(magnitude) + " bytes, expected " + std::to_string(bytes));
        is.seekg(at);
        scratch.resize(bytes ? bytes : 1);
        try {
            if (compression & openvdb::io::COMPRESS_BLOSC) openvdb::io::bloscFromStream(is, scratch.data(), bytes);
            else openvdb::io::unzipFromStream(is, scratch.data(), bytes);
        } catch (const std::exception& e) {
            fail(node + ": " + printable(e.what(), 160));
        }
        if (!is) fail(node + ": compressed chunk truncated");
    }

    // io::readCompressedValues for `count` values under `value_mask` (count bits).
    void compressed_values(uint32_t count, const std::vector<uint64_t>& value_mask, const std::string& node)
    {
        int8_t metadata = openvdb::io::NO_MASK_AND_ALL_VALS;
        read(&metadata, 1, "value metadata");
        using namespace openvdb::io;
        if (metadata == NO_MASK_AND_ONE_INACTIVE_VAL || metadata == MASK_AND_ONE_INACTIVE_VAL || metadata == MASK_AND_TWO_INACTIVE_VALS)
            skip(metadata == MASK_AND_TWO_INACTIVE_VALS ? 8 : 4, "inactive values");
        if (metadata == MASK_AND_NO_INACTIVE_VALS || metadata == MASK_AND_ONE_INACTIVE_VAL || metadata == MASK_AND_TWO_INACTIVE_VALS)
            skip(count / 8, "selection mask");
        uint64_t n = count;
        if ((compression & COMPRESS_ACTIVE_MASK) && metadata != NO_MASK_AND_ALL_VALS) {
            n = 0;
            for (uint64_t w : value_mask) n += uint64_t(__builtin_popcountll(w));
        }
        if (half && n == 0) return; // HalfReader::read reads nothing for no values (readData does)
        values(n * (half ? 2 : 4), node);
    }

    std::vector<uint64_t> mask(uint32_t bits, const char* field)
    {
        std::vector<uint64_t> words(bits / 64);
        read(words.data(), bits / 8, field);
        return words;
    }

    // InternalNode::readTopology (format >= 222) with 2^(3 log2dim) entries; children recursively.
    void internal(int log2dim, const std::string& node)
    {
        const uint32_t entries = uint32_t(1) << (3 * log2dim);
        const std::vector<uint64_t> children = mask(entries, "child mask");
        const std::vector<uint64_t> active = mask(entries, "value mask");
        compressed_values(entries, active, node);
        for (uint32_t w = 0; w < children.size(); ++w)
            for (uint64_t bits = children[w]; bits; bits &= bits - 1) {
                if (log2dim == 4) skip(64, "leaf value mask"); // LeafNode<float, 3>::readTopology
                else internal(4, node + " child " + std::to_string(w * 64 + uint32_t(__builtin_ctzll(bits))));
            }
    }
};

} // namespace

void check_float_topology(std::istream& is, std::streamoff grid_end, uint32_t compression, bool half, uint64_t tiles,
                          uint64_t children, const std::string& what)
{
    Walk walk{is, grid_end, compression, half, what, {}};
    walk.skip(tiles * (12 + 4 + 1), "root tiles");
    std::set<std::tuple<int32_t, int32_t, int32_t>> origins;
    for (uint64_t n = 0; n < children; ++n) {
        int32_t origin[3];
        walk.read(origin, sizeof origin, "root child origin");
        if (!origins.insert(std::make_tuple(origin[0], origin[1], origin[2])).second)
            walk.fail("root child " + std::to_string(n) + " repeats the origin (" + std::to_string(origin[0]) + ", " +
                      std::to_string(origin[1]) + ", " + std::to_string(origin[2]) + ")");
        walk.internal(5, "root child " + std::to_string(n));
    }
}

} // namespace vbl_vdb

#pragma GCC visibility pop
