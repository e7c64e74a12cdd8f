// Large allocations on transparent huge pages: the global operator new and delete, replaced for every
// program linked with candela_engine (the static library supplies them before libstdc++ does).
//
// Why: on the machines Candela is developed and tested on (Debian 12 virtual machines whose transparent
// huge pages are in "madvise" mode), the first touch of each 4 KB page costs about 11 us, about 2.8 ms per
// MB: building the light tree over 1e6 lights spent 0.8 of its 1.2 s in page faults (its entries, binary
// and wide nodes, ~280 MB). On 2 MB pages the same memory costs about 0.07 ms per MB (measured with a
// 256 MB touch loop, 2026-12-02: 720 ms on 4 KB pages, 17-20 ms on huge pages). Fewer pages could also
// mean fewer TLB misses; the tree's sampling bench showed no change from it.
//
// What: a request on_huge_pages accepts (2 MB or more, at most half of it wasted) is rounded up to whole 2 MB
// pages, allocated 2 MB-aligned and advised MADV_HUGEPAGE before anyone touches it (madvise is advice: where the
// kernel declines, the memory is ordinary). Other requests go to malloc as before. Everything is released with free().
//
// Not compiled into the sanitizer and fuzzing builds (engine/CMakeLists.txt): their runtimes replace
// operator new themselves to check every allocation.
#include <sys/mman.h>

#include <algorithm>
#include <cstdlib>
#include <new>

namespace {

constexpr size_t kHugePage = size_t(2) << 20;

size_t round_up(size_t bytes, size_t multiple) { return (bytes + multiple - 1) / multiple * multiple; }

// From one huge page up, where rounding up to whole pages wastes at most half the request: exactly 2 MB, and every
// request from 2.67 MB. The planes of a 640x360 frame qualify: vec3 planes (2.8 MB) and packed surfaces (7.4 MB), which
// the reuse stages read at scattered pixels. Until 2026-12-06 the bound was 8 MB, which left them on 4 KB pages:
// moving them cut the history searches to ~0.9x and temporal reuse to ~0.97x (ab_stats, restir-di on manylights and
// city; docs/performance.md, "ReSTIR frame time").
bool on_huge_pages(size_t bytes) { return bytes >= kHugePage && round_up(bytes, kHugePage) - bytes <= bytes / 2; }

void* try_allocate(size_t bytes, size_t alignment) {
  if (on_huge_pages(bytes)) {
    const size_t page = std::max(kHugePage, alignment);
    const size_t rounded = round_up(bytes, page);
    void* p = std::aligned_alloc(page, rounded);
    if (p) madvise(p, rounded, MADV_HUGEPAGE);
    return p;
  }
  if (bytes == 0) bytes = 1;
  if (alignment <= __STDCPP_DEFAULT_NEW_ALIGNMENT__) return std::malloc(bytes);
  return std::aligned_alloc(alignment, round_up(bytes, alignment));
}

// The standard's contract for operator new: call the new-handler until the allocation succeeds, or throw
// std::bad_alloc when there is none.
void* allocate(size_t bytes, size_t alignment) {
  for (;;) {
    if (void* p = try_allocate(bytes, alignment)) return p;
    std::new_handler handler = std::get_new_handler();
    if (!handler) throw std::bad_alloc();
    handler();
  }
}

}  // namespace

void* operator new(size_t bytes) { return allocate(bytes, 0); }
void* operator new[](size_t bytes) { return allocate(bytes, 0); }
void* operator new(size_t bytes, std::align_val_t alignment) { return allocate(bytes, size_t(alignment)); }
void* operator new[](size_t bytes, std::align_val_t alignment) { return allocate(bytes, size_t(alignment)); }
// The nothrow forms of libstdc++ call the throwing ones above; every delete form frees.
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, size_t) noexcept { std::free(p); }
void operator delete[](void* p, size_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, size_t, std::align_val_t) noexcept { std::free(p); }
