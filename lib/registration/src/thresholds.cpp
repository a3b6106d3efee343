#include "laserfit/registration/thresholds.hpp"

#include <cmath>
#include <sstream>

#include "laserfit/core/atomic_file.hpp"
#include "laserfit/io/yaml_reader.hpp"

namespace laserfit::registration {
namespace {

constexpr const char* kSchema = "laserfit.thresholds/1";

// Every tunable: YAML key, unit, the field, its valid range. One table for reading and writing.
struct Param {
  const char* key;
  const char* unit;
  double lo, hi;
};
const Param kParams[] = {
    {"voxel_scale", "1", 0.25, 4},
    {"feature_radius", "voxel", 2, 20},
    {"ransac_iterations", "count", 100, 1e7},
    {"max_correspondence", "voxel", 0.5, 20},
    {"rho_icp", "voxel^2", 1e-4, 10},
    {"rho_rot", "deg", 0.1, 180},
    {"max_rmse", "voxel", 0.01, 10},
    {"min_overlap", "fraction", 0, 1},
};

double* field(Thresholds& t, const std::string& key, double& iterations) {
  if (key == "voxel_scale") return &t.voxel_scale;
  if (key == "feature_radius") return &t.feature_radius_vox;
  if (key == "ransac_iterations") return &iterations;
  if (key == "max_correspondence") return &t.max_correspondence_vox;
  if (key == "rho_icp") return &t.rho_icp_vox2;
  if (key == "rho_rot") return &t.rho_rot_deg;
  if (key == "max_rmse") return &t.max_rmse_vox;
  return &t.min_overlap;
}

double valued(const io::YamlReader& R, const YAML::Node& n, const std::string& where,
              const std::string& unit, double lo, double hi) {
  R.only(n, where, {"value", "unit"});
  R.need(n, "value", where);
  R.need(n, "unit", where);
  const std::string u = R.str(n, "unit", "", where);
  if (u != unit) R.fail(where + ".unit", "is '" + u + "', expected '" + unit + "'");
  const double v = R.num(n, "value", 0, where);
  if (v < lo || v > hi) {
    std::ostringstream m;
    m << "value " << v << " out of range [" << lo << ", " << hi << "] " << unit;
    R.fail(where, m.str());
  }
  return v;
}

}  // namespace

void Thresholds::apply(RegistrationSettings& s, const std::string& object,
                       double fallback_voxel_mm) const {
  const auto v = voxel_mm.find(object);
  const double voxel = v != voxel_mm.end() ? v->second : fallback_voxel_mm;
  s.pre.voxel_mm = voxel > 0 ? voxel * voxel_scale : 0;
  apply_method(s, method);
  s.coarse.feature_radius_vox = feature_radius_vox;
  s.coarse.ransac_iterations = ransac_iterations;
  s.refine.max_correspondence_vox = max_correspondence_vox;
  s.rho_icp_vox2 = rho_icp_vox2;
  s.rho_rot_deg = rho_rot_deg;
  s.trust.max_rmse_vox = max_rmse_vox;
  s.trust.min_overlap = min_overlap;
}

static Thresholds load_thresholds_unguarded(const std::string& path) {
  const io::YamlReader R{path};
  const YAML::Node root = R.load();
  R.only(root, "thresholds", {"schema", "provenance", "registration", "objects"});
  R.need(root, "schema", "thresholds");
  const std::string schema = R.str(root, "schema", "", "thresholds");
  if (schema != kSchema)
    R.fail("schema", "is '" + schema + "', this laserfit reads '" + kSchema + "'");
  Thresholds t;
  const auto prov = R.need(root, "provenance", "thresholds");
  R.only(prov, "provenance", {"benchmark", "file", "digest", "seed", "train", "test", "held_out"});
  for (const char* k : {"benchmark", "file", "digest", "seed", "train", "test", "held_out"})
    R.need(prov, k, "provenance");
  t.benchmark = R.str(prov, "benchmark", "", "provenance");
  t.benchmark_file = R.str(prov, "file", "", "provenance");
  t.benchmark_digest = R.str(prov, "digest", "", "provenance");
  t.seed = R.seed(prov, "seed", 0, "provenance");
  t.train = R.str(prov, "train", "", "provenance");
  t.test = R.str(prov, "test", "", "provenance");
  const auto ho = prov["held_out"];
  R.only(ho, "provenance.held_out",
         {"registrations", "success_rate", "false_accepts", "median_translation_error"});
  for (const char* k :
       {"registrations", "success_rate", "false_accepts", "median_translation_error"})
    R.need(ho, k, "provenance.held_out");
  t.held_out_registrations =
      int(R.integer(ho, "registrations", 0, "provenance.held_out", 0, 1 << 30));
  t.held_out_false_accepts =
      int(R.integer(ho, "false_accepts", 0, "provenance.held_out", 0, 1 << 30));
  t.held_out_success_rate =
      valued(R, ho["success_rate"], "provenance.held_out.success_rate", "fraction", 0, 1);
  t.held_out_median_t_um = valued(R, ho["median_translation_error"],
                                  "provenance.held_out.median_translation_error", "um", 0, 1e6);

  const auto reg = R.need(root, "registration", "thresholds");
  std::set<std::string> keys = {"method"};
  for (const auto& p : kParams) keys.insert(p.key);
  R.only(reg, "registration", keys);
  for (const auto& k : keys) R.need(reg, k, "registration");
  try {
    t.method = parse_enum<Method>(R.str(reg, "method", "", "registration"));
  } catch (const Error& e) {
    R.fail("registration.method", e.what());
  }
  double iterations = 0;
  for (const auto& p : kParams)
    *field(t, p.key, iterations) =
        valued(R, reg[p.key], std::string("registration.") + p.key, p.unit, p.lo, p.hi);
  if (iterations != std::floor(iterations))
    R.fail("registration.ransac_iterations", "must be a whole number");
  t.ransac_iterations = int(iterations);

  const auto objs = R.need(root, "objects", "thresholds");
  if (!objs.IsMap()) R.fail("objects", "expected a mapping of object name to settings");
  for (const auto& kv : objs) {
    const std::string name = kv.first.as<std::string>(), where = "objects." + name;
    R.only(kv.second, where, {"voxel"});
    t.voxel_mm[name] =
        valued(R, R.need(kv.second, "voxel", where), where + ".voxel", "mm", 1e-4, 10);
  }
  return t;
}

std::string thresholds_yaml(const Thresholds& t) {
  std::ostringstream o;
  o.precision(10);
  auto val = [&](double v, const char* unit) {
    o << "{value: " << v << ", unit: \"" << unit << "\"}\n";
  };
  o << "# Registration thresholds tuned by `laserfit tune` (read by laserfit register "
       "--thresholds\n"
       "# and laserfit-controller). Every value carries its unit; voxel-relative values scale "
       "with\n"
       "# each object's voxel.\n";
  o << "schema: " << kSchema << "\n";
  o << "provenance:\n  benchmark: " << t.benchmark << "\n  file: \"" << t.benchmark_file
    << "\"\n  digest: \"" << t.benchmark_digest << "\"\n  seed: " << t.seed << "\n  train: \""
    << t.train << "\"\n  test: \"" << t.test
    << "\"\n  held_out:\n    registrations: " << t.held_out_registrations
    << "\n    false_accepts: " << t.held_out_false_accepts << "\n    success_rate: ";
  val(t.held_out_success_rate, "fraction");
  o << "    median_translation_error: ";
  val(t.held_out_median_t_um, "um");
  o << "registration:\n  method: " << name_of(t.method) << "\n";
  Thresholds copy = t;
  double iterations = t.ransac_iterations;
  for (const auto& p : kParams) {
    o << "  " << p.key << ": ";
    val(*field(copy, p.key, iterations), p.unit);
  }
  o << "objects:\n";
  if (t.voxel_mm.empty()) o << "  {}\n";
  for (const auto& [name, v] : t.voxel_mm) {
    o << "  " << name << ":\n    voxel: ";
    val(v, "mm");
  }
  return o.str();
}

void write_thresholds(const std::string& path, const Thresholds& t) {
  write_file_atomic(path, thresholds_yaml(t));
}

Thresholds load_thresholds(const std::string& path) {
  return io::guard_yaml(path, [&] { return load_thresholds_unguarded(path); });
}

}  // namespace laserfit::registration
