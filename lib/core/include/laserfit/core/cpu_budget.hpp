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

}  // namespace laserfit
