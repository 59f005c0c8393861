// An allocator for large arrays whose value-initialized elements are all zero bytes (the film's
// pixel sums). It maps fresh anonymous pages, which the kernel fills with zeros when they are
// first touched, so a vector of n elements is made without writing them: the pages are zeroed by
// the render threads that first write them, in parallel, rather than by one thread beforehand
// (~45 ms for a 512x512 film of 64 MiB). The mapping asks for transparent huge pages, so that
// 2 MiB rather than 4 KiB is zeroed per page fault.
//
// Only for types whose value-initialized state is all zero bytes and that are implicit-lifetime
// (aggregates of integers, like PixelSums): such objects exist in freshly mapped memory without a
// constructor call. Copies are still constructed as usual.
#pragma once

#include <cstddef>
#include <new>
#include <type_traits>
#include <utility>

#include <sys/mman.h>

namespace penumbra {

template <typename T>
class ZeroPageAllocator {
public:
    using value_type = T;

    ZeroPageAllocator() = default;
    template <typename U>
    ZeroPageAllocator(const ZeroPageAllocator<U>&) noexcept {}

    T* allocate(size_t n) {
        if (n > size_t(-1) / sizeof(T)) throw std::bad_array_new_length();
        void* p = mmap(nullptr, bytes(n), PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
        if (p == MAP_FAILED) throw std::bad_alloc();
        madvise(p, bytes(n), MADV_HUGEPAGE);  // a hint: without huge pages the memory works the same
        return static_cast<T*>(p);
    }
    void deallocate(T* p, size_t n) noexcept { munmap(p, bytes(n)); }

    // Value-initialization of an element: the mapped bytes are zero already.
    template <typename U>
    void construct(U*) noexcept {
        static_assert(std::is_aggregate_v<U> || std::is_trivially_default_constructible_v<U>,
                      "ZeroPageAllocator only leaves aggregates of zero-valued members unconstructed");
    }
    template <typename U, typename... Args>
    void construct(U* p, Args&&... args) {
        ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }

    friend bool operator==(const ZeroPageAllocator&, const ZeroPageAllocator&) { return true; }

private:
    static size_t bytes(size_t n) { return n == 0 ? 1 : n * sizeof(T); }
};

}  // namespace penumbra
