// Procedural demo/benchmark cloud: a union of spheres (a cumulus heap) eroded by our own fBm value noise,
// density in [0, 1] with smooth edges, written as a "density" fog volume. Deterministic (fixed lattice
// hash, no RNG state). Usage: make_cloud OUTPUT.vdb
#include <cmath>
#include <cstdint>
#include <cstdio>

#include <openvdb/openvdb.h>

namespace {

// Integer lattice hash -> [0, 1).
double lattice(int x, int y, int z)
{
    uint32_t h = uint32_t(x) * 0x8da6b343u ^ uint32_t(y) * 0xd8163841u ^ uint32_t(z) * 0xcb1ab31fu;
    h ^= h >> 16;
    h *= 0x7feb352du;
    h ^= h >> 15;
    h *= 0x846ca68bu;
    h ^= h >> 16;
    return double(h) * (1.0 / 4294967296.0);
}

double fade(double t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); } // quintic, C2 smooth

// Value noise in [-1, 1].
double value_noise(double x, double y, double z)
{
    const double fx = std::floor(x), fy = std::floor(y), fz = std::floor(z);
    const int ix = int(fx), iy = int(fy), iz = int(fz);
    const double u = fade(x - fx), v = fade(y - fy), w = fade(z - fz);
    double c[2][2][2];
    for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b)
            for (int d = 0; d < 2; ++d) c[a][b][d] = lattice(ix + a, iy + b, iz + d);
    auto lerp = [](double p, double q, double t) { return p + (q - p) * t; };
    double x00 = lerp(c[0][0][0], c[1][0][0], u), x10 = lerp(c[0][1][0], c[1][1][0], u);
    double x01 = lerp(c[0][0][1], c[1][0][1], u), x11 = lerp(c[0][1][1], c[1][1][1], u);
    return 2.0 * lerp(lerp(x00, x10, v), lerp(x01, x11, v), w) - 1.0;
}

// Fractional Brownian motion: 5 octaves, lacunarity 2, gain 0.5; roughly in [-1, 1].
double fbm(double x, double y, double z)
{
    double sum = 0.0, amp = 0.5, freq = 1.0;
    for (int o = 0; o < 5; ++o) {
        sum += amp * value_noise(x * freq + 17.0 * o, y * freq - 5.0 * o, z * freq + 3.0 * o);
        freq *= 2.0;
        amp *= 0.5;
    }
    return sum / 0.96875;
}

double smoothstep(double e0, double e1, double x)
{
    double t = (x - e0) / (e1 - e0);
    t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
    return t * t * (3.0 - 2.0 * t);
}

struct Sphere { double x, y, z, r; };

// The heap, in voxels, inside [0,128)^2 x [0,128) (y up, flat-ish base).
const Sphere kSpheres[] = {
    {64, 44, 64, 30}, {38, 38, 58, 22}, {90, 38, 70, 22}, {62, 40, 36, 20}, {66, 38, 94, 20},
    {50, 66, 58, 20}, {78, 64, 66, 18}, {64, 84, 60, 14}, {30, 30, 84, 14}, {98, 30, 40, 14},
};

} // namespace

int main(int argc, char** argv)
{
    if (argc != 2) {
        std::fprintf(stderr, "usage: make_cloud OUTPUT.vdb\n");
        return 2;
    }
    openvdb::initialize();
    openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(0.0f);
    grid->setName("density");
    grid->setGridClass(openvdb::GRID_FOG_VOLUME);
    grid->setTransform(openvdb::math::Transform::createLinearTransform(1.0 / 64.0)); // 2 world units wide
    auto acc = grid->getAccessor();
    const double noise_scale = 1.0 / 16.0, erosion = 9.0, edge = 5.0; // voxels
    for (int i = -16; i < 144; ++i)
        for (int j = 0; j < 144; ++j)
            for (int k = -16; k < 144; ++k) {
                const double x = i + 0.5, y = j + 0.5, z = k + 0.5;
                double d = 1e30; // signed distance to the union of spheres (negative inside)
                for (const Sphere& s0 : kSpheres) {
                    // Spread the heap to fill the 128^3 box: 1.2x sideways, 1.15x up, radii 1.25x.
                    const Sphere s = {64.0 + (s0.x - 64.0) * 1.2, s0.y * 1.15, 64.0 + (s0.z - 64.0) * 1.2, s0.r * 1.25};
                    d = std::fmin(d, std::sqrt((x - s.x) * (x - s.x) + (y - s.y) * (y - s.y) + (z - s.z) * (z - s.z)) - s.r);
                }
                if (d > erosion) continue;
                d += erosion * fbm(x * noise_scale, y * noise_scale, z * noise_scale);
                const double flat = smoothstep(8.0, 20.0, y); // flatter, denser base
                const double density = smoothstep(0.0, edge, -d) * (0.35 + 0.65 * flat);
                if (density > 1e-4) acc.setValueOn(openvdb::Coord(i, j, k), float(density));
            }
    grid->pruneGrid(0.0f);
    openvdb::io::File file(argv[1]);
    file.setCompression(openvdb::io::COMPRESS_BLOSC | openvdb::io::COMPRESS_ACTIVE_MASK);
    file.write({grid});
    file.close();
    std::printf("make_cloud: %s: %llu active voxels\n", argv[1], (unsigned long long)grid->activeVoxelCount());
    return 0;
}
