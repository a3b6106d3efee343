#pragma once
// Report figures rendered off screen by VTK (the 3D library that comes with PCL): line and scatter
// charts, and registration overlays (the scan in one colour, the registered reference in another,
// as in the paper's Fig. 5 and Fig. 7). PNGs are written atomically. VTK on Debian renders through
// X: without a DISPLAY the caller must run under Xvfb (laserfit report re-executes itself under
// xvfb-run).
#include <Eigen/Core>
#include <string>
#include <vector>

#include "laserfit/core/cloud.hpp"

namespace laserfit::report {

struct Series {
  std::string name;
  std::vector<double> x, y;
};

struct ChartSettings {
  std::string title, x_label, y_label;
  bool log_x = false;
  bool points = false;          // scatter instead of lines
  double y_min = 0, y_max = 0;  // fixed range when y_max > y_min
  int width = 900, height = 560;
};

void render_chart(const std::string& png, const std::vector<Series>& series,
                  const ChartSettings& s);

// `cloud` labels: 0 = scan (grey), 1 = registered reference (orange); seen from `viewpoint` (mm,
// the sensor position) towards the cloud's centre.
void render_overlay(const std::string& png, const PointCloud& cloud,
                    const Eigen::Vector3d& viewpoint, const std::string& title, int width = 900,
                    int height = 700);

// True when an X display is available for VTK.
bool have_display();

}  // namespace laserfit::report
