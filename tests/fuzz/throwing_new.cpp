// Global operator new and delete over malloc and free, linked into fuzz_vdb
// only.
//
// OpenVDB sizes compressed blocks from 64-bit lengths in the file. In a release
// build an absurd length makes `new` throw std::bad_alloc, and gvr refuses the
// file. AddressSanitizer's own operator new aborts instead, even with
// allocator_may_return_null=1, so every corrupt length would be a false
// finding. Its malloc does return null under that option (and
// max_allocation_size_mb), and still checks every access, leak and double free;
// these operators turn that null into std::bad_alloc, as the release build sees
// it. Only new/delete mismatches go unchecked in this one target.

#include <algorithm>
#include <cstdlib>
#include <new>

namespace {

void* allocate(std::size_t size) noexcept { return std::malloc(std::max<std::size_t>(size, 1)); }

void* allocateAligned(std::size_t size, std::align_val_t alignment) noexcept {
    void* p = nullptr;
    const std::size_t bytes = std::max<std::size_t>(size, 1);
    return posix_memalign(&p, std::max(std::size_t(alignment), sizeof(void*)), bytes) == 0 ? p : nullptr;
}

void* orThrow(void* p) {
    if (!p) throw std::bad_alloc();
    return p;
}

}  // namespace

void* operator new(std::size_t size) { return orThrow(allocate(size)); }
void* operator new[](std::size_t size) { return orThrow(allocate(size)); }
void* operator new(std::size_t size, std::align_val_t a) { return orThrow(allocateAligned(size, a)); }
void* operator new[](std::size_t size, std::align_val_t a) { return orThrow(allocateAligned(size, a)); }
void* operator new(std::size_t size, const std::nothrow_t&) noexcept { return allocate(size); }
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept { return allocate(size); }
void* operator new(std::size_t size, std::align_val_t a, const std::nothrow_t&) noexcept {
    return allocateAligned(size, a);
}
void* operator new[](std::size_t size, std::align_val_t a, const std::nothrow_t&) noexcept {
    return allocateAligned(size, a);
}

void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept { std::free(p); }
