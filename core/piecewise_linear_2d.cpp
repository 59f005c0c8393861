#include "core/piecewise_linear_2d.h"

#include <algorithm>
#include <cmath>

#include "core/check.h"

namespace penumbra {

namespace {

// The cell of a grid of n nodes over [0, 1] holding x, and x's position within it in [0, 1].
struct CellPosition {
    int index;
    float offset;
};

CellPosition cellOf(float x, int n) {
    const float g = (x >= 0.0f ? std::min(x, 1.0f) : 0.0f) * float(n - 1);  // NaN: the first cell
    const int index = std::min(int(g), n - 2);
    return {index, std::clamp(g - float(index), 0.0f, 1.0f)};
}

// t in [0, 1] where the integral of the ramp from a (at 0) to b (at 1) from 0 to t reaches c:
// a t + (b - a) t^2 / 2 = c, in the form that stays accurate when b is close to a or a is 0.
float invertRamp(float a, float b, float c) {
    const float root = std::sqrt(std::max(a * a + 2.0f * (b - a) * c, 0.0f));
    const float denominator = a + root;
    if (!(denominator > 0.0f)) return 0.0f;
    return std::clamp(2.0f * c / denominator, 0.0f, 1.0f);
}

// The largest index i in [0, n - 2] with value(i) <= target (value increasing).
template <typename Value>
int lastAtMost(int n, float target, const Value& value) {
    int low = 0, high = n - 2;
    while (low < high) {
        const int middle = (low + high + 1) / 2;
        if (value(middle) <= target)
            low = middle;
        else
            high = middle - 1;
    }
    return low;
}

template <typename Table>
float blended(const Table& table, size_t sliceSize, size_t index, const ParameterBlend& blend) {
    float sum = 0.0f;
    for (int k = 0; k < blend.count; ++k) sum += blend.weight[k] * table[blend.slice[k] * sliceSize + index];
    return sum;
}

}  // namespace

ParameterGrid::ParameterGrid(std::vector<std::vector<float>> nodes) : nodes_(std::move(nodes)) {
    PENUMBRA_CHECK(nodes_.size() <= 3, "a table depends on at most three parameters");
    strides_.assign(nodes_.size(), 0);
    for (size_t d = nodes_.size(); d-- > 0;) {
        PENUMBRA_CHECK(!nodes_[d].empty(), "a parameter has nodes");
        strides_[d] = uint32_t(slices_);
        slices_ *= nodes_[d].size();
    }
}

ParameterBlend ParameterGrid::blend(const float* values) const {
    ParameterBlend blend;
    blend.count = 1;
    blend.slice[0] = 0;
    blend.weight[0] = 1.0f;
    for (size_t d = 0; d < nodes_.size(); ++d) {
        const std::vector<float>& nodes = nodes_[d];
        if (nodes.size() == 1) continue;
        const int n = int(nodes.size());
        const int index = lastAtMost(n, values[d], [&](int i) { return nodes[size_t(i)]; });
        float upper = (values[d] - nodes[size_t(index)]) / (nodes[size_t(index) + 1] - nodes[size_t(index)]);
        upper = upper > 0.0f ? std::min(upper, 1.0f) : 0.0f;
        // Each slice so far splits in two: this parameter's lower and upper node.
        for (int k = 0; k < blend.count; ++k) {
            blend.slice[size_t(k + blend.count)] =
                blend.slice[size_t(k)] + (uint32_t(index) + 1) * strides_[d];
            blend.weight[size_t(k + blend.count)] = blend.weight[size_t(k)] * upper;
            blend.slice[size_t(k)] += uint32_t(index) * strides_[d];
            blend.weight[size_t(k)] *= 1.0f - upper;
        }
        blend.count *= 2;
    }
    return blend;
}

BilinearTable::BilinearTable(std::vector<float> values, int nx, int ny, int channels)
    : values_(std::move(values)), nx_(nx), ny_(ny), channels_(channels) {
    PENUMBRA_CHECK(nx >= 2 && ny >= 2 && channels >= 1, "a table has at least 2 x 2 nodes and a channel");
    PENUMBRA_CHECK(values_.size() % (size_t(nx) * size_t(ny) * size_t(channels)) == 0,
                   "a table holds whole slices");
}

float BilinearTable::eval(Vec2f p, const ParameterBlend& blend, int channel) const {
    const CellPosition x = cellOf(p.x, nx_), y = cellOf(p.y, ny_);
    const size_t sliceSize = size_t(nx_) * size_t(ny_) * size_t(channels_);
    const size_t node =
        (size_t(y.index) * size_t(nx_) + size_t(x.index)) * size_t(channels_) + size_t(channel);
    const size_t right = size_t(channels_), up = size_t(nx_) * size_t(channels_);
    const float v00 = blended(values_, sliceSize, node, blend),
                v10 = blended(values_, sliceSize, node + right, blend),
                v01 = blended(values_, sliceSize, node + up, blend),
                v11 = blended(values_, sliceSize, node + up + right, blend);
    return (1.0f - y.offset) * ((1.0f - x.offset) * v00 + x.offset * v10) +
           y.offset * ((1.0f - x.offset) * v01 + x.offset * v11);
}

std::array<float, 3> BilinearTable::eval3(Vec2f p, const ParameterBlend& blend) const {
    return {eval(p, blend, 0), eval(p, blend, 1), eval(p, blend, 2)};
}

PiecewiseLinear2D::PiecewiseLinear2D(const std::vector<float>& values, int nx, int ny, size_t slices)
    : nx_(nx), ny_(ny) {
    const size_t sliceSize = size_t(nx) * size_t(ny);
    PENUMBRA_CHECK(nx >= 2 && ny >= 2 && values.size() == sliceSize * slices,
                   "a density has at least 2 x 2 nodes in every slice");
    density_.resize(values.size());
    rowCumulative_.resize(values.size());
    marginal_.resize(size_t(ny) * slices);
    const double dx = 1.0 / double(nx - 1), dy = 1.0 / double(ny - 1);
    std::vector<double> rows(sliceSize);
    std::vector<double> marginal(static_cast<size_t>(ny));
    for (size_t s = 0; s < slices; ++s) {
        const float* v = values.data() + s * sliceSize;
        // Integrals along each row (trapezoids are exact for a linear function), then over rows:
        // the row integral is linear in y between nodes too.
        for (size_t y = 0; y < size_t(ny); ++y) {
            rows[y * size_t(nx)] = 0.0;
            for (size_t x = 1; x < size_t(nx); ++x)
                rows[y * size_t(nx) + x] =
                    rows[y * size_t(nx) + x - 1] +
                    0.5 * dx * (double(v[y * size_t(nx) + x - 1]) + v[y * size_t(nx) + x]);
        }
        marginal[0] = 0.0;
        for (size_t y = 1; y < size_t(ny); ++y)
            marginal[y] =
                marginal[y - 1] + 0.5 * dy * (rows[y * size_t(nx) - 1] + rows[(y + 1) * size_t(nx) - 1]);
        const double total = marginal[size_t(ny) - 1];
        PENUMBRA_CHECK(total > 0.0, "a density's slice has a positive integral (the reader checks)");
        for (size_t i = 0; i < sliceSize; ++i) {
            density_[s * sliceSize + i] = float(double(v[i]) / total);
            rowCumulative_[s * sliceSize + i] = float(rows[i] / total);
        }
        for (size_t y = 0; y < size_t(ny); ++y) marginal_[s * size_t(ny) + y] = float(marginal[y] / total);
    }
}

float PiecewiseLinear2D::density(size_t node, const ParameterBlend& blend) const {
    return blended(density_, size_t(nx_) * size_t(ny_), node, blend);
}

float PiecewiseLinear2D::rowCumulative(size_t node, const ParameterBlend& blend) const {
    return blended(rowCumulative_, size_t(nx_) * size_t(ny_), node, blend);
}

float PiecewiseLinear2D::marginal(size_t row, const ParameterBlend& blend) const {
    return blended(marginal_, size_t(ny_), row, blend);
}

PiecewiseLinear2D::Warped PiecewiseLinear2D::sample(Vec2f u, const ParameterBlend& blend) const {
    const float dx = 1.0f / float(nx_ - 1), dy = 1.0f / float(ny_ - 1);
    const size_t nx = size_t(nx_);
    // The row: the marginal's cell, then the height within it where the ramp's integral reaches u.y.
    const int row = lastAtMost(ny_, u.y, [&](int y) { return marginal(size_t(y), blend); });
    const size_t rowNode = size_t(row) * nx;
    const float r0 = rowCumulative(rowNode + nx - 1, blend), r1 = rowCumulative(rowNode + 2 * nx - 1, blend);
    const float t = invertRamp(r0, r1, (u.y - marginal(size_t(row), blend)) / dy);
    // The column, along the density at that height.
    const float target = u.x * ((1.0f - t) * r0 + t * r1);
    const auto cumulativeAt = [&](int x) {
        return (1.0f - t) * rowCumulative(rowNode + size_t(x), blend) +
               t * rowCumulative(rowNode + nx + size_t(x), blend);
    };
    const int column = lastAtMost(nx_, target, cumulativeAt);
    const size_t node = rowNode + size_t(column);
    const float c0 = (1.0f - t) * density(node, blend) + t * density(node + nx, blend),
                c1 = (1.0f - t) * density(node + 1, blend) + t * density(node + nx + 1, blend);
    const float s = invertRamp(c0, c1, (target - cumulativeAt(column)) / dx);
    return {{(float(column) + s) * dx, (float(row) + t) * dy}, (1.0f - s) * c0 + s * c1};
}

PiecewiseLinear2D::Warped PiecewiseLinear2D::invert(Vec2f p, const ParameterBlend& blend) const {
    const float dx = 1.0f / float(nx_ - 1), dy = 1.0f / float(ny_ - 1);
    const size_t nx = size_t(nx_);
    const CellPosition x = cellOf(p.x, nx_), y = cellOf(p.y, ny_);
    const size_t rowNode = size_t(y.index) * nx, node = rowNode + size_t(x.index);
    const float s = x.offset, t = y.offset;
    const float c0 = (1.0f - t) * density(node, blend) + t * density(node + nx, blend),
                c1 = (1.0f - t) * density(node + 1, blend) + t * density(node + nx + 1, blend);
    const float r0 = rowCumulative(rowNode + nx - 1, blend), r1 = rowCumulative(rowNode + 2 * nx - 1, blend);
    const float alongRow = (1.0f - t) * rowCumulative(node, blend) + t * rowCumulative(node + nx, blend) +
                           dx * (c0 * s + 0.5f * (c1 - c0) * s * s);
    const float rowTotal = (1.0f - t) * r0 + t * r1;
    const float ux = rowTotal > 0.0f ? std::clamp(alongRow / rowTotal, 0.0f, 1.0f) : 0.0f;
    const float uy = marginal(size_t(y.index), blend) + dy * (r0 * t + 0.5f * (r1 - r0) * t * t);
    return {{ux, std::clamp(uy, 0.0f, 1.0f)}, (1.0f - s) * c0 + s * c1};
}

float PiecewiseLinear2D::pdf(Vec2f p, const ParameterBlend& blend) const {
    const CellPosition x = cellOf(p.x, nx_), y = cellOf(p.y, ny_);
    const size_t nx = size_t(nx_), node = size_t(y.index) * nx + size_t(x.index);
    const float c0 = (1.0f - y.offset) * density(node, blend) + y.offset * density(node + nx, blend),
                c1 = (1.0f - y.offset) * density(node + 1, blend) + y.offset * density(node + nx + 1, blend);
    return (1.0f - x.offset) * c0 + x.offset * c1;
}

}  // namespace penumbra
