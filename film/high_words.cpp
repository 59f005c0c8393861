#include "film/high_words.h"

#include <algorithm>
#include <utility>

namespace penumbra {

HighWords::HighWords(size_t pixelCount, int sumCount)
    : slotCount_((pixelCount + kBlockPixels - 1) / kBlockPixels * size_t(sumCount)),
      sumCount_(sumCount),
      blocks_(new std::atomic<int64_t*>[slotCount_]) {
    for (size_t i = 0; i < slotCount_; ++i) blocks_[i].store(nullptr, std::memory_order_relaxed);
}

HighWords::~HighWords() { release(); }

HighWords::HighWords(const HighWords& other) : HighWords(0, 0) { *this = other; }

HighWords& HighWords::operator=(const HighWords& other) {
    if (this == &other) return *this;
    HighWords copy(other.slotCount_ / std::max(other.sumCount_, 1) * kBlockPixels, other.sumCount_);
    for (size_t i = 0; i < other.slotCount_; ++i)
        if (const int64_t* block = other.blocks_[i].load(std::memory_order_acquire))
            std::copy(block, block + kBlockPixels, copy.allocate(i));
    return *this = std::move(copy);
}

HighWords::HighWords(HighWords&& other) noexcept
    : slotCount_(std::exchange(other.slotCount_, 0)),
      sumCount_(other.sumCount_),
      blocks_(std::move(other.blocks_)) {}

HighWords& HighWords::operator=(HighWords&& other) noexcept {
    if (this == &other) return *this;
    release();
    slotCount_ = std::exchange(other.slotCount_, 0);
    sumCount_ = other.sumCount_;
    blocks_ = std::move(other.blocks_);
    return *this;
}

bool HighWords::anyAllocated(int sum) const {
    for (size_t i = size_t(sum); i < slotCount_; i += size_t(sumCount_))
        if (blocks_[i].load(std::memory_order_acquire)) return true;
    return false;
}

int64_t* HighWords::allocate(size_t slot) {
    auto fresh = std::make_unique<int64_t[]>(kBlockPixels);  // zeroed
    int64_t* expected = nullptr;
    // Another thread may allocate the same block at the same time (pixels of one run in two tiles):
    // the first one stored is kept.
    if (blocks_[slot].compare_exchange_strong(expected, fresh.get(), std::memory_order_acq_rel))
        return fresh.release();
    return expected;
}

void HighWords::release() {
    for (size_t i = 0; i < slotCount_; ++i) delete[] blocks_[i].load(std::memory_order_relaxed);
    slotCount_ = 0;
}

}  // namespace penumbra
