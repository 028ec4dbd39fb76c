// Memory for the large arrays that traversal reads at random (BVH nodes, a mesh's vertices and leaf-ordered
// triangles) and for the builder's scratch arrays: large blocks are 2 MiB aligned and ask Linux for transparent
// huge pages, so that a ray's node and leaf visits do not each miss the TLB as well as the cache, and a fresh array
// costs a few faults instead of thousands. Debian's default (THP "madvise") gives huge pages only to memory that
// asks for them; Embree asks the same way for its BVH. Measured on the 1M-triangle isosurface (10 interleaved runs
// each): incoherent rays 1.14x faster with the persistent arrays on huge pages, primary and shadow rays unchanged;
// the build's fresh scratch memory had cost a tenth of its time in page faults.
#pragma once

#include <sys/mman.h>

#include <algorithm>
#include <cstddef>
#include <limits>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

namespace whitted {

/// Raw blocks: minBytes or more are 2 MiB aligned (their size rounded up to whole huge pages) and marked for huge
/// pages; smaller ones are 64-byte aligned.
struct HugePages {
  static constexpr std::size_t kHuge = std::size_t(2) << 20;
  static constexpr std::size_t kScratchMin = kHuge / 2;  ///< The builder's threshold (short-lived blocks).
  static std::size_t alignment(std::size_t bytes, std::size_t minBytes) { return bytes >= minBytes ? kHuge : 64; }
  static std::size_t rounded(std::size_t bytes, std::size_t minBytes) {
    const std::size_t a = alignment(bytes, minBytes);
    return (std::max<std::size_t>(bytes, 1) + a - 1) / a * a;
  }
  static void* allocate(std::size_t bytes, std::size_t minBytes = kScratchMin) {
    void* p = ::operator new(rounded(bytes, minBytes), std::align_val_t(alignment(bytes, minBytes)));
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    if (alignment(bytes, minBytes) == kHuge) madvise(p, rounded(bytes, minBytes), MADV_HUGEPAGE);  // a hint
#endif
    return p;
  }
  static void deallocate(void* p, std::size_t bytes, std::size_t minBytes = kScratchMin) {
    ::operator delete(p, std::align_val_t(alignment(bytes, minBytes)));
  }
};

/// Uninitialised short-lived array of trivially copyable T (a build's scratch memory) on HugePages: no
/// value-initialisation pass, and a large one faults in 2 MiB pages, first touched by whoever fills it (so by all the
/// threads of a parallel fill). Performance note: on the development VM a fresh 4 KiB page faulted in at ~14 us, and
/// the value-initialised std::vectors of one 1M-triangle rebuild (76 MB) cost 12-280 ms before the build started.
template <class T>
class ScratchArray {
  static_assert(std::is_trivially_copyable<T>::value, "raw storage");

 public:
  explicit ScratchArray(std::size_t n) : bytes_(n * sizeof(T)), p_(static_cast<T*>(HugePages::allocate(bytes_))) {}
  ~ScratchArray() { HugePages::deallocate(p_, bytes_); }
  ScratchArray(const ScratchArray&) = delete;
  ScratchArray& operator=(const ScratchArray&) = delete;
  T* data() { return p_; }
  const T* data() const { return p_; }
  T& operator[](std::size_t i) { return p_[i]; }
  const T& operator[](std::size_t i) const { return p_[i]; }

 private:
  std::size_t bytes_;
  T* p_;
};

/// std::vector allocator on HugePages for long-lived arrays: from 4 MiB (rounding up to whole huge pages then costs
/// at most a third more).
template <typename T>
struct HugePageAllocator {
  using value_type = T;
  static constexpr std::size_t kMinBytes = 2 * HugePages::kHuge;

  HugePageAllocator() = default;
  template <typename U>
  HugePageAllocator(const HugePageAllocator<U>&) {}  // NOLINT(google-explicit-constructor): allocator rebind

  /// At most half the address space, less a huge page of rounding (std::vector throws length_error beyond).
  std::size_t max_size() const noexcept {
    return (std::size_t(std::numeric_limits<std::ptrdiff_t>::max()) - HugePages::kHuge) / sizeof(T);
  }
  T* allocate(std::size_t n) {
    if (n > max_size()) throw std::bad_array_new_length();
    return static_cast<T*>(HugePages::allocate(n * sizeof(T), kMinBytes));
  }
  void deallocate(T* p, std::size_t n) noexcept { HugePages::deallocate(p, n * sizeof(T), kMinBytes); }
  template <typename U>
  bool operator==(const HugePageAllocator<U>&) const {
    return true;
  }
  template <typename U>
  bool operator!=(const HugePageAllocator<U>&) const {
    return false;
  }
};

/// A std::vector whose large blocks sit on huge pages (see HugePageAllocator).
template <typename T>
using LargeVector = std::vector<T, HugePageAllocator<T>>;

/// HugePageAllocator whose value-less construct default-initialises: resize() leaves new elements of a trivial T
/// uninitialised, for arrays written in full right after (a volume's scalars: a 2 GiB grid's zeroing pass, on one
/// thread, took as long as the parallel copy that follows it).
template <typename T>
struct UninitHugePageAllocator : HugePageAllocator<T> {
  using value_type = T;
  UninitHugePageAllocator() = default;
  template <typename U>
  UninitHugePageAllocator(const UninitHugePageAllocator<U>&) {}  // NOLINT(google-explicit-constructor): rebind
  template <typename U>
  struct rebind {
    using other = UninitHugePageAllocator<U>;
  };
  template <typename U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible<U>::value) {
    ::new (static_cast<void*>(p)) U;
  }
  template <typename U, typename... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

/// LargeVector whose resize() does not initialise (UninitHugePageAllocator).
template <typename T>
using UninitLargeVector = std::vector<T, UninitHugePageAllocator<T>>;

}  // namespace whitted
