#include "laserfit/core/parallel.hpp"

#include <algorithm>
#include <atomic>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "laserfit/core/error.hpp"

namespace laserfit {

void parallel_for(size_t n, int jobs, const std::function<void(size_t)>& f) {
  std::atomic<size_t> next{0};
  std::mutex m;
  std::string first_error;
  auto worker = [&] {
    for (size_t i; (i = next++) < n;) {
      try {
        f(i);
      } catch (const std::exception& e) {
        std::lock_guard<std::mutex> l(m);
        if (first_error.empty()) first_error = e.what();
        next = n;
      }
    }
  };
  // No more threads than indices, and none for one: a thread that starts or ends while another
  // forks a reader (lib/core/isolate) is one more moment in which the child can inherit a lock.
  const size_t threads = std::min(n, static_cast<size_t>(std::max(1, jobs)));
  std::vector<std::thread> pool;
  for (size_t j = 0; threads > 1 && j < threads; ++j) pool.emplace_back(worker);
  if (threads <= 1) worker();
  for (auto& t : pool) t.join();
  if (!first_error.empty()) throw Error(first_error);
}

}  // namespace laserfit
