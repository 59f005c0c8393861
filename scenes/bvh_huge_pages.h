// An allocator for the arrays BVH traversal reads (nodes and primitive blocks): large arrays are
// aligned to 2 MiB and marked for transparent huge pages (madvise MADV_HUGEPAGE). Incoherent rays
// touch the arrays at random; with 4 KiB pages nearly every node or leaf on a large mesh is also
// a TLB miss, with 2 MiB pages a few dozen pages cover the whole tree. Embree does the same by
// default on Linux (its "hugepages" device option). Where the system does not give huge pages the
// advice is ignored and nothing changes.
#pragma once

#include <cstddef>
#include <cstdlib>
#include <new>

#include <sys/mman.h>

namespace penumbra {

inline constexpr size_t kHugePageSize = size_t(2) << 20;

template <typename T, size_t Alignment>
struct HugePageAllocator {
    static_assert(Alignment <= kHugePageSize);
    using value_type = T;
    template <typename U>
    struct rebind {
        using other = HugePageAllocator<U, Alignment>;
    };
    HugePageAllocator() = default;
    template <typename U>
    HugePageAllocator(const HugePageAllocator<U, Alignment>&) {}

    T* allocate(size_t n) {
        const size_t bytes = n * sizeof(T);
        if (bytes < kHugePageSize)
            return static_cast<T*>(::operator new(bytes, std::align_val_t(Alignment)));
        void* p = nullptr;
        if (posix_memalign(&p, kHugePageSize, bytes) != 0) throw std::bad_alloc();
        // Before the first touch, so the pages are huge from the start; failure is harmless.
        madvise(p, bytes, MADV_HUGEPAGE);
        return static_cast<T*>(p);
    }
    void deallocate(T* p, size_t n) {
        if (n * sizeof(T) < kHugePageSize)
            ::operator delete(p, std::align_val_t(Alignment));
        else
            std::free(p);
    }
    template <typename U>
    bool operator==(const HugePageAllocator<U, Alignment>&) const {
        return true;
    }
};

}  // namespace penumbra
