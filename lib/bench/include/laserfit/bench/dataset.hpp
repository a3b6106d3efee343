#pragma once
// A benchmark's dataset on disk: datasets/<name>/scans/<trial>.pcd (the simulated scan, organized,
// labelled), gt/<trial>.json (conditions, seeds, true and prior poses of every target) and
// manifest.json (the benchmark's digest and every file's size and CRC-32). Regenerating with the
// same seed writes identical bytes, whatever the job count.
#include <string>
#include <vector>

#include "laserfit/bench/spec.hpp"

namespace laserfit::bench {

struct DatasetSummary {
  size_t trials = 0, bytes = 0;
  double wall_s = 0;
};

// `repetitions`: only these repetitions of every cell; `scenes`: only these scenes (empty: all).
DatasetSummary generate_dataset(const Benchmark& b, const std::string& dir, int jobs = 1,
                                const std::vector<int>& repetitions = {},
                                const std::vector<std::string>& scenes = {});

// Re-reads every file of a dataset and compares it with its manifest; throws laserfit::Error
// naming the first file that differs or is missing.
void verify_dataset(const std::string& dir);

// A manifest's file path, refused (laserfit::Error naming the manifest) unless it is relative
// and stays inside the dataset: a manifest must not make laserfit read /etc/shadow or ../x.
std::string manifest_path(const std::string& manifest, const std::string& path);

}  // namespace laserfit::bench
