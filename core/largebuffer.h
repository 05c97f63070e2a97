#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <new>
#include <vector>

namespace marbles {

/// Memory for one large buffer (at least largeBufferBytes), mapped on its own in whole 2 MiB
/// pages and marked for the kernel's transparent huge pages before anything is written to it.
///
/// Why: a crowd's broad phase reads its neighbours anywhere in a 100k-marble model's buffers
/// (tens of MB), and with 4 KiB pages many such reads also miss the processor's cache of page
/// table entries, which covers a few MB (huge pages made the 100k crowds 5 to 8 % faster).
/// Debian's kernel gives huge pages only where they are asked for (transparent_hugepage
/// "madvise"); where they are refused or unsupported, the buffer is simply in small pages, with
/// the same contents. Nothing here changes a result.
/// Smaller buffers come from operator new as usual.
inline constexpr std::size_t largeBufferBytes = std::size_t(1) << 20;
void *allocateLargeBuffer(std::size_t bytes, std::size_t alignment);
void freeLargeBuffer(void *data, std::size_t bytes, std::size_t alignment) noexcept;
/// Whether this build maps large buffers apart (on Linux; not under AddressSanitizer, which
/// watches only operator new's memory): otherwise they too come from operator new.
bool mapsLargeBuffers();
/// How many buffers allocateLargeBuffer() has mapped so far (each is an allocation that operator
/// new does not see).
std::uint64_t largeBuffersMapped();

/// An allocator for the models' per-marble and per-bucket buffers (see allocateLargeBuffer()).
template<typename T>
struct LargeBufferAllocator {
    using value_type = T;

    LargeBufferAllocator() = default;
    template<typename U>
    LargeBufferAllocator(const LargeBufferAllocator<U> &) noexcept
    {
    }

    T *allocate(std::size_t n)
    {
        if (n > std::numeric_limits<std::size_t>::max() / sizeof(T))
            throw std::bad_array_new_length();
        return static_cast<T *>(allocateLargeBuffer(n * sizeof(T), alignof(T)));
    }
    void deallocate(T *p, std::size_t n) noexcept { freeLargeBuffer(p, n * sizeof(T), alignof(T)); }

    friend bool operator==(const LargeBufferAllocator &, const LargeBufferAllocator &) { return true; }
};

/// A std::vector whose storage, once it is large, lies in huge pages where the kernel allows.
template<typename T>
using LargeVector = std::vector<T, LargeBufferAllocator<T>>;

} // namespace marbles
