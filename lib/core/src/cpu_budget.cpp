#include "laserfit/core/cpu_budget.hpp"

#include <sched.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <thread>

namespace laserfit {
namespace {

// The process's cgroup v2 path ("0::/slurm/uid_0/job_12/step_0" -> that path), or "".
std::string cgroup_v2_path() {
  std::ifstream in("/proc/self/cgroup");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("0::", 0) == 0) return line.substr(3);
  return {};
}

// CPUs a quota allows (ceil(quota / period)), or 0 when unlimited or unknown. Walks from the
// process's cgroup up to the root: a limit set on a parent applies too.
int cgroup_cpus() {
  int best = 0;
  auto take = [&](double quota, double period) {
    if (quota > 0 && period > 0) {
      const int n = std::max(1, static_cast<int>(std::ceil(quota / period)));
      best = best == 0 ? n : std::min(best, n);
    }
  };
  for (std::string p = cgroup_v2_path(); !p.empty();) {
    std::ifstream in("/sys/fs/cgroup" + (p == "/" ? std::string() : p) + "/cpu.max");
    std::string quota;
    double period = 0;
    if (in >> quota >> period && quota != "max") take(std::atof(quota.c_str()), period);
    if (p == "/") break;
    p = p.substr(0, p.rfind('/'));
    if (p.empty()) p = "/";
  }
  std::ifstream q("/sys/fs/cgroup/cpu/cpu.cfs_quota_us"),
      per("/sys/fs/cgroup/cpu/cpu.cfs_period_us");
  double quota = 0, period = 0;
  if (q >> quota && per >> period) take(quota, period);
  return best;
}

int affinity_cpus() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) == 0) return CPU_COUNT(&set);
  return static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

}  // namespace

CpuBudget cpu_budget() {
  CpuBudget b{affinity_cpus(), "affinity"};
  if (const int c = cgroup_cpus(); c > 0 && c < b.jobs) b = {c, "cgroup"};
  if (const char* s = std::getenv("SLURM_CPUS_PER_TASK")) {
    char* end = nullptr;
    const long n = std::strtol(s, &end, 10);
    if (end != s && *end == '\0' && n >= 1 && n < b.jobs)
      b = {static_cast<int>(n), "SLURM_CPUS_PER_TASK"};
  }
  b.jobs = std::max(1, b.jobs);
  return b;
}

namespace {
std::atomic<int> g_thread_limit{0};
}  // namespace

void set_thread_limit(int threads) { g_thread_limit = threads > 0 ? threads : 0; }
int thread_limit() { return g_thread_limit; }

}  // namespace laserfit
