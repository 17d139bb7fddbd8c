// tests/alloc_counter.h: replaces the global allocation functions with counting ones.
// Include in exactly one source file of a test binary; read g_allocations around the code
// that must not allocate.
#pragma once

#include <atomic>
#include <cstdlib>
#include <new>

// malloc/free pair correctly; GCC's -Wmismatched-new-delete cannot see that these replace
// the global new/delete.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"

inline std::atomic<long> g_allocations{0};

void* operator new(std::size_t n) {
  ++g_allocations;
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
