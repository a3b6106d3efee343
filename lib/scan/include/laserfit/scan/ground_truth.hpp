#pragma once
// Ground truth of a simulated scan as JSON: object poses (true, and as the scan shows them),
// per-profile sensor poses (nominal and true), the seed and every setting, and statistics.
#include "laserfit/io/json.hpp"
#include "laserfit/scan/scanner.hpp"

namespace laserfit::scan {

io::Json ground_truth_json(const ScanScene& scene, const ScanResult& result);
io::Json settings_json(const ScanSettings& s);

}  // namespace laserfit::scan
