#pragma once
// `laserfit report`: benchmark results (results.jsonl of one or more runs) -> a Markdown report
// with tables per method and per scene/object, and PNG figures: error CDFs, success vs noise level
// and vs outlier rate, time vs scan size, registration overlays.
#include <string>
#include <vector>

namespace laserfit::report {

struct ReportSettings {
  std::vector<std::string> results;  // results.jsonl files (their directories' run.json and
                                     // overlays/ are used when present)
  std::string out_dir;
  bool overlays = true;
  std::vector<int> only_repetitions;  // non-empty: only records of these repetitions, so runs of
                                      // different lengths compare on the same scans
};

struct ReportSummary {
  size_t records = 0;
  std::vector<std::string> files;  // written, relative to out_dir
};

ReportSummary make_report(const ReportSettings& s);

}  // namespace laserfit::report
