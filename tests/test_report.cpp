// Report figures and tables. VTK renders through X here, so ctest runs this under xvfb-run.
#include <gtest/gtest.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>

#include <filesystem>

#include "laserfit/core/error.hpp"
#include "laserfit/io/cloud_io.hpp"
#include "laserfit/io/json.hpp"
#include "laserfit/report/figures.hpp"
#include "laserfit/report/report.hpp"
#include "test_util.hpp"

using namespace laserfit;

namespace {

struct Image {
  int width = 0, height = 0;
  size_t coloured = 0, dark = 0;  // pixels far from white: saturated colour / grey-black
};

Image read_png(const std::string& path) {
  vtkNew<vtkPNGReader> r;
  r->SetFileName(path.c_str());
  r->Update();
  Image im;
  int* dim = r->GetOutput()->GetDimensions();
  im.width = dim[0], im.height = dim[1];
  const int nc = r->GetOutput()->GetNumberOfScalarComponents();
  auto* px = static_cast<unsigned char*>(r->GetOutput()->GetScalarPointer());
  for (int i = 0; i < im.width * im.height; ++i) {
    const int R = px[i * nc], G = px[i * nc + 1], B = px[i * nc + 2];
    const int mx = std::max({R, G, B}), mn = std::min({R, G, B});
    if (mx - mn > 80)
      ++im.coloured;
    else if (mx < 128)
      ++im.dark;
  }
  return im;
}

io::Json record(int trial, const std::string& method, bool success, double t_um, double noise) {
  return {{"benchmark", "synthetic"},
          {"scene", "s"},
          {"object", "o"},
          {"method", method},
          {"trial", trial},
          {"repetition", trial},
          {"conditions", {{"noise_scale", noise}, {"outlier_rate", 0.0}}},
          {"expect", "pose"},
          {"status", success ? "ok" : "failed"},
          {"success", success},
          {"false_accept", false},
          {"t_err_um", t_um},
          {"r_err_deg", t_um / 100},
          {"scan_points", 1000000 + trial},
          {"timing", {{"time_s", 1.0 + trial}, {"peak_rss_mb", 100.0}}}};
}

}  // namespace

// Tolerance: the image has the requested size exactly and the plotted line covers at least
// a few hundred coloured pixels (a blank or background-only render fails).
TEST(Report, ChartIsRenderedWithItsSeries) {
  test::TempDir dir;
  report::Series s{"a", {1, 10, 100}, {0.1, 0.5, 1.0}};
  report::render_chart(dir / "c.png", {s}, {"title", "x", "y", true, false, 0, 1, 640, 400});
  const Image im = read_png(dir / "c.png");
  EXPECT_EQ(im.width, 640);
  EXPECT_EQ(im.height, 400);
  EXPECT_GT(im.coloured, 300u);
}

TEST(Report, OverlayShowsScanAndReferenceInTwoColours) {
  test::TempDir dir;
  PointCloud c;
  for (int i = 0; i < 100; ++i)
    for (int j = 0; j < 100; ++j) {
      c.points.emplace_back(i * 0.1f, j * 0.1f, 0.0f);
      c.labels.push_back(0);
      c.points.emplace_back(i * 0.1f + 12, j * 0.1f, 0.0f);
      c.labels.push_back(1);
    }
  c.width = int(c.points.size()), c.height = 1;
  report::render_overlay(dir / "o.png", c, {10, 5, 100}, "test", 600, 400);
  const Image im = read_png(dir / "o.png");
  EXPECT_GT(im.coloured, 2000u);  // the orange reference patch
  EXPECT_GT(im.dark, 2000u);      // the grey scan patch
}

TEST(Report, TablesCountWhatTheRecordsSay) {
  test::TempDir dir;
  std::string lines;
  lines += record(0, "ceres", true, 3, 1).dump() + "\n";
  lines += record(1, "ceres", true, 5, 1).dump() + "\n";
  io::Json absent = record(2, "ceres", false, 900, 2);
  absent["visible_points"] = 4;    // the target hardly in the scan: counted as not visible
  absent["determinable"] = false;  // and its pose not determinable from the scan
  lines += absent.dump() + "\n";
  lines += record(3, "ceres", true, 4, 2).dump() + "\n";
  lines += record(0, "gicp", false, 800, 1).dump() + "\n";
  std::filesystem::create_directories(dir / "run");
  test::write_text(dir / "run/results.jsonl", lines);
  report::ReportSettings s;
  s.results = {dir / "run/results.jsonl"};
  s.out_dir = dir / "rep";
  const auto r = report::make_report(s);
  EXPECT_EQ(r.records, 5u);
  const std::string md = test::read_bytes(dir / "rep/README.md");
  // ceres: 3 of 4 succeed; the failed one (not visible) returns no pose, so the median is over
  // 3, 4, 5 um. The other three determine their pose and succeed: 100 % of 3.
  EXPECT_NE(md.find("| ceres | 4 | 75 % | 0 | 0 | 1 | 1 | 100 % of 3 | 4 / "), std::string::npos)
      << md;
  EXPECT_NE(md.find("| gicp | 1 | 0 % |"), std::string::npos) << md;
  for (const char* f : {"error_cdf_translation.png", "error_cdf_rotation.png",
                        "success_vs_noise_scale.png", "time_vs_scan_size.png"})
    EXPECT_TRUE(std::filesystem::exists(dir / (std::string("rep/") + f))) << f;
  EXPECT_FALSE(std::filesystem::exists(dir / "rep/success_vs_outlier_rate.png"));  // one value only
  test::write_text(dir / "run/results.jsonl", "{\"trial\": 1}\n");
  EXPECT_THROW(report::make_report(s), Error);
}

// Exact: a repetition filter keeps the records of those repetitions from every run and no other,
// and says so in the report; a filter that matches nothing, or records without a repetition, are
// errors rather than an empty or silently unfiltered report.
TEST(Report, RepetitionsSelectTheSameScansFromEveryRun) {
  test::TempDir dir;
  std::filesystem::create_directories(dir / "a");
  std::filesystem::create_directories(dir / "b");
  std::string a, b;
  for (int t = 0; t < 4; ++t) a += record(t, "ceres", t != 1, 3, 1).dump() + "\n";
  for (int t = 0; t < 2; ++t) b += record(t, "gicp", false, 800, 1).dump() + "\n";
  test::write_text(dir / "a/results.jsonl", a);
  test::write_text(dir / "b/results.jsonl", b);
  report::ReportSettings s;
  s.results = {dir / "a/results.jsonl", dir / "b/results.jsonl"};
  s.out_dir = dir / "rep";
  s.overlays = false;
  s.only_repetitions = {0, 1};
  EXPECT_EQ(report::make_report(s).records, 4u);
  const std::string md = test::read_bytes(dir / "rep/README.md");
  EXPECT_NE(md.find("| ceres | 2 | 50 % |"), std::string::npos) << md;
  EXPECT_NE(md.find("| gicp | 2 | 0 % |"), std::string::npos) << md;
  EXPECT_NE(md.find("Only repetitions 0–1 of each run (2 repetitions)"), std::string::npos) << md;
  s.only_repetitions = {7};
  EXPECT_THROW(report::make_report(s), Error);
  io::Json bare = record(0, "ceres", true, 3, 1);
  bare.erase("repetition");
  test::write_text(dir / "a/results.jsonl", bare.dump() + "\n");
  s.only_repetitions = {0};
  EXPECT_THROW(report::make_report(s), Error);
}
