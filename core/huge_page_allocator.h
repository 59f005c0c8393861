// Memory for large arrays on transparent huge pages (madvise MADV_HUGEPAGE): large arrays are
// aligned to 2 MiB and marked before their first touch. Where the system does not give huge
// pages the advice is ignored and nothing changes.
//
// Two reasons to want them:
//  - Random access (BVH nodes and primitive blocks): with 4 KiB pages nearly every node or leaf
//    on a large mesh is also a TLB miss, with 2 MiB pages a few dozen pages cover the whole tree.
//    Embree does the same by default on Linux (its "hugepages" device option).
//  - Page faults (the film, the EXR writer's buffers): a fresh 4 KiB page costs a fault when it is
//    first written, and on a virtual machine a fault is dear (bench/README.md, "Speed tricks").
#pragma once

#include <sys/mman.h>

#include <cstddef>
#include <cstdlib>
#include <memory>
#include <new>
#include <type_traits>

namespace penumbra {

inline constexpr size_t kHugePageSize = size_t(2) << 20;

// Allocates `bytes` aligned to `alignment`, on huge pages when it is at least one huge page.
inline void* allocateHugePageBytes(size_t bytes, size_t alignment) {
    if (bytes < kHugePageSize) return ::operator new(bytes, std::align_val_t(alignment));
    void* p = nullptr;
    if (posix_memalign(&p, kHugePageSize, bytes) != 0) throw std::bad_alloc();
    // Before the first touch, so the pages are huge from the start; failure is harmless.
    madvise(p, bytes, MADV_HUGEPAGE);
    return p;
}

inline void freeHugePageBytes(void* p, size_t bytes, size_t alignment) {
    if (bytes < kHugePageSize)
        ::operator delete(p, std::align_val_t(alignment));
    else
        std::free(p);
}

template <typename T, size_t Alignment = alignof(T)>
struct HugePageAllocator {
    static_assert(Alignment <= kHugePageSize && Alignment >= alignof(T));
    using value_type = T;
    template <typename U>
    struct rebind {
        using other = HugePageAllocator<U, Alignment>;
    };
    HugePageAllocator() = default;
    template <typename U>
    HugePageAllocator(const HugePageAllocator<U, Alignment>&) {}

    T* allocate(size_t n) { return static_cast<T*>(allocateHugePageBytes(n * sizeof(T), Alignment)); }
    void deallocate(T* p, size_t n) { freeHugePageBytes(p, n * sizeof(T), Alignment); }
    template <typename U>
    bool operator==(const HugePageAllocator<U, Alignment>&) const {
        return true;
    }
};

// An array of `size` trivial values left uninitialized, for buffers written in full before they
// are read (no zero-filling pass).
template <typename T>
class HugePageBuffer {
    static_assert(std::is_trivially_default_constructible_v<T> && std::is_trivially_destructible_v<T>);

public:
    explicit HugePageBuffer(size_t size)
        : data_(static_cast<T*>(allocateHugePageBytes(size * sizeof(T), alignof(T))),
                Free{size * sizeof(T)}) {}
    T* get() const { return data_.get(); }

private:
    struct Free {
        size_t bytes;
        void operator()(T* p) const { freeHugePageBytes(p, bytes, alignof(T)); }
    };
    std::unique_ptr<T, Free> data_;
};

}  // namespace penumbra
