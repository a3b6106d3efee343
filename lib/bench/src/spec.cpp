#include "laserfit/bench/spec.hpp"

#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>

#include "laserfit/bench/checksum.hpp"
#include "laserfit/bench/recorded.hpp"
#include "laserfit/core/error.hpp"
#include "laserfit/io/yaml_reader.hpp"
#include "laserfit/registration/registration.hpp"

namespace laserfit::bench {

const std::vector<std::string>& axis_names() {
  static const std::vector<std::string> n = {
      "noise_scale",        "outlier_rate",         "rotation_deg",  "translation_mm",
      "prior_rotation_deg", "prior_translation_mm", "sweep_fraction"};
  return n;
}

double& axis(Conditions& c, const std::string& name) {
  double* f[] = {&c.noise_scale,    &c.outlier_rate,       &c.rotation_deg,
                 &c.translation_mm, &c.prior_rotation_deg, &c.prior_translation_mm,
                 &c.sweep_fraction};
  const auto& n = axis_names();
  for (size_t i = 0; i < n.size(); ++i)
    if (n[i] == name) return *f[i];
  throw Error("unknown condition '" + name + "'");
}
double axis(const Conditions& c, const std::string& name) {
  return axis(const_cast<Conditions&>(c), name);
}

namespace {

using io::YamlReader;

// The value of an enum named under `key` (`def` when absent); another name fails at `at` (the
// key's path) with the names it may take: "must be a, b or c".
template <class E>
E choice(const YamlReader& R, const YAML::Node& n, const std::string& key, E def,
         const std::string& where, const std::string& at) {
  if (!n[key]) return def;
  const std::string text = R.str(n, key, "", where);
  std::string all;
  const size_t count = std::size(EnumNames<E>::table);
  for (size_t i = 0; i < count; ++i) {
    const auto& [value, name] = EnumNames<E>::table[i];
    if (text == name) return value;
    all += (i == 0 ? "" : i + 1 == count ? " or " : ", ") + std::string(name);
  }
  R.fail(at, "must be " + all);
}

// Physically meaningful ranges of each axis (an impossible config is an error, not a NaN later).
void check_axis(const YamlReader& R, const std::string& name, double v) {
  const std::string where = "conditions." + name;
  if (name == "noise_scale" && !(v >= 0 && v <= 100)) R.fail(where, "must be in 0..100");
  if (name == "outlier_rate" && !(v >= -1 && v <= 0.5))
    R.fail(where, "must be in 0..0.5 (or -1: the scene's)");
  if ((name == "rotation_deg" || name == "prior_rotation_deg") && !(v >= -1 && v <= 180))
    R.fail(where, "must be in 0..180 deg");
  if ((name == "translation_mm" || name == "prior_translation_mm") && !(v >= -1 && v <= 100))
    R.fail(where, "must be in 0..100 mm");
  if (name == "sweep_fraction" && !(v > 0 && v <= 1)) R.fail(where, "must be in (0, 1]");
}

Target read_target(const YamlReader& R, const YAML::Node& t, const std::string& where,
                   const std::filesystem::path& dir) {
  R.only(t, where,
         {"object", "symmetry", "voxel_mm", "reference", "reference_mesh", "reference_points",
          "expect", "weak_rotation", "weak_translation", "pivot", "turn_about", "resample_view",
          "obj_id", "reference_cloud", "model", "label"});
  Target tg;
  R.need(t, "object", where);
  tg.object = R.str(t, "object", "", where);
  try {
    tg.symmetry = metrics::parse_symmetry(R.str(t, "symmetry", "none", where));
  } catch (const Error& e) {
    R.fail(where + ".symmetry", e.what());
  }
  tg.voxel_mm = R.num(t, "voxel_mm", 0, where);
  if (tg.voxel_mm < 0 || tg.voxel_mm > 10)
    R.fail(where + ".voxel_mm", "must be in 0..10 mm (0 = auto)");
  tg.reference = choice(R, t, "reference",
                        t["reference_cloud"] ? ReferenceSource::Cloud : ReferenceSource::View,
                        where, where + ".reference");
  auto path = [&](const char* key) {
    return t[key] ? (dir / R.str(t, key, "", where)).lexically_normal().string() : std::string();
  };
  tg.reference_mesh = path("reference_mesh");
  tg.reference_cloud = path("reference_cloud"), tg.model = path("model");
  if ((tg.reference == ReferenceSource::Cloud) != !tg.reference_cloud.empty())
    R.fail(where + ".reference_cloud", "is the file of reference: cloud (and only of it)");
  if (t["obj_id"]) tg.obj_id = int(R.integer(t, "obj_id", 0, where, 0, 1000000000));
  if (t["label"]) tg.label = int(R.integer(t, "label", 0, where, 0, 1000000));
  tg.reference_points = size_t(R.integer(t, "reference_points", 60000, where, 100, 10000000));
  tg.resample_view = R.flag(t, "resample_view", false, where);
  if (tg.resample_view && tg.reference != ReferenceSource::View)
    R.fail(where + ".resample_view", "needs reference: view");
  const std::string expect = R.str(t, "expect", "pose", where);
  if (expect != "pose" && expect != "failure") R.fail(where + ".expect", "must be pose or failure");
  tg.expect_failure = expect == "failure";
  tg.pivot = choice(R, t, "pivot", Pivot::Origin, where, where + ".pivot");
  if (t["turn_about"]) {
    const std::string a = R.str(t, "turn_about", "", where);
    if (a != "x" && a != "y" && a != "z")
      R.fail(where + ".turn_about", "must be x, y or z (the scene's frame)");
    tg.turn_about = registration::named_axis(a);
  }
  for (const char* key : {"weak_rotation", "weak_translation"}) {
    if (!t[key]) continue;
    const std::string a = R.str(t, key, "", where);
    if (a != "x" && a != "y" && a != "z")
      R.fail(where + "." + key, "must be x, y or z (object frame)");
    (std::string(key) == "weak_rotation" ? tg.weak_rotation : tg.weak_translation) =
        registration::named_axis(a);
  }
  if (tg.object.empty()) R.fail(where + ".object", "must name a scene object");
  return tg;
}

// What a simulated scene's target may not say, and a recorded scene's must.
void check_target_source(const YamlReader& R, const SceneCase& sc, const Target& t,
                         const std::string& where) {
  if (!sc.recorded()) {
    if (t.obj_id >= 0 || t.label >= 0 || !t.model.empty() || t.reference == ReferenceSource::Cloud)
      R.fail(where, "obj_id, label, model and reference: cloud belong to recorded scenes");
    return;
  }
  if (t.obj_id < 0) R.fail(where + ".obj_id", "a recorded scene's target needs its BOP obj_id");
  if (t.reference == ReferenceSource::View || t.resample_view || t.pivot != Pivot::Origin)
    R.fail(where + ".reference",
           "a recorded scene has no scanner model to view the part with: give reference_cloud, "
           "or reference: full with reference_mesh (and no resample_view or pivot)");
  if (t.reference == ReferenceSource::Full && t.reference_mesh.empty())
    R.fail(where + ".reference_mesh", "reference: full in a recorded scene samples this mesh");
}

SceneCase read_scene_case(const YamlReader& R, const YAML::Node& s, const std::string& where,
                          const std::filesystem::path& dir) {
  R.only(s, where, {"name", "scene", "recorded", "unit", "prior", "targets"});
  SceneCase sc;
  sc.name = R.str(s, "name", "", where);
  if (sc.name.empty()) R.fail(where + ".name", "missing");
  if (bool(s["scene"]) == bool(s["recorded"]))
    R.fail(where, "give either scene (simulated) or recorded (a folder of scans)");
  if (s["scene"]) sc.scene_path = (dir / R.str(s, "scene", "", where)).lexically_normal().string();
  if (s["recorded"]) {
    sc.recorded_dir = (dir / R.str(s, "recorded", "", where)).lexically_normal().string();
    try {
      sc.unit = parse_unit(R.str(s, "unit", "mm", where));
      if (sc.unit == Unit::Auto) throw Error("the unit must be stated, not guessed");
    } catch (const Error& e) {
      R.fail(where + ".unit", e.what());
    }
    sc.truth = read_scene_gt(sc.recorded_dir + "/scene_gt.json");
    const std::string prior = sc.recorded_dir + "/scene_prior.json";
    std::error_code ec;
    if ((sc.has_prior = std::filesystem::exists(prior, ec))) sc.prior = read_scene_gt(prior);
  } else if (s["unit"]) {
    R.fail(where + ".unit", "belongs to recorded scenes (a scan scene states its own units)");
  }
  const std::string prior = R.str(s, "prior", "cell", where);
  if (prior != "cell" && prior != "none") R.fail(where + ".prior", "must be cell or none");
  sc.use_prior = prior == "cell";
  const auto targets = R.need(s, "targets", where);
  if (!targets.IsSequence() || targets.size() == 0)
    R.fail(where + ".targets", "expected a non-empty list");
  for (size_t k = 0; k < targets.size(); ++k) {
    const std::string w = where + ".targets[" + std::to_string(k) + "]";
    sc.targets.push_back(read_target(R, targets[k], w, dir));
    check_target_source(R, sc, sc.targets.back(), w);
  }
  return sc;
}

}  // namespace

static Benchmark load_benchmark_unguarded(const std::string& path) {
  const YamlReader R{path};
  const YAML::Node root = R.load();
  R.only(root, "benchmark",
         {"name", "seed", "trials", "mode", "conditions", "tolerance", "methods", "scenes"});
  const auto dir = std::filesystem::path(path).parent_path();
  Benchmark b;
  b.file = path;
  R.need(root, "name", "benchmark");
  b.name = R.str(root, "name", "", "benchmark");
  if (b.name.empty() || b.name.find_first_of("/ \t") != std::string::npos)
    R.fail("name", "must be a non-empty word (it names datasets/<name>/)");
  b.seed = R.seed(root, "seed", 1, "benchmark");
  b.trials = int(R.integer(root, "trials", 10, "benchmark", 1, 1000000));
  b.mode = choice(R, root, "mode", Sampling::Grid, "benchmark", "mode");
  if (const auto c = root["conditions"]) {
    std::set<std::string> names(axis_names().begin(), axis_names().end());
    R.only(c, "conditions", names);
    for (const auto& kv : c) {
      const auto k = kv.first.as<std::string>();
      std::vector<double> v = kv.second.IsSequence()
                                  ? R.list(kv.second, "conditions." + k)
                                  : std::vector<double>{R.num(c, k, 0, "conditions")};
      if (v.empty()) R.fail("conditions." + k, "needs at least one value");
      if (b.mode == Sampling::Random && v.size() != 2 && v.size() != 1)
        R.fail("conditions." + k, "random mode: a value or a [min, max] range");
      if (b.mode == Sampling::Random && v.size() == 2 && v[0] > v[1])
        R.fail("conditions." + k, "min above max");
      for (double x : v) check_axis(R, k, x);
      b.axes[k] = v;
    }
  }
  if (const auto t = root["tolerance"]) {
    R.numbers(t, "tolerance", {{"translation_mm", &b.t_tol_mm}, {"rotation_deg", &b.r_tol_deg}});
    if (!(b.t_tol_mm > 0) || !(b.r_tol_deg > 0)) R.fail("tolerance", "must be positive");
  }
  if (const auto m = root["methods"]) {
    if (!m.IsSequence() || m.size() == 0)
      R.fail("methods", "expected a non-empty list of method names");
    b.methods.clear();
    for (const auto& x : m) try {
        b.methods.push_back(parse_enum<registration::Method>(x.as<std::string>()));
      } catch (const Error& e) {
        R.fail("methods", e.what());
      }
  }
  const auto scenes = R.need(root, "scenes", "benchmark");
  if (!scenes.IsSequence() || scenes.size() == 0) R.fail("scenes", "expected a non-empty list");
  for (size_t i = 0; i < scenes.size(); ++i) {
    const std::string where = "scenes[" + std::to_string(i) + "]";
    const auto& s = scenes[i];
    SceneCase sc = read_scene_case(R, s, where, dir);
    for (const auto& other : b.scenes)
      if (other.name == sc.name) R.fail(where + ".name", "duplicate scene name '" + sc.name + "'");
    b.scenes.push_back(sc);
  }
  bool simulated = false;
  for (const auto& sc : b.scenes) simulated |= !sc.recorded();
  if (!simulated && !b.axes.empty())
    R.fail("conditions", "apply to simulated scenes; every scene here is recorded");
  // The run's identity: this file, and the ground truth of its recorded scenes (a corrected
  // scene_gt.json is another run; the scans are not hashed, they can be gigabytes).
  auto bytes = [](const std::string& file) {
    std::ifstream in(file, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  std::string all = bytes(path);
  for (const auto& sc : b.scenes)
    if (sc.recorded())
      all +=
          bytes(sc.recorded_dir + "/scene_gt.json") + bytes(sc.recorded_dir + "/scene_prior.json");
  b.digest = crc32(all);
  return b;
}

std::vector<int> scene_indices(const Benchmark& b, const std::vector<std::string>& names) {
  std::vector<int> idx;
  if (names.empty())
    for (size_t i = 0; i < b.scenes.size(); ++i) idx.push_back(int(i));
  std::string known;
  for (const auto& sc : b.scenes) known += (known.empty() ? "" : ", ") + sc.name;
  for (const auto& n : names) {
    size_t i = 0;
    while (i < b.scenes.size() && b.scenes[i].name != n) ++i;
    if (i == b.scenes.size())
      throw Error(b.file, "no scene named '" + n + "' (scenes: " + known + ")");
    idx.push_back(int(i));
  }
  return idx;
}

Benchmark load_benchmark(const std::string& path) {
  return io::guard_yaml(path, [&] { return load_benchmark_unguarded(path); });
}

}  // namespace laserfit::bench
