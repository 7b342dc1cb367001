#pragma once
// A std::vector whose resize() leaves new elements of trivial types uninitialised, for buffers that are filled
// right after (a pread, a copy): value-initialising them first zeroes every byte once more, which was a fifth of
// an exact far frame of the 140M city out of core (docs/outofcore.md, "Reading subtrees").
#include <memory>
#include <type_traits>
#include <utility>
#include <vector>

namespace chcrt {

template <class T>
struct DefaultInitAllocator : std::allocator<T> {
    using value_type = T;
    template <class U>
    struct rebind {
        using other = DefaultInitAllocator<U>;
    };
    DefaultInitAllocator() noexcept = default;
    template <class U>
    DefaultInitAllocator(const DefaultInitAllocator<U>&) noexcept {}

    // No arguments: default-initialise (nothing for trivial types) instead of value-initialise (zero).
    template <class U>
    void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
        ::new (static_cast<void*>(p)) U;
    }
    template <class U, class... Args>
    void construct(U* p, Args&&... args) {
        ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
};

template <class T>
using UninitializedVector = std::vector<T, DefaultInitAllocator<T>>;

} // namespace chcrt
