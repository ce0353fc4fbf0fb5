// OpenVDB side of bench_volume: ValueAccessor + BoxSampler lookups at the same points.
#include <chrono>
#include <cstddef>

#include <openvdb/openvdb.h>
#include <openvdb/tools/Interpolation.h>

extern "C" double vbl_bench_openvdb_lookups(const char* path, const char* grid_name, const double* points, size_t n,
                                            double* checksum)
{
    openvdb::initialize();
    openvdb::io::File file(path);
    file.open();
    openvdb::GridBase::Ptr base = file.readGrid(grid_name);
    file.close();
    auto grid = openvdb::gridPtrCast<openvdb::FloatGrid>(base);
    if (!grid) return -1.0;
    auto acc = grid->getConstAccessor();
    openvdb::tools::GridSampler<openvdb::FloatGrid::ConstAccessor, openvdb::tools::BoxSampler> sampler(acc, grid->transform());
    double sum = 0.0;
    auto t0 = std::chrono::steady_clock::now();
    for (size_t i = 0; i < n; ++i)
        sum += sampler.wsSample(openvdb::Vec3d(points[3 * i], points[3 * i + 1], points[3 * i + 2]));
    auto t1 = std::chrono::steady_clock::now();
    *checksum = sum;
    return std::chrono::duration<double>(t1 - t0).count();
}
