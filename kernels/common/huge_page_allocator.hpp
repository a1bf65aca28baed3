#pragma once
// An allocator for the library's own large buffers (the stream sort's records, the sorted rays): a
// buffer of at least kHugePageMinBytes is aligned to 2 MiB and marked for transparent huge pages
// (madvise(MADV_HUGEPAGE), which Linux's default "madvise" setting honours) before anything touches
// it. Buffers written or read at random places over hundreds of megabytes then miss the TLB far less
// often (docs/streams.md, "Sorting the rays themselves"). Smaller buffers come from operator new.
#include <cstddef>
#include <cstdlib>
#include <new>

#include <sys/mman.h>

namespace beamtrace {

inline constexpr std::size_t kHugePageBytes = std::size_t{2} << 20;
inline constexpr std::size_t kHugePageMinBytes = std::size_t{8} << 20;

template <class T>
struct HugePageAllocator {
    using value_type = T;
    HugePageAllocator() = default;
    template <class U>
    HugePageAllocator(const HugePageAllocator<U>&) noexcept {}

    T* allocate(std::size_t n) {
        if (n > std::size_t(-1) / sizeof(T)) throw std::bad_array_new_length();
        const std::size_t bytes = n * sizeof(T);
        if (bytes < kHugePageMinBytes) return static_cast<T*>(::operator new(bytes, std::align_val_t(alignof(T))));
        const std::size_t rounded = (bytes + kHugePageBytes - 1) / kHugePageBytes * kHugePageBytes;
        void* p = std::aligned_alloc(kHugePageBytes, rounded);
        if (!p) throw std::bad_alloc();
        madvise(p, rounded, MADV_HUGEPAGE);  // advice only: without it the buffer still works
        return static_cast<T*>(p);
    }
    void deallocate(T* p, std::size_t n) noexcept {
        if (n * sizeof(T) < kHugePageMinBytes)
            ::operator delete(p, std::align_val_t(alignof(T)));
        else
            std::free(p);
    }
    template <class U>
    bool operator==(const HugePageAllocator<U>&) const noexcept {
        return true;
    }
};

}  // namespace beamtrace
