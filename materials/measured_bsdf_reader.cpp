#include "materials/measured_bsdf_reader.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cmath>
#include <cstring>
#include <numbers>
#include <vector>

#include "core/colorimetry.h"
#include "core/error.h"
#include "core/input_file.h"
#include "core/input_limits.h"
#include "core/tensor_file.h"

namespace penumbra {

namespace {

constexpr float kPi = std::numbers::pi_v<float>;
// The largest magnitudes accepted: far beyond measured data, small enough that their products stay
// finite in single precision.
constexpr float kMaxDensity = 1e12f, kMaxReflectance = 1e6f, kMinSigma = 1e-8f, kMaxSigma = 1e8f;

// The parameter nodes of one axis: finite, strictly increasing, within [low, high].
std::vector<float> readNodes(const TensorFile& file, const char* name, float low, float high) {
    const TensorField& field = file.require(name, TensorType::Float32, 1);
    std::vector<float> nodes = file.floats(field);
    if (nodes.empty()) file.fail(fmt::format("the field \"{}\" is empty", name));
    for (size_t i = 0; i < nodes.size(); ++i) {
        if (!(nodes[i] >= low && nodes[i] <= high))
            file.fail(
                fmt::format("{}[{}] is {}: expected a number in [{}, {}]", name, i, nodes[i], low, high));
        if (i > 0 && !(nodes[i] > nodes[i - 1]))
            file.fail(fmt::format("{} is not increasing: {}[{}] = {} follows {}", name, name, i, nodes[i],
                                  nodes[i - 1]));
    }
    return nodes;
}

void requireShape(const TensorFile& file, const TensorField& field, const std::vector<uint64_t>& expected) {
    if (field.shape == expected) return;
    const auto show = [](const std::vector<uint64_t>& shape) {
        return fmt::format("[{}]", fmt::join(shape, ", "));
    };
    file.fail(fmt::format("the field \"{}\" has shape {}, expected {}", field.name, show(field.shape),
                          show(expected)));
}

// A grid extent of a table: at least 2 nodes (a grid of cells), and few enough for 32-bit indices.
int gridExtent(const TensorFile& file, const TensorField& field, size_t dimension) {
    const uint64_t n = field.shape[dimension];
    if (n < 2 || n > (1u << 15))
        file.fail(fmt::format("the field \"{}\" has {} nodes along dimension {}: expected 2 to 32768",
                              field.name, n, dimension));
    return int(n);
}

// Every value finite and within [low, high].
void requireValuesIn(const TensorFile& file, const TensorField& field, const std::vector<float>& values,
                     float low, float high) {
    for (size_t i = 0; i < values.size(); ++i)
        if (!(values[i] >= low && values[i] <= high))
            file.fail(fmt::format("the field \"{}\" holds {} at element {}: expected values in [{}, {}]",
                                  field.name, values[i], i, low, high));
}

// A density per slice: values in [0, kMaxDensity], not all zero in any slice.
void requireDensities(const TensorFile& file, const TensorField& field, const std::vector<float>& values,
                      size_t sliceSize) {
    requireValuesIn(file, field, values, 0.0f, kMaxDensity);
    for (size_t start = 0; start < values.size(); start += sliceSize) {
        bool positive = false;
        for (size_t i = start; i < start + sliceSize && !positive; ++i) positive = values[i] > 0.0f;
        if (!positive)
            file.fail(fmt::format(
                "the field \"{}\" is zero everywhere in slice {}: a density must be positive somewhere",
                field.name, start / sliceSize));
    }
}

// RGB weights of each wavelength node: a spectrum linear between the nodes (constant beyond them)
// integrated against the observer as a reflectance (core/colorimetry.h).
std::vector<Rgb> rgbWeightsOfWavelengths(const std::vector<float>& wavelengths) {
    std::vector<Xyz> xyz(wavelengths.size(), Xyz{});
    const std::vector<Xyz>& matching = cieMatchingAt1nm();
    const size_t n = wavelengths.size();
    size_t lower = 0;  // the node at or below lambda, which only grows
    for (size_t k = 0; k < matching.size(); ++k) {
        const float lambda = float(kVisibleLambdaMin) + float(k);
        float upperWeight = 0.0f;
        if (n > 1 && lambda > wavelengths[0]) {
            while (lower + 2 < n && wavelengths[lower + 1] <= lambda) ++lower;
            upperWeight = std::clamp(
                (lambda - wavelengths[lower]) / (wavelengths[lower + 1] - wavelengths[lower]), 0.0f, 1.0f);
        }
        for (int c = 0; c < 3; ++c) {
            xyz[lower][size_t(c)] += (1.0 - upperWeight) * matching[k][size_t(c)];
            if (upperWeight > 0.0f) xyz[lower + 1][size_t(c)] += upperWeight * matching[k][size_t(c)];
        }
    }
    std::vector<Rgb> weights;
    for (Xyz& w : xyz) {
        for (double& v : w) v /= cieYIntegral();
        weights.push_back(reflectanceXyzToLinearSrgb(w));  // linear, so weights of the nodes combine
    }
    return weights;
}

// The reflectance table in RGB, [slice][row][column][channel], from "rgb" or "spectra".
std::vector<float> readReflectance(const TensorFile& file, uint64_t slices, uint64_t phiCount,
                                   uint64_t thetaCount, uint64_t rows, uint64_t columns) {
    const size_t cells = size_t(rows * columns);
    const bool rgb = file.find("rgb") != nullptr;
    if (!rgb && !file.find("spectra"))
        file.fail("the file has neither \"spectra\" nor \"rgb\": no reflectance");
    const TensorField& field = file.require(rgb ? "rgb" : "spectra", TensorType::Float32, 5);
    std::vector<Rgb> weights;
    uint64_t bands = 3;
    if (!rgb) {
        weights = rgbWeightsOfWavelengths(readNodes(file, "wavelengths", 1.0f, 1e5f));
        bands = weights.size();
    }
    requireShape(file, field, {phiCount, thetaCount, bands, rows, columns});
    std::vector<float> out(size_t(slices) * cells * 3);
    for (size_t slice = 0; slice < slices; ++slice)
        for (size_t band = 0; band < bands; ++band)
            for (size_t cell = 0; cell < cells; ++cell) {
                const size_t element = (slice * size_t(bands) + band) * cells + cell;
                float value;
                std::memcpy(&value, field.bytes.data() + element * sizeof(float), sizeof value);
                if (!(std::abs(value) <= kMaxReflectance))
                    file.fail(
                        fmt::format("the field \"{}\" holds {} at element {}: expected values in [-{}, {}]",
                                    field.name, value, element, kMaxReflectance, kMaxReflectance));
                float* rgbOut = &out[(slice * cells + cell) * 3];
                if (rgb) {
                    rgbOut[band] = value;
                } else {
                    rgbOut[0] += weights[band].r * value;
                    rgbOut[1] += weights[band].g * value;
                    rgbOut[2] += weights[band].b * value;
                }
            }
    return out;
}

// The albedo for the AOV: the mean weight of a 32 x 32 grid of samples seen from the normal.
Rgb albedoAtNormalIncidence(const std::shared_ptr<const MeasuredBrdfTables>& tables) {
    const MeasuredBsdf bsdf{tables};
    Rgb sum(0.0f);
    constexpr int kSide = 32;
    for (int y = 0; y < kSide; ++y)
        for (int x = 0; x < kSide; ++x)
            if (auto s = bsdf.sample({0.0f, 0.0f, 1.0f}, 0.5f,
                                     {(float(x) + 0.5f) / kSide, (float(y) + 0.5f) / kSide}, true))
                sum = sum + s->weight;
    return sum * (1.0f / float(kSide * kSide));
}

}  // namespace

std::shared_ptr<const MeasuredBrdfTables> parseMeasuredBsdf(std::string_view bytes,
                                                            const std::string& fileName) {
    const TensorFile file(bytes, fileName);
    auto tables = std::make_shared<MeasuredBrdfTables>();

    const TensorField& description = file.require("description", TensorType::UInt8, 1);
    tables->description = std::string(description.bytes);
    const TensorField& jacobian = file.require("jacobian", TensorType::UInt8, 1);
    requireShape(file, jacobian, {1});
    tables->storesJacobian = jacobian.bytes[0] != 0;

    const std::vector<float> theta = readNodes(file, "theta_i", 0.0f, 0.5f * kPi + 1e-3f);
    const std::vector<float> phi = readNodes(file, "phi_i", -kPi - 1e-3f, kPi + 1e-3f);
    tables->isotropic = phi.size() <= 2;
    if (!tables->isotropic) {
        const float reduction = std::rint(2.0f * kPi / (phi.back() - phi.front()));
        if (reduction != 1.0f && reduction != 2.0f && reduction != 4.0f)
            file.fail(
                fmt::format("phi_i spans {} radians, 2 pi / {}: only the whole circle, a half or a quarter "
                            "(reduction 1, 2 or 4) is read",
                            phi.back() - phi.front(), reduction));
        tables->reduction = int(reduction);
    }
    const uint64_t slices = uint64_t(phi.size()) * theta.size();
    tables->incidence = ParameterGrid({phi, theta});

    // The normal distribution and the projected area, over the square.
    for (const char* name : {"ndf", "sigma"}) {
        const TensorField& field = file.require(name, TensorType::Float32, 2);
        const int rows = gridExtent(file, field, 0), columns = gridExtent(file, field, 1);
        std::vector<float> values = file.floats(field);
        const bool isSigma = std::strcmp(name, "sigma") == 0;
        requireValuesIn(file, field, values, isSigma ? kMinSigma : 0.0f, isSigma ? kMaxSigma : kMaxDensity);
        (isSigma ? tables->sigma : tables->ndf) = BilinearTable(std::move(values), columns, rows, 1);
    }

    // The visible normals and the luminance: densities over the square, one per incidence.
    const TensorField& vndf = file.require("vndf", TensorType::Float32, 4);
    const int vndfRows = gridExtent(file, vndf, 2), vndfColumns = gridExtent(file, vndf, 3);
    requireShape(file, vndf, {phi.size(), theta.size(), uint64_t(vndfRows), uint64_t(vndfColumns)});
    std::vector<float> values = file.floats(vndf);
    requireDensities(file, vndf, values, size_t(vndfRows) * size_t(vndfColumns));
    tables->vndf = PiecewiseLinear2D(values, vndfColumns, vndfRows, size_t(slices));

    const TensorField& luminance = file.require("luminance", TensorType::Float32, 4);
    const int rows = gridExtent(file, luminance, 2), columns = gridExtent(file, luminance, 3);
    requireShape(file, luminance, {phi.size(), theta.size(), uint64_t(rows), uint64_t(columns)});
    values = file.floats(luminance);
    requireDensities(file, luminance, values, size_t(rows) * size_t(columns));
    tables->luminance = PiecewiseLinear2D(values, columns, rows, size_t(slices));

    // The reflectance, on the luminance's grid.
    tables->reflectance = BilinearTable(
        readReflectance(file, slices, phi.size(), theta.size(), uint64_t(rows), uint64_t(columns)), columns,
        rows, 3);
    tables->albedoAtNormalIncidence = albedoAtNormalIncidence(tables);
    return tables;
}

std::shared_ptr<const MeasuredBrdfTables> readMeasuredBsdf(const std::filesystem::path& path) {
    InputFile file(path, "measured BRDF", limits::kMaxMeasuredBsdfFileBytes);
    const std::string bytes = file.readAll();
    return parseMeasuredBsdf(bytes, path.string());
}

}  // namespace penumbra
