#include "laserfit/report/report.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

#include "laserfit/bench/runner.hpp"
#include "laserfit/core/atomic_file.hpp"
#include "laserfit/core/error.hpp"
#include "laserfit/io/cloud_io.hpp"
#include "laserfit/metrics/stats.hpp"
#include "laserfit/report/figures.hpp"

namespace laserfit::report {
namespace fs = std::filesystem;
using io::Json;

namespace {

std::string fmt(double v, int prec = 3) {
  if (!std::isfinite(v)) return "–";
  std::ostringstream o;
  o.precision(prec);
  o << v;
  return o.str();
}

// Empirical CDF of an error over every record expected to give a pose; a failed registration
// never reaches any error level, so the curve ends below 1 by the failure rate.
Series cdf(const std::string& name, const std::vector<const Json*>& rs, const char* key,
           double floor) {
  std::vector<double> v;
  size_t n = 0;
  for (const auto* r : rs) {
    if (r->at("expect") != "pose") continue;
    ++n;
    if (r->at("status") != "failed") v.push_back(std::max(floor, r->at(key).get<double>()));
  }
  std::sort(v.begin(), v.end());
  Series s{name, {}, {}};
  for (size_t i = 0; i < v.size(); ++i)
    s.x.push_back(v[i]), s.y.push_back(double(i + 1) / double(n));
  return s;
}

// Success rate against a condition; continuous draws are grouped into 5 equal-count bins.
Series success_vs(const std::string& name, const std::vector<const Json*>& rs,
                  const std::string& cond) {
  std::vector<std::pair<double, bool>> v;
  for (const auto* r : rs)
    v.push_back({r->at("conditions").at(cond).get<double>(), r->at("success").get<bool>()});
  std::sort(v.begin(), v.end());
  std::set<double> distinct;
  for (const auto& p : v) distinct.insert(p.first);
  Series s{name, {}, {}};
  if (distinct.size() <= 8) {
    for (double x : distinct) {
      int n = 0, k = 0;
      for (const auto& p : v)
        if (p.first == x) ++n, k += p.second;
      s.x.push_back(x), s.y.push_back(double(k) / n);
    }
    return s;
  }
  const size_t bins = 5;
  for (size_t b = 0; b < bins; ++b) {
    const size_t lo = b * v.size() / bins, hi = (b + 1) * v.size() / bins;
    if (hi <= lo) continue;
    double x = 0;
    int k = 0;
    for (size_t i = lo; i < hi; ++i) x += v[i].first, k += v[i].second;
    s.x.push_back(x / double(hi - lo)), s.y.push_back(double(k) / double(hi - lo));
  }
  return s;
}

std::string table_row(const std::string& head, const std::vector<const Json*>& rs) {
  const bench::GroupStats g = bench::group_stats(rs);
  std::ostringstream o;
  o << "| " << head << " | " << g.records << " | " << fmt(100.0 * g.success_rate(), 4) << " % | "
    << g.false_accepts << " | " << g.ambiguous << " | " << g.failed << " | " << g.not_visible
    << " | " << fmt(100.0 * g.determinable_success_rate(), 4) << " % of " << g.determinable << " | "
    << fmt(g.t_median_um) << " / " << fmt(g.t_p95_um) << " | " << fmt(g.r_median_deg) << " / "
    << fmt(g.r_p95_deg) << " | " << fmt(g.time_median_s) << " / " << fmt(g.time_p95_s) << " | "
    << (g.peak_rss_mb > 0 ? fmt(g.peak_rss_mb, 4) : "not measured") << " |\n";
  return o.str();
}

const char* kTableHead =
    "| registrations | success | false accepts | ambiguous | failed | unsuccessful, target not "
    "visible | success where the scan determines the pose | "
    "t error median / p95 (µm) | r error median / p95 (°) "
    "| time median / p95 (s) | peak memory (MiB) |\n";

}  // namespace

ReportSummary make_report(const ReportSettings& s) {
  const std::set<int> reps(s.only_repetitions.begin(), s.only_repetitions.end());
  auto wanted = [&](const Json& r, const std::string& path) {
    if (reps.empty()) return true;
    if (!r.contains("repetition") || !r.at("repetition").is_number_integer())
      throw Error(path, "a record without an integer 'repetition'; cannot select repetitions");
    return reps.count(r.at("repetition").get<int>()) > 0;
  };
  std::vector<Json> records;
  std::vector<Json> runs;
  std::vector<std::string> overlay_files;
  std::set<fs::path> dirs;
  for (const auto& path : s.results) {
    auto rs = bench::read_results(path);
    for (auto& r : rs)
      if (wanted(r, path)) records.push_back(std::move(r));
    const fs::path dir = fs::path(path).parent_path();
    if (!dirs.insert(dir).second) continue;  // run.json and overlays once per directory
    if (fs::exists(dir / "run.json")) runs.push_back(io::read_json((dir / "run.json").string()));
    if (s.overlays && fs::is_directory(dir / "overlays"))
      for (const auto& e : fs::directory_iterator(dir / "overlays"))
        if (e.path().extension() == ".pcd") overlay_files.push_back(e.path().string());
  }
  if (records.empty() && !reps.empty())
    throw Error(s.results.front(), "no record of the selected repetitions");
  std::sort(overlay_files.begin(), overlay_files.end());
  const size_t shared = bench::share_scan_facts(records);
  fs::create_directories(s.out_dir);
  ReportSummary out;
  out.records = records.size();

  std::map<std::string, std::vector<const Json*>> by_method;
  std::map<std::string, std::vector<const Json*>> by_target;  // "scene / object / method"
  for (const auto& r : records) {
    by_method[r.at("method")].push_back(&r);
    by_target[r.at("scene").get<std::string>() + " | " + r.at("object").get<std::string>() + " | " +
              r.at("method").get<std::string>()]
        .push_back(&r);
  }
  std::ostringstream md;
  md << "# Benchmark report\n\nGenerated by `laserfit report` from";
  for (const auto& p : s.results) md << " `" << p << "`";
  md << ".\n\n";
  if (!reps.empty())
    md << "Only repetitions " << *reps.begin() << "–" << *reps.rbegin() << " of each run ("
       << reps.size() << " repetitions).\n\n";
  for (const auto& run : runs)
    md << "- run: benchmark `" << run.value("benchmark", "?") << "` (file digest "
       << run.value("digest", "?") << ", seed " << run.value("seed", Json(0)).dump() << ", shard "
       << run.value("shard", "?") << "), " << run.value("trials", Json(0)).dump() << " trials, "
       << fmt(run.value("wall_s", 0.0)) << " s wall, " << run.value("jobs", Json(0)).dump()
       << " jobs\n";
  md << "\nSuccess: translation ≤ tolerance and rotation ≤ tolerance (modulo the part's "
        "symmetries) with status "
        "`ok`, or `ambiguous` naming a DoF the target declares unobservable from its view (a "
        "continuous "
        "symmetry, `weak_rotation`, `weak_translation`) with the rest of the pose within "
        "tolerance; for a "
        "wrong-object trial, any status but `ok`. A false accept is an `ok` outside tolerance. "
        "The scan determines the pose when the default method (`ceres`), refined from the true "
        "pose on the "
        "scan points near it, is a success by the same rule and the scan holds the target (at "
        "least "
     << bench::kMinVisiblePoints
     << " labelled points, of a thin part on its side); where it is not (a view holding one plane "
        "of "
        "the part), no method can be right with `ok`, and the trial still counts as a miss in "
        "`success`. "
        "Errors are over the registrations that returned a pose (status not `failed`).";
  if (shared)
    md << " " << shared
       << " records without the check at the truth (a baseline outside laserfit) take their "
       << "target's visibility and determinability from a laserfit record of the same trial.";
  md << "\n\n";
  md << "## Per method\n\n| method " << kTableHead
     << "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const auto& [m, rs] : by_method) md << table_row(m, rs);
  md << "\n## Per scene and object\n\n| scene | object | method " << kTableHead
     << "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const auto& [k, rs] : by_target) md << table_row(k, rs);

  md << "\n## Figures\n\n";
  auto figure = [&](const std::string& file, const std::string& caption) {
    out.files.push_back(file);
    md << "![" << caption << "](" << file << ")\n\n" << caption << "\n\n";
  };
  {
    std::vector<Series> t, r;
    for (const auto& [m, rs] : by_method)
      t.push_back(cdf(m, rs, "t_err_um", 0.01)), r.push_back(cdf(m, rs, "r_err_deg", 1e-4));
    render_chart(s.out_dir + "/error_cdf_translation.png", t,
                 {"Translation error CDF", "translation error (um, log)", "fraction of trials",
                  true, false, 0, 1});
    figure("error_cdf_translation.png",
           "Cumulative distribution of the translation error (failed registrations never count as "
           "reached).");
    render_chart(s.out_dir + "/error_cdf_rotation.png", r,
                 {"Rotation error CDF", "rotation error (deg, log)", "fraction of trials", true,
                  false, 0, 1});
    figure("error_cdf_rotation.png", "Cumulative distribution of the rotation error.");
  }
  for (const auto& [cond, label] : std::vector<std::pair<std::string, std::string>>{
           {"noise_scale", "noise level (x the sensor's default sigmas)"},
           {"outlier_rate", "outlier rate (per point)"}}) {
    std::set<double> values;
    for (const auto& r : records) values.insert(r.at("conditions").at(cond).get<double>());
    if (values.size() < 2) {
      md << "(No figure of success vs " << cond << ": every trial ran at " << fmt(*values.begin())
         << ".)\n\n";
      continue;
    }
    std::vector<Series> ss;
    for (const auto& [m, rs] : by_method) ss.push_back(success_vs(m, rs, cond));
    const std::string file = "success_vs_" + cond + ".png";
    render_chart(s.out_dir + "/" + file, ss,
                 {"Success rate vs " + cond, label, "success rate", false, false, 0, 1.05});
    figure(file, "Success rate against " + label + ".");
  }
  {
    std::vector<Series> ss;
    for (const auto& [m, rs] : by_method) {
      Series se{m, {}, {}};
      for (const auto* r : rs)
        se.x.push_back(r->at("scan_points").get<double>() / 1e6),
            se.y.push_back(r->at("timing").at("time_s").get<double>());
      ss.push_back(se);
    }
    render_chart(s.out_dir + "/time_vs_scan_size.png", ss,
                 {"Registration time vs scan size", "scan points (millions)",
                  "time per registration (s)", false, true});
    figure("time_vs_scan_size.png",
           "Registration time (segmentation, features, RANSAC, refinement, trust) against the "
           "scan's valid points.");
  }
  if (!overlay_files.empty()) md << "### Registration overlays (first trial of each scene)\n\n";
  for (const auto& f : overlay_files) {
    const PointCloud c = io::read_cloud(f);
    const Eigen::Vector3d v = c.sensor_origin.value_or(Eigen::Vector3d(0, 0, 1000));
    const std::string name = fs::path(f).stem().string(), file = "overlay_" + name + ".png";
    render_overlay(s.out_dir + "/" + file, c, v, name);
    figure(file, "Overlay " + name +
                     ": the scan near the part (grey) and the reference at the estimated pose "
                     "(orange), seen from the sensor.");
  }
  write_file_atomic(s.out_dir + "/README.md", md.str());
  write_file_atomic(s.out_dir + "/summary.csv", bench::summary_csv(records));
  out.files.push_back("README.md");
  out.files.push_back("summary.csv");
  return out;
}

}  // namespace laserfit::report
