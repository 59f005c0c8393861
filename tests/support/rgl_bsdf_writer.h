// Writing measured BRDFs of our own in the RGL format (materials/measured_bsdf.h): a tensor file
// writer, and the tabulation of a known microfacet BRDF into the format's tables, as Dupuy and
// Jakob's pipeline lays them out (the NDF, the projected area, the visible normals' density in the
// square, the sampling weight and its luminance on the grid that the visible normals' warp carries
// to the sphere). Rendering such a file must give the BRDF it was made from.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <numbers>
#include <string>
#include <vector>

#include "core/piecewise_linear_2d.h"
#include "core/tensor_file.h"
#include "materials/measured_bsdf.h"
#include "materials/microfacet.h"

namespace penumbra::test {

struct TensorFieldToWrite {
    std::string name;
    TensorType type;
    std::vector<uint64_t> shape;
    std::string bytes;
};

inline TensorFieldToWrite floatField(std::string name, std::vector<uint64_t> shape,
                                     const std::vector<float>& values) {
    std::string bytes(values.size() * sizeof(float), '\0');
    if (!values.empty()) std::memcpy(bytes.data(), values.data(), bytes.size());
    return {std::move(name), TensorType::Float32, std::move(shape), std::move(bytes)};
}

inline TensorFieldToWrite byteField(std::string name, std::string bytes) {
    const uint64_t n = bytes.size();
    return {std::move(name), TensorType::UInt8, {n}, std::move(bytes)};
}

template <typename T>
void appendRaw(std::string& out, T value) {
    out.append(reinterpret_cast<const char*>(&value), sizeof value);
}

// The file: magic, version 1.0, the fields' headers, then their data in order.
inline std::string writeTensorFile(const std::vector<TensorFieldToWrite>& fields) {
    size_t headerSize = 12 + 2 + 4;
    for (const TensorFieldToWrite& f : fields)
        headerSize += 2 + f.name.size() + 2 + 1 + 8 + 8 * f.shape.size();
    std::string out("tensor_file", 12);
    out.push_back(char(1));
    out.push_back(char(0));
    appendRaw(out, uint32_t(fields.size()));
    uint64_t offset = headerSize;
    for (const TensorFieldToWrite& f : fields) {
        appendRaw(out, uint16_t(f.name.size()));
        out += f.name;
        appendRaw(out, uint16_t(f.shape.size()));
        appendRaw(out, uint8_t(f.type));
        appendRaw(out, offset);
        for (uint64_t extent : f.shape) appendRaw(out, extent);
        offset += f.bytes.size();
    }
    for (const TensorFieldToWrite& f : fields) out += f.bytes;
    return out;
}

// How to tabulate an isotropic BRDF whose normals follow a GGX distribution.
struct TabulationGrid {
    int thetaNodes = 20;         // viewer elevations, equal steps of sqrt(theta) from 0 to 90 degrees
    int normalGrid = 64;         // nodes per side of the NDF, projected area and visible normals' tables
    int sampleGrid = 32;         // nodes per side of the weight and luminance tables
    bool spectral = false;       // "spectra" (see tabulateIsotropicGgxBrdf) rather than "rgb"
    bool storesJacobian = true;  // false: the table holds f cos(theta_i) itself
    // Incident azimuths: 1 node (an isotropic file, azimuths of normals relative to the viewer's),
    // or more, equally spaced over 2 pi / reduction from -pi (an anisotropic file, absolute azimuths).
    int phiNodes = 1;
    int reduction = 1;
};

// Tabulates fCos(wo, wi) = f(wo, wi) cos(theta_i) of an isotropic BRDF over GGX normals of
// `alpha`, in the RGL format. Spectral files hold channel 0's value at every wavelength (a grey
// spectrum), so that they can be checked against a grey analytic BRDF.
inline std::string tabulateIsotropicGgxBrdf(float alpha, const std::function<Rgb(Vec3f, Vec3f)>& fCos,
                                            const TabulationGrid& grid = {}) {
    const MicrofacetDistribution ggx{alpha, alpha, MicrofacetKind::Ggx};
    const float pi = std::numbers::pi_v<float>;
    const auto sigma = [&](float theta) {
        // The projected area of GGX normals seen from theta: cos(theta) (1 + Lambda).
        const float c = std::cos(theta), s = std::sin(theta);
        return 0.5f * (c + std::sqrt(c * c + alpha * alpha * s * s));
    };
    const auto normalAt = [&](float ux, float uy, float phiO) {
        const float theta = measured::uToTheta(ux), phi = measured::uToPhi(uy) + phiO;
        return Vec3f{std::cos(phi) * std::sin(theta), std::sin(phi) * std::sin(theta), std::cos(theta)};
    };
    const int n = grid.normalGrid, m = grid.sampleGrid, t = grid.thetaNodes, p = grid.phiNodes;
    std::vector<float> thetaI(size_t(t), 0.0f), phiI(size_t(p), 0.0f);
    for (int k = 0; k < t; ++k) thetaI[size_t(k)] = measured::uToTheta(float(k) / float(t - 1));
    for (int k = 0; k < p && p > 1; ++k)
        phiI[size_t(k)] = -pi + 2.0f * pi / float(grid.reduction) * float(k) / float(p - 1);

    std::vector<float> ndf, sigmaTable;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const float ux = float(x) / float(n - 1), uy = float(y) / float(n - 1);
            ndf.push_back(ggx.D(normalAt(ux, uy, 0.0f)));
            sigmaTable.push_back(sigma(measured::uToTheta(ux)));
        }
    std::vector<float> vndf, weights, luminance, spectra;
    const std::vector<float> wavelengths{360.0f, 450.0f, 550.0f, 650.0f, 830.0f};
    for (int j = 0; j < p; ++j)
        for (int k = 0; k < t; ++k) {
            const float theta = thetaI[size_t(k)], phi = phiI[size_t(j)];
            const Vec3f wo{std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
            // An isotropic file's normals are at azimuths relative to the viewer's.
            const float phiOfNormals = p == 1 ? phi : 0.0f;
            std::vector<float> slice;
            for (int y = 0; y < n; ++y)
                for (int x = 0; x < n; ++x) {
                    const float ux = float(x) / float(n - 1), uy = float(y) / float(n - 1);
                    const Vec3f wm = normalAt(ux, uy, phiOfNormals);
                    slice.push_back(ggx.D(wm) * std::max(dot(wo, wm), 0.0f) / sigma(theta) * 2.0f * pi * pi *
                                    ux * std::sin(measured::uToTheta(ux)));
                }
            vndf.insert(vndf.end(), slice.begin(), slice.end());
            const PiecewiseLinear2D warp(slice, n, n, 1);
            std::vector<Rgb> sliceWeights;
            for (int y = 0; y < m; ++y)
                for (int x = 0; x < m; ++x) {
                    const PiecewiseLinear2D::Warped u =
                        warp.sample({float(x) / float(m - 1), float(y) / float(m - 1)}, {});
                    const Vec3f wm = normalAt(u.point.x, u.point.y, phiOfNormals);
                    const Vec3f wi = wm * (2.0f * dot(wo, wm)) - wo;
                    Rgb w(0.0f);
                    const float d = ggx.D(wm);
                    if (wi.z > 0.0f && d > 0.0f)
                        w = grid.storesJacobian ? fCos(wo, wi) * (4.0f * sigma(theta) / d) : fCos(wo, wi);
                    sliceWeights.push_back(w);
                    luminance.push_back(0.2126f * w.r + 0.7152f * w.g + 0.0722f * w.b + 1e-6f);
                }
            for (int c = 0; c < (grid.spectral ? int(wavelengths.size()) : 3); ++c)
                for (const Rgb& w : sliceWeights)
                    (grid.spectral ? spectra : weights).push_back(grid.spectral ? w.r : w[c]);
        }
    const auto ut = uint64_t(t), up = uint64_t(p), un = uint64_t(n), um = uint64_t(m);
    std::vector<TensorFieldToWrite> fields{
        byteField("description", "a GGX BRDF tabulated by penumbra's tests"),
        byteField("jacobian", std::string(1, grid.storesJacobian ? '\1' : '\0')),
        floatField("theta_i", {ut}, thetaI),
        floatField("phi_i", {up}, phiI),
        floatField("ndf", {un, un}, ndf),
        floatField("sigma", {un, un}, sigmaTable),
        floatField("vndf", {up, ut, un, un}, vndf),
        floatField("luminance", {up, ut, um, um}, luminance)};
    if (grid.spectral) {
        fields.push_back(floatField("wavelengths", {wavelengths.size()}, wavelengths));
        fields.push_back(floatField("spectra", {up, ut, wavelengths.size(), um, um}, spectra));
    } else {
        fields.push_back(floatField("rgb", {up, ut, 3, um, um}, weights));
    }
    return writeTensorFile(fields);
}

}  // namespace penumbra::test
