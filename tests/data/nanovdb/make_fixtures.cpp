// Writes the NanoVDB fixtures of tests/data/nanovdb/ with the NanoVDB library itself (32.3.3, the
// headers pbrt-v4 vendors) from OpenVDB grids (Debian's OpenVDB 10). Not built by penumbra.
//   make_fixtures OUTDIR
#include <openvdb/openvdb.h>
#define NANOVDB_USE_ZIP 1
#include <nanovdb/util/IO.h>
#include <nanovdb/util/OpenToNanoVDB.h>

#include <cstdio>
#include <string>
#include <vector>

// The density of voxel (i, j, k): distinct at every voxel, exact in float.
static float density(int i, int j, int k) {
    return 1.0f + 0.25f * float(i + 64) + 16.0f * float(j + 64) + 1024.0f * float(k + 64);
}

int main(int argc, char** argv) {
    if (argc != 2) return 2;
    const std::string out = argv[1];
    openvdb::initialize();

    // "density": voxel size 0.5, translated by (1, -2, 3); active voxels i in [-20, -5], j in
    // [-12, -1], k in [-9, -2] (negative coordinates, crossing leaf boundaries at -16 and -8), all
    // but (-10, -6, -5), switched off (it reads as the background, 0); plus an active tile of the
    // size of a leaf, value 7, at [-40, -33] x [-8, -1] x [-8, -1].
    auto grid = openvdb::FloatGrid::create(0.0f);
    grid->setName("density");
    grid->setGridClass(openvdb::GRID_FOG_VOLUME);
    auto xform = openvdb::math::Transform::createLinearTransform(0.5);
    xform->postTranslate(openvdb::Vec3d(1.0, -2.0, 3.0));
    grid->setTransform(xform);
    auto acc = grid->getAccessor();
    for (int i = -20; i <= -5; ++i)
        for (int j = -12; j <= -1; ++j)
            for (int k = -9; k <= -2; ++k) acc.setValue(openvdb::Coord(i, j, k), density(i, j, k));
    acc.setValueOff(openvdb::Coord(-10, -6, -5), 0.0f);
    grid->tree().addTile(1, openvdb::Coord(-40, -8, -8), 7.0f, true);

    // "temperature": voxel size 0.25, no translation; active voxels i in [100, 102], j in
    // [200, 201], k in [300, 301] of 1000 + (i - 100) + 10 (j - 200) + 100 (k - 300).
    auto temperature = openvdb::FloatGrid::create(0.0f);
    temperature->setName("temperature");
    temperature->setTransform(openvdb::math::Transform::createLinearTransform(0.25));
    auto tacc = temperature->getAccessor();
    for (int i = 100; i <= 102; ++i)
        for (int j = 200; j <= 201; ++j)
            for (int k = 300; k <= 301; ++k)
                tacc.setValue(openvdb::Coord(i, j, k),
                              1000.0f + float(i - 100) + 10.0f * float(j - 200) + 100.0f * float(k - 300));

    // "heat": a grid of doubles, which penumbra refuses by its type (NanoVDB's smallest grid of
    // another type than float).
    auto heat = openvdb::DoubleGrid::create(0.0);
    heat->setName("heat");
    heat->tree().setValue(openvdb::Coord(1, 2, 3), 5.0);

    // The same grids as an OpenVDB file, for the test that reads both formats.
    openvdb::io::File(out + "/smoke.vdb").write({grid, temperature, heat});

    // Each converted as pbrt-v4's tools do (statistics and checksum by default), written
    // uncompressed, and the density once more compressed with ZIP.
    std::vector<nanovdb::GridHandle<nanovdb::HostBuffer>> handles;
    handles.push_back(nanovdb::openToNanoVDB(*grid));
    handles.push_back(nanovdb::openToNanoVDB(*temperature));
    handles.push_back(nanovdb::openToNanoVDB(*heat));
    nanovdb::io::writeGrids(out + "/smoke.nvdb", handles, nanovdb::io::Codec::NONE);
    nanovdb::io::writeGrid(out + "/density_zip.nvdb", handles[0], nanovdb::io::Codec::ZIP);
    std::printf("wrote %s/smoke.vdb, smoke.nvdb, density_zip.nvdb\n", out.c_str());
    return 0;
}
