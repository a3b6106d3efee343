#pragma once
// Which build of laserfit made a result: the version and the GNU build-id of the running
// executable (a hash of its contents that the linker writes, so two copies of one build agree
// and any rebuild with other code differs). Shards of one benchmark run must share it.
#include <string>

namespace laserfit {

inline constexpr const char* kVersion = "0.1.0";

// "laserfit 0.1.0 (build-id 3f2a...)", or "(build-id unknown)" where the linker wrote none.
std::string build_info();

}  // namespace laserfit
