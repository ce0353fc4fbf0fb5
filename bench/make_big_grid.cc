// Writes a large float fog grid for the load-memory benchmark (bench_load_memory.sh): a ball of
// EDGE voxels across (EDGE = 530 gives about 79 M active voxels, the size issue 18 measured) as
// OUT.vdb (blosc + active mask) and OUT.nvdb (NanoVDB, no codec). Not built into any test.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include <openvdb/openvdb.h>
#include <nanovdb/util/IO.h>
#include <nanovdb/util/OpenToNanoVDB.h>

int main(int argc, char** argv)
{
    if (argc != 3) {
        std::fprintf(stderr, "usage: make_big_grid OUT EDGE   (writes OUT.vdb and OUT.nvdb)\n");
        return 2;
    }
    const int edge = std::atoi(argv[2]);
    if (edge < 8 || edge > 4000) {
        std::fprintf(stderr, "make_big_grid: EDGE must be in [8, 4000]\n");
        return 2;
    }
    openvdb::initialize();
    openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(0.0f);
    grid->setName("density");
    grid->setGridClass(openvdb::GRID_FOG_VOLUME);
    grid->setTransform(openvdb::math::Transform::createLinearTransform(2.0 / edge));
    auto acc = grid->getAccessor();
    const double r = 0.5 * edge, c = 0.5 * edge;
    for (int i = 0; i < edge; ++i)
        for (int j = 0; j < edge; ++j)
            for (int k = 0; k < edge; ++k) {
                const double x = i + 0.5 - c, y = j + 0.5 - c, z = k + 0.5 - c;
                const double d = std::sqrt(x * x + y * y + z * z) / r;
                if (d < 1.0) acc.setValueOn(openvdb::Coord(i, j, k), float(0.5 + 0.5 * std::sin(0.05 * (i + 2 * j + 3 * k)) * (1.0 - d)));
            }
    const std::string out = argv[1];
    openvdb::io::File file(out + ".vdb");
    file.setCompression(openvdb::io::COMPRESS_BLOSC | openvdb::io::COMPRESS_ACTIVE_MASK);
    file.write({grid});
    file.close();
    auto handle = nanovdb::openToNanoVDB(*grid);
    nanovdb::io::writeGrid(out + ".nvdb", handle);
    std::printf("make_big_grid: %s.vdb/.nvdb: %llu active voxels, NanoVDB %llu bytes\n", out.c_str(),
                (unsigned long long)grid->activeVoxelCount(), (unsigned long long)handle.size());
    return 0;
}
