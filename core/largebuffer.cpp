#include "core/largebuffer.h"

#include <atomic>
#include <cstdint>

// Under AddressSanitizer every buffer comes from operator new, where the sanitizer sees overruns
// (it does not watch a mapping of our own).
#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define MARBLES_ADDRESS_SANITIZER 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__)
#define MARBLES_ADDRESS_SANITIZER 1
#endif

#if defined(__linux__) && !defined(MARBLES_ADDRESS_SANITIZER)
#define MARBLES_MAP_LARGE_BUFFERS 1
#include <sys/mman.h>
#endif

namespace marbles {

namespace {

std::atomic<std::uint64_t> mappings{0};

// A small buffer: operator new as std::allocator calls it (the aligned form only for a type
// aligned beyond what plain new guarantees).
void *allocateSmall(std::size_t bytes, std::size_t alignment)
{
    if (alignment > __STDCPP_DEFAULT_NEW_ALIGNMENT__)
        return ::operator new(bytes, std::align_val_t(alignment));
    return ::operator new(bytes);
}

// (Unsized: clang before 16 declares no sized operator delete unless asked.)
void freeSmall(void *data, std::size_t alignment) noexcept
{
    if (alignment > __STDCPP_DEFAULT_NEW_ALIGNMENT__)
        ::operator delete(data, std::align_val_t(alignment));
    else
        ::operator delete(data);
}

} // namespace

bool mapsLargeBuffers()
{
#if defined(MARBLES_MAP_LARGE_BUFFERS)
    return true;
#else
    return false;
#endif
}

std::uint64_t largeBuffersMapped()
{
    return mappings.load(std::memory_order_relaxed);
}

#if defined(MARBLES_MAP_LARGE_BUFFERS)

namespace {

constexpr std::size_t hugePageBytes = std::size_t(2) << 20;

std::size_t roundUpToHugePages(std::size_t bytes)
{
    return (bytes + hugePageBytes - 1) / hugePageBytes * hugePageBytes;
}

// Whether a buffer of this size and alignment is mapped apart (else it comes from operator new):
// what allocating and freeing it must agree on.
bool isMappedApart(std::size_t bytes, std::size_t alignment)
{
    return bytes >= largeBufferBytes && alignment <= hugePageBytes;
}

} // namespace

// A mapping of its own, 2 MiB aligned: the kernel can only back a whole, aligned 2 MiB range with
// a huge page. 2 MiB more is mapped than asked for, and the unaligned head and tail unmapped
// again. The advice comes before the first write, so each first touch can take a huge page at
// once (khugepaged would only merge small pages long after).
void *allocateLargeBuffer(std::size_t bytes, std::size_t alignment)
{
    if (!isMappedApart(bytes, alignment))
        return allocateSmall(bytes, alignment);
    const std::size_t size = roundUpToHugePages(bytes);
    if (size < bytes || size + hugePageBytes < size)
        throw std::bad_alloc();
    void *mapped = mmap(nullptr, size + hugePageBytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (mapped == MAP_FAILED)
        throw std::bad_alloc();
    const auto start = reinterpret_cast<std::uintptr_t>(mapped);
    const std::uintptr_t aligned = (start + hugePageBytes - 1) / hugePageBytes * hugePageBytes;
    if (aligned > start)
        munmap(mapped, aligned - start);
    if (const std::uintptr_t tail = start + size + hugePageBytes - (aligned + size); tail > 0)
        munmap(reinterpret_cast<void *>(aligned + size), tail);
    mappings.fetch_add(1, std::memory_order_relaxed);
    void *data = reinterpret_cast<void *>(aligned);
    madvise(data, size, MADV_HUGEPAGE); // a hint: refused (no THP), the pages are small ones
    return data;
}

void freeLargeBuffer(void *data, std::size_t bytes, std::size_t alignment) noexcept
{
    if (!data)
        return;
    if (!isMappedApart(bytes, alignment)) {
        freeSmall(data, alignment);
        return;
    }
    munmap(data, roundUpToHugePages(bytes));
}

#else

void *allocateLargeBuffer(std::size_t bytes, std::size_t alignment)
{
    return allocateSmall(bytes, alignment);
}

void freeLargeBuffer(void *data, std::size_t, std::size_t alignment) noexcept
{
    freeSmall(data, alignment);
}

#endif

} // namespace marbles
