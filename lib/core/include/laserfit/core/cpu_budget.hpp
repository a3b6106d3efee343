#pragma once
// How many threads this process may use: not the machine's cores but what it was given. On a
// cluster node a 1-CPU Slurm task that starts a thread per core oversubscribes the node (and
// loses per-trial memory figures); in a container the cgroup quota, not the core count, is the
// budget. Read once per call from the process's CPU affinity, its cgroup's cpu.max (v2) or
// cpu.cfs_quota_us (v1), and SLURM_CPUS_PER_TASK; the smallest wins.
#include <string>

namespace laserfit {

struct CpuBudget {
  int jobs = 1;        // >= 1
  std::string source;  // what bounded it: "affinity", "cgroup", "SLURM_CPUS_PER_TASK"
};

CpuBudget cpu_budget();

// The thread limit a command was given (--jobs), for the stages that size their own pools (PCL's
// OpenMP estimators); 0 when none was given. The CLIs also cap TBB with it (tbb::global_control).
void set_thread_limit(int threads);
int thread_limit();
// Threads for a stage that would use `fallback` without a limit: the limit when one was given.
inline int threads_or(int fallback) { return thread_limit() > 0 ? thread_limit() : fallback; }

}  // namespace laserfit
