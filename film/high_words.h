// The high 64 bits of the film's 128-bit sums, held only where a sum has outgrown its low 64.
//
// A sum counts 2^-48 units (film/film.h), so its low 64 bits hold it up to 2^15 = 32768: enough
// for most pixels, but not for the squared radiance of a bright one, nor for depth in scene units
// summed over thousands of samples. When a low word wraps, the pixel's high word for that sum counts
// the wrap (the sum is high * 2^64 + low, low signed). High words are kept per run of
// kBlockPixels pixels and per sum, allocated at the first wrap in the run: a film where nothing
// wraps holds only the block pointers (2 bytes a pixel for 15 sums).
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>

namespace penumbra {

class HighWords {
public:
    static constexpr size_t kBlockPixels = 64;
    // What the block pointers of 15 sums take, per pixel (rounded up).
    static constexpr size_t kPointerBytesPerPixel = 2;
    static_assert(15 * sizeof(void*) <= kPointerBytesPerPixel * kBlockPixels);

    HighWords(size_t pixelCount, int sumCount);
    ~HighWords();
    HighWords(const HighWords& other);
    HighWords& operator=(const HighWords& other);
    HighWords(HighWords&& other) noexcept;
    HighWords& operator=(HighWords&& other) noexcept;

    // 0 where the block was never allocated.
    int64_t get(size_t pixel, int sum) const {
        const int64_t* block = blocks_[slot(pixel, sum)].load(std::memory_order_acquire);
        return block ? block[pixel % kBlockPixels] : 0;
    }
    // The pixel's high word for `sum`, its block allocated first where need be. Threads may call
    // it at the same time for different pixels (each pixel's words are written by one thread).
    int64_t& at(size_t pixel, int sum) {
        int64_t* block = blocks_[slot(pixel, sum)].load(std::memory_order_acquire);
        if (!block) block = allocate(slot(pixel, sum));
        return block[pixel % kBlockPixels];
    }
    // Whether any pixel's high word for `sum` may be nonzero (its block was allocated).
    bool anyAllocated(int sum) const;

private:
    size_t slot(size_t pixel, int sum) const {
        return (pixel / kBlockPixels) * size_t(sumCount_) + size_t(sum);
    }
    int64_t* allocate(size_t slot);
    void release();

    size_t slotCount_ = 0;
    int sumCount_ = 0;
    std::unique_ptr<std::atomic<int64_t*>[]> blocks_;
};

}  // namespace penumbra
