#pragma once
// The benchmark tests' fixture: a tiny simulated USB benchmark and quiet runs.
#include <string>
#include <vector>

#include "laserfit/bench/runner.hpp"
#include "laserfit/io/json.hpp"
#include "test_util.hpp"

namespace laserfit::test {

inline const std::string kSource = LASERFIT_SOURCE_DIR;

// A small USB scene (a coarse, short sweep: ~0.2 M points) so that a run takes seconds.
inline std::string tiny_benchmark(const TempDir& dir, int trials = 3,
                                  const std::string& extra = "") {
  write_text(
      dir / "scene.yaml",
      "objects:\n"
      "  - {name: usb_a_receptacle, mesh: " +
          kSource +
          "/cad/usb_a_receptacle.ply, pose: [500, 0, 100, 0, 1, 0, 0]}\n"
          "  - {name: usb_a_plug, mesh: " +
          kSource +
          "/cad/usb_a_plug.ply, pose: [500.4, -0.3, 106, 0, 0.99985, 0.01745, 0]}\n"
          "sweep:\n"
          "  center: {look_from: [455, -45, 166.64], look_at: [500, 0, 103], line: [1, -1, 0]}\n"
          "  direction: [0, 1, 0]\n  length_mm: 20\n  speed_mm_s: 50\n  profile_rate_hz: 1000\n");
  write_text(dir / "tiny.yaml",
             "name: tiny\nseed: 3\nmode: random\ntrials: " + std::to_string(trials) +
                 "\n"
                 "conditions: {noise_scale: [0.5, 2], rotation_deg: 10, translation_mm: 0.5}\n" +
                 extra +
                 "scenes:\n  - name: usb\n    scene: scene.yaml\n    targets:\n"
                 "      - {object: usb_a_receptacle, symmetry: none, reference_points: 20000}\n");
  return dir / "tiny.yaml";
}

inline std::vector<io::Json> without_timing(std::vector<io::Json> rs) {
  for (auto& r : rs) r.erase("timing");
  return rs;
}

inline bench::RunSettings quiet_run(const std::string& out) {
  bench::RunSettings s;
  s.out_dir = out;
  s.progress = false;
  s.jobs = 2;
  return s;
}

}  // namespace laserfit::test
