#pragma once
// Large outputs written once, in parallel (a scan's 2048 x 1000 points): reserved and advised to
// the kernel as transparent-huge-page memory before the first write. A fresh buffer is otherwise
// paid for by one page fault per 4 KiB on the first write (a 2 M-point scan: ~14 000 faults, a
// third of its time on a virtual machine); with 2 MiB pages it takes ~30.
#include <cstddef>
#include <vector>

namespace laserfit {

// Advises [data, data + bytes) as huge-page memory where the system allows it (Linux THP in
// "always" or "madvise" mode); a no-op elsewhere. Only whole 2 MiB pages inside the range are
// affected, so the call is harmless on any allocation.
void advise_huge_pages(void* data, size_t bytes);

// v.resize(n) with the storage advised before any element is written. The elements are
// value-initialised as resize() does (a no-op for Eigen vectors, zero for integers).
template <class T>
void resize_advised(std::vector<T>& v, size_t n) {
  v.clear();
  v.reserve(n);
  advise_huge_pages(v.data(), n * sizeof(T));
  v.resize(n);
}

}  // namespace laserfit
