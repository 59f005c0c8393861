// A pixel's samples summed in 64-bit integers before they reach the film's sums.
//
// Each addend is rounded to 2^-48 units exactly as ExactSum::add rounds it, and integer addition
// is associative, so the pixel's sums come out bit for bit as if every sample had been added to
// it directly. Adding to a register is cheaper than to a 128-bit sum in memory (bench/README.md,
// "Speed tricks"). Addends too large to be summed in 64 bits go to the pixel at once.
#pragma once

#include <algorithm>
#include <cstdint>
#include <iterator>

#include "film/film.h"

namespace penumbra {

class PixelAccumulator {
public:
    // At most this many samples are summed before they are added to the pixel: 2^6 addends of
    // fewer than 2^56 units each cannot overflow an int64.
    static constexpr int kMaxSamples = 64;
    static_assert(kMaxSamples * ExactSum::kSmallAddendUnits <= 0x1p62);

    PixelAccumulator(Film& film, int x, int y) : film_(film), x_(x), y_(y) {}
    PixelAccumulator(const PixelAccumulator&) = delete;
    PixelAccumulator& operator=(const PixelAccumulator&) = delete;
    ~PixelAccumulator() { flush(); }

    void add(Rgb value, float sampleWeight, const FirstHitAovs& aovs) {
        if (samples_ == kMaxSamples) flush();
        ++samples_;
        PixelSums::forEachAddend(value, sampleWeight, &aovs, [this](int i, double addend) {
            int64_t units;
            if (ExactSum::smallAddendUnits(addend, units))
                units_[i] += units;
            else
                film_.addAddend(x_, y_, i, addend);
        });
    }

    // Adds what was summed to the pixel.
    void flush() {
        film_.addUnits(x_, y_, units_, samples_);
        std::fill(std::begin(units_), std::end(units_), 0);
        samples_ = 0;
    }

private:
    Film& film_;
    int x_, y_;
    int64_t units_[PixelSums::kSumCount] = {};
    uint32_t samples_ = 0;
};

}  // namespace penumbra
