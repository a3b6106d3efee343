#include "laserfit/bench/memory.hpp"

#include <atomic>
#include <fstream>
#include <sstream>

namespace laserfit::bench {
namespace {
std::atomic<bool> g_exclusive{false};
}

void MemoryProbe::set_exclusive(bool one_job) { g_exclusive = one_job; }

MemoryProbe::MemoryProbe() {
  if (!g_exclusive) return;
  std::ofstream clear("/proc/self/clear_refs");  // "5": reset the peak RSS (Linux >= 4.0)
  clear << "5";
  clear.flush();
  reset_ = bool(clear);
}

double MemoryProbe::peak_mb() const {
  std::ifstream in("/proc/self/status");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("VmHWM:", 0) == 0) {
      std::istringstream s(line.substr(6));
      double kb = 0;
      s >> kb;
      return kb / 1024.0;
    }
  return 0;
}

}  // namespace laserfit::bench
