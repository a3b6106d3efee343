#include "campaign.hpp"

#include <yaml-cpp/yaml.h>

#include <filesystem>

#include "laserfit/core/error.hpp"

namespace laserfit::campaign {

Campaign load_campaign(const std::string& path) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const std::exception& e) {
    throw Error(path, std::string("not a readable YAML file: ") + e.what());
  }
  const auto dir = std::filesystem::path(path).parent_path();
  Campaign c;
  try {
    c.seed = root["seed"].as<uint64_t>(c.seed);
    c.trials = root["trials"].as<int>(c.trials);
    if (const auto p = root["perturbation"]) {
      c.rotation_deg = p["rotation_deg"].as<double>(c.rotation_deg);
      c.translation_mm = p["translation_mm"].as<double>(c.translation_mm);
    }
    if (const auto t = root["tolerance"]) {
      c.t_tol_mm = t["translation_mm"].as<double>(c.t_tol_mm);
      c.r_tol_deg = t["rotation_deg"].as<double>(c.r_tol_deg);
    }
    for (const auto& s : root["scenes"]) {
      SceneCase sc;
      sc.name = s["name"].as<std::string>();
      sc.scene_path = (dir / s["scene"].as<std::string>()).lexically_normal().string();
      for (const auto& t : s["targets"]) {
        Target tg;
        tg.object = t["object"].as<std::string>();
        tg.symmetry = metrics::parse_symmetry(t["symmetry"].as<std::string>("none"));
        tg.voxel_mm = t["voxel_mm"].as<double>(0);
        tg.reference = t["reference"].as<std::string>("view");
        tg.reference_points = t["reference_points"].as<size_t>(60000);
        if (tg.reference != "view" && tg.reference != "full") throw Error("reference must be view or full");
        sc.targets.push_back(tg);
      }
      c.scenes.push_back(sc);
    }
  } catch (const YAML::Exception& e) {
    throw Error(path, e.what());
  } catch (const Error& e) {
    throw Error(path, e.what());
  }
  if (c.trials < 1 || c.scenes.empty() || !(c.rotation_deg >= 0) || !(c.translation_mm >= 0))
    throw Error(path, "needs trials >= 1, at least one scene, non-negative perturbations");
  return c;
}

registration::RegistrationSettings method_settings(const std::string& method) {
  registration::RegistrationSettings s;
  if (method == "paper") {
    s.coarse.method = "pcl";
    s.refine.method = "paper";
    return s;
  }
  s.refine.method = method;  // validated by the registration itself
  return s;
}

}  // namespace laserfit::campaign
