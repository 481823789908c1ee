// std::vector whose storage starts on a cache line and fills whole lines, so
// that no two arrays share a line: a thread writing one array never evicts
// another thread's line of a neighbouring array (false sharing), and the
// vectorised loops start aligned.
#pragma once

#include <cstddef>
#include <new>
#include <vector>

namespace dem2d {

inline constexpr std::size_t kCacheLine = 64;  // bytes

template <class T>
struct CacheLineAllocator {
  using value_type = T;
  CacheLineAllocator() = default;
  template <class U>
  CacheLineAllocator(const CacheLineAllocator<U>&) {}  // NOLINT: implicit, as the standard allocators
  static std::size_t padded(std::size_t n) { return (n * sizeof(T) + kCacheLine - 1) / kCacheLine * kCacheLine; }
  T* allocate(std::size_t n) {
    return static_cast<T*>(::operator new(padded(n), std::align_val_t{kCacheLine}));
  }
  void deallocate(T* q, std::size_t n) { ::operator delete(q, padded(n), std::align_val_t{kCacheLine}); }
  template <class U>
  bool operator==(const CacheLineAllocator<U>&) const { return true; }
};

template <class T>
using AlignedVector = std::vector<T, CacheLineAllocator<T>>;

}  // namespace dem2d
