// make_smoke: writes a procedural plume of smoke as an OpenVDB file with two float grids, "density"
// and "temperature", through the OpenVDB library. The example scenes' volume
// (scenes/volumes/smoke.vdb, used by scenes/smoke.json and, with its temperature, scenes/fire.json)
// is its output with the defaults:
//
//   make_smoke OUTPUT.vdb [VOXELS_ACROSS [FLOOR]]
//
// The plume rises along +y from a disk at the origin, widening as it rises (radius 0.25 at the
// base, 0.7 at the top, 2.5 units up), its density thinning with height and carved by fractal
// value noise so that it has wisps and holes. Voxels are 1 / (VOXELS_ACROSS / 1.6) units (default
// 48 across the plume's widest 1.6 units). Every voxel of the box around the plume is stored, with
// FLOOR (default 0) added to the plume's density: a medium with the grid's coefficients times FLOOR
// around the box then continues into it unbroken (the haze of scenes/smoke.json: its FLOOR is the
// haze's sigma_s over the smoke's). The temperature, in kelvin, is that of a fire burning in the
// plume: hottest (2300 K) at the base of its core, cooling with height and towards its edge, and
// flickering with the same noise; 0 outside the plume. The box's corners, where the lattice's cells
// end, are printed.
#include <openvdb/openvdb.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace {

// Value noise on the integer lattice, trilinear with a smoothstep, from a hash of the corner.
double latticeValue(int x, int y, int z) {
    uint64_t h = uint64_t(uint32_t(x)) * 0x9e3779b97f4a7c15ULL ^
                 uint64_t(uint32_t(y)) * 0xc2b2ae3d27d4eb4fULL ^
                 uint64_t(uint32_t(z)) * 0x165667b19e3779f9ULL;
    h ^= h >> 33;
    h *= 0xff51afd7ed558ccdULL;
    h ^= h >> 33;
    return double(h >> 11) * 0x1p-53;
}

double valueNoise(double x, double y, double z) {
    const int x0 = int(std::floor(x)), y0 = int(std::floor(y)), z0 = int(std::floor(z));
    auto smooth = [](double t) { return t * t * (3 - 2 * t); };
    const double fx = smooth(x - x0), fy = smooth(y - y0), fz = smooth(z - z0);
    auto lerp = [](double t, double a, double b) { return a + t * (b - a); };
    double c[2][2];
    for (int j = 0; j < 2; ++j)
        for (int k = 0; k < 2; ++k)
            c[j][k] = lerp(fx, latticeValue(x0, y0 + j, z0 + k), latticeValue(x0 + 1, y0 + j, z0 + k));
    return lerp(fz, lerp(fy, c[0][0], c[1][0]), lerp(fy, c[0][1], c[1][1]));
}

// Fractal sum of four octaves, in [0, 1].
double fractalNoise(double x, double y, double z) {
    double sum = 0, amplitude = 0.5, norm = 0;
    for (int octave = 0; octave < 4; ++octave) {
        sum += amplitude * valueNoise(x, y, z);
        norm += amplitude;
        amplitude *= 0.5;
        x *= 2.03, y *= 2.03, z *= 2.03;
    }
    return sum / norm;
}

constexpr double kHeight = 2.5;

// Where (x, y, z) lies in the plume: h its height over kHeight, r its distance from the swaying
// axis over the radius there; false outside.
bool plumeCoordinates(double x, double y, double z, double& h, double& r) {
    if (y < 0 || y > kHeight) return false;
    h = y / kHeight;
    const double cx = 0.15 * std::sin(2.5 * y), cz = 0.1 * std::sin(1.7 * y + 1.0);
    const double radius = 0.25 + 0.45 * h;
    r = std::hypot(x - cx, z - cz) / radius;
    return r < 1;
}

// The plume's density at (x, y, z).
double plumeDensity(double x, double y, double z) {
    double h, r;
    if (!plumeCoordinates(x, y, z, h, r)) return 0;
    const double profile = (1 - r * r) * (1 - h * h) * std::min(1.0, y / 0.1);
    const double noise = fractalNoise(3 * x, 3 * y - 1.5, 3 * z);
    return std::max(0.0, profile * (2.2 * noise - 0.6));
}

// The fire's temperature at (x, y, z), kelvin.
double plumeTemperature(double x, double y, double z) {
    double h, r;
    if (!plumeCoordinates(x, y, z, h, r)) return 0;
    const double noise = fractalNoise(3 * x, 3 * y - 1.5, 3 * z);
    return 2300.0 * std::exp(-1.0 * h) * (1 - 0.5 * r * r) * (0.75 + 0.5 * noise);
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2 || argc > 4) {
        std::fprintf(stderr, "usage: make_smoke OUTPUT.vdb [VOXELS_ACROSS [FLOOR]]\n");
        return 2;
    }
    const int across = argc >= 3 ? std::atoi(argv[2]) : 48;
    const double floor = argc == 4 ? std::atof(argv[3]) : 0.0;
    if (across < 4 || across > 1024 || !(floor >= 0.0 && floor < 1.0)) {
        std::fprintf(stderr, "make_smoke: VOXELS_ACROSS must be from 4 to 1024, FLOOR from 0 to below 1\n");
        return 2;
    }
    openvdb::initialize();
    const double voxel = 1.6 / across;
    openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(0.0f);
    grid->setName("density");
    grid->setGridClass(openvdb::GRID_FOG_VOLUME);
    grid->setTransform(openvdb::math::Transform::createLinearTransform(voxel));
    openvdb::FloatGrid::Ptr temperature = openvdb::FloatGrid::create(0.0f);
    temperature->setName("temperature");
    temperature->setGridClass(openvdb::GRID_FOG_VOLUME);
    temperature->setTransform(grid->transform().copy());
    auto accessor = grid->getAccessor();
    auto temperatureAccessor = temperature->getAccessor();
    const int half = across / 2 + 2, height = int(std::ceil(2.5 / voxel)) + 1;
    for (int i = -half; i <= half; ++i)
        for (int j = 0; j <= height; ++j)
            for (int k = -half; k <= half; ++k) {
                const double d = plumeDensity(i * voxel, j * voxel, k * voxel) + floor;
                if (d > 0.01 || floor > 0.0) accessor.setValue(openvdb::Coord(i, j, k), float(d));
                const double t = plumeTemperature(i * voxel, j * voxel, k * voxel);
                if (t > 0.0) temperatureAccessor.setValue(openvdb::Coord(i, j, k), float(t));
            }
    openvdb::io::File file(argv[1]);
    file.write({grid, temperature});
    file.close();
    std::printf(
        "wrote %s: %llu active voxels of %g units; with every voxel stored, the lattice spans "
        "[%g, %g] x [%g, %g] x [%g, %g]\n",
        argv[1], static_cast<unsigned long long>(grid->activeVoxelCount()), voxel, (-half - 0.5) * voxel,
        (half + 0.5) * voxel, -0.5 * voxel, (height + 0.5) * voxel, (-half - 0.5) * voxel,
        (half + 0.5) * voxel);
    return 0;
}
