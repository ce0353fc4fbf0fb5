// The buffer type both readers hand to NanoVDB (openToNanoVDB, nanovdb::io::readGrid): allocated with
// vbl_aligned_alloc, so the core takes the grid without another copy, and checked against the memory
// limit (vbl_memory_limit) before the allocation.
#ifndef VBL_VDB_ALIGNED_BUFFER_H
#define VBL_VDB_ALIGNED_BUFFER_H

#include <cstdint>
#include <new>

#include <nanovdb/NanoVDB.h>

#include "core/alloc.h"
#include "vdb_internal.h"

namespace vbl_vdb {

// NanoVDB buffer type that allocates with vbl_aligned_alloc, so the converted grid is handed to the core
// without another copy (openToNanoVDB builds straight into it).
class AlignedBuffer {
public:
    AlignedBuffer() = default;
    AlignedBuffer(const AlignedBuffer&) = delete;
    AlignedBuffer& operator=(const AlignedBuffer&) = delete;
    AlignedBuffer(AlignedBuffer&& other) noexcept : mData(other.mData), mSize(other.mSize) { other.mData = nullptr, other.mSize = 0; }
    AlignedBuffer& operator=(AlignedBuffer&& other) noexcept
    {
        if (this != &other) {
            clear();
            mData = other.mData;
            mSize = other.mSize;
            other.mData = nullptr;
            other.mSize = 0;
        }
        return *this;
    }
    ~AlignedBuffer() { clear(); }
    static AlignedBuffer create(uint64_t size, const AlignedBuffer* = nullptr)
    {
        check_memory_limit(size, "the NanoVDB grid");
        AlignedBuffer b;
        b.mData = static_cast<uint8_t*>(vbl_aligned_alloc(NANOVDB_DATA_ALIGNMENT, size));
        if (!b.mData) throw std::bad_alloc();
        b.mSize = size;
        return b;
    }
    uint8_t* data() const { return mData; }
    uint64_t size() const { return mSize; }
    bool empty() const { return mSize == 0; }
    void clear()
    {
        vbl_aligned_free(mData);
        mData = nullptr;
        mSize = 0;
    }
    void* release()
    {
        void* p = mData;
        mData = nullptr;
        mSize = 0;
        return p;
    }

private:
    uint8_t* mData = nullptr;
    uint64_t mSize = 0;
};

} // namespace vbl_vdb

#endif
