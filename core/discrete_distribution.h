// Choosing one of n items with probability proportional to a weight (lights by power).
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

namespace penumbra {

class DiscreteDistribution {
public:
    DiscreteDistribution() = default;
    // Negative or non-finite weights count as 0. All-zero weights make an empty distribution.
    explicit DiscreteDistribution(const std::vector<double>& weights) {
        double total = 0.0;
        cdf_.reserve(weights.size());
        for (double w : weights) {
            total += (w > 0.0 && w < 1e300) ? w : 0.0;
            cdf_.push_back(total);
        }
        if (!(total > 0.0)) {
            cdf_.clear();
            return;
        }
        probabilities_.resize(weights.size());
        for (size_t i = 0; i < weights.size(); ++i) {
            cdf_[i] /= total;
            probabilities_[i] = float((weights[i] > 0.0 && weights[i] < 1e300) ? weights[i] / total : 0.0);
        }
        cdf_.back() = 1.0;
    }

    bool empty() const { return cdf_.empty(); }
    size_t size() const { return cdf_.size(); }
    float probability(size_t index) const { return probabilities_[index]; }

    // The item whose CDF interval contains u (u in [0, 1)); never an item of zero probability.
    uint32_t sample(float u) const {
        if (cdf_.size() == 1) return 0;  // one light, the common case: no search
        const auto it = std::upper_bound(cdf_.begin(), cdf_.end(), double(u));
        size_t index = std::min(size_t(it - cdf_.begin()), cdf_.size() - 1);
        while (probabilities_[index] == 0.0f && index > 0) --index;  // only reachable through rounding
        return uint32_t(index);
    }

    // The same item, and u replaced by its position within the item's interval, in [0, 1): a
    // value that can be used again (Cycles and pbrt-v4 reuse the light choice's sample so). The
    // values that choose an item then cover [0, 1) in the order they had, so stratified values
    // stay stratified for each item.
    uint32_t sampleAndRemap(float& u) const {
        const uint32_t index = sample(u);
        if (cdf_.size() == 1) return index;
        const double start = index == 0 ? 0.0 : cdf_[index - 1];
        const double width = cdf_[index] - start;
        const double remapped = width > 0.0 ? (double(u) - start) / width : 0.5;
        u = std::clamp(float(remapped), 0.0f, kOneMinusUlp);
        return index;
    }

    // The largest float below 1: where a remapped sample value is clamped to stay in [0, 1).
    static constexpr float kOneMinusUlp = 0x1.fffffep-1f;

private:
    std::vector<double> cdf_;
    std::vector<float> probabilities_;
};

}  // namespace penumbra
