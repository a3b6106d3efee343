#include "laserfit/scan/ground_truth.hpp"

namespace laserfit::scan {
namespace {
io::Json tq(const Pose& T) {
  const auto v = pose_to_tq(T);
  return io::Json(std::vector<double>(v.begin(), v.end()));
}
}  // namespace

io::Json settings_json(const ScanSettings& s) {
  const auto& g = s.sensor;
  const auto& n = s.noise;
  const auto& m = s.motion;
  return {{"sensor",
           {{"points_per_profile", g.points_per_profile},
            {"z_min_mm", g.z_min_mm},
            {"z_max_mm", g.z_max_mm},
            {"width_mid_mm", g.width_mid_mm},
            {"triangulation_angle_deg", g.triangulation_angle_deg},
            {"max_incidence_deg", g.max_incidence_deg},
            {"max_camera_angle_deg", g.max_camera_angle_deg},
            {"baseline_mm", g.baseline_mm()},
            {"pitch_mid_mm", g.pitch_mid_mm()}}},
          {"sweep",
           {{"start", tq(s.sweep.T_base_sensor_start)},
            {"direction", {s.sweep.direction.x(), s.sweep.direction.y(), s.sweep.direction.z()}},
            {"length_mm", s.sweep.length_mm},
            {"speed_mm_s", s.sweep.speed_mm_s},
            {"profile_rate_hz", s.sweep.profile_rate_hz},
            {"spacing_mm", s.sweep.spacing_mm()},
            {"profiles", s.sweep.profiles()}}},
          {"noise",
           {{"enabled", n.enabled},
            {"depth_sigma_um", n.depth_sigma_um},
            {"x_jitter_um", n.x_jitter_um},
            {"z_quantum_um", n.z_quantum_um},
            {"speckle_sigma_um", n.speckle_sigma_um},
            {"speckle_corr_um", n.speckle_corr_um},
            {"dropout_rate", n.dropout_rate},
            {"grazing_start_deg", n.grazing_start_deg},
            {"mixed_pixel_prob", n.mixed_pixel_prob},
            {"mixed_pixel_jump_mm", n.mixed_pixel_jump_mm},
            {"outlier_rate", n.outlier_rate},
            {"outlier_max_mm", n.outlier_max_mm},
            {"bias_sigma_um", n.bias_sigma_um}}},
          {"motion",
           {{"enabled", m.enabled},
            {"offset_sigma_mm", m.offset_sigma_mm},
            {"offset_sigma_deg", m.offset_sigma_deg},
            {"jitter_sigma_mm", m.jitter_sigma_mm},
            {"jitter_sigma_deg", m.jitter_sigma_deg},
            {"jitter_corr_profiles", m.jitter_corr_profiles},
            {"calibration_error", m.calibration_error}}}};
}

io::Json ground_truth_json(const ScanScene& sc, const ScanResult& r) {
  io::Json objects = io::Json::array();
  for (size_t i = 0; i < sc.objects.size(); ++i)
    objects.push_back({{"name", sc.objects[i].name},
                       {"label", i},
                       {"mesh", sc.objects[i].mesh_path},
                       {"shiny", sc.objects[i].shiny},
                       {"T_base_object", io::pose_to_json(sc.objects[i].T_base_object)},
                       {"T_scan_object", io::pose_to_json(r.T_scan_object[i])}});
  io::Json nominal = io::Json::array(), truth = io::Json::array();
  for (const auto& T : r.T_base_sensor_nominal) nominal.push_back(tq(T));
  for (const auto& T : r.T_base_sensor_true) truth.push_back(tq(T));
  const auto& s = r.stats;
  io::Json j{{"laserfit_ground_truth", 1},
             {"unit", "mm"},
             {"pose_format", "[x, y, z, qw, qx, qy, qz]"},
             {"scene", sc.file},
             {"seed", r.seed},
             {"width", r.cloud.width},
             {"height", r.cloud.height},
             {"objects", objects},
             {"settings", settings_json(sc.settings)},
             {"stats",
              {{"rays", s.rays},
               {"hits", s.hits},
               {"valid", s.valid},
               {"out_of_range", s.out_of_range},
               {"grazing", s.grazing},
               {"camera_shadow", s.camera_shadow},
               {"dropouts", s.dropouts},
               {"outliers", s.outliers},
               {"mixed_pixels", s.mixed_pixels}}},
             {"T_base_sensor_nominal", nominal},
             {"T_base_sensor_true", truth}};
  return j;
}

}  // namespace laserfit::scan
