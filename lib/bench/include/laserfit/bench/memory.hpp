#pragma once
// Peak resident memory of a piece of work (Linux /proc). The kernel keeps one high-water mark per
// process; a probe resets it when it is the only work running (one job), so the figure is that
// work's own peak, and otherwise reports the process's peak since the run started (scope says
// which).
#include <string>

namespace laserfit::bench {

class MemoryProbe {
 public:
  MemoryProbe();           // resets the high-water mark if exclusive() allows
  double peak_mb() const;  // VmHWM now, MiB (0 when /proc is unavailable)
  const char* scope() const { return reset_ ? "trial" : "process"; }
  static void set_exclusive(bool one_job);  // the runner says whether work runs one at a time

 private:
  bool reset_ = false;
};

}  // namespace laserfit::bench
