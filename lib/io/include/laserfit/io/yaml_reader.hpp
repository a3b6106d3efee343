#pragma once
// Strict YAML reading shared by every configuration file (scenes, benchmarks, thresholds): an
// unknown key is an error (a typo must not silently fall back to a default), and every problem
// is reported as "<file>: <where>: <what>".
#include <yaml-cpp/yaml.h>

#include <charconv>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <ios>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "laserfit/core/error.hpp"
#include "laserfit/core/input_file.hpp"
#include "laserfit/core/pose.hpp"

namespace laserfit::io {

struct YamlReader {
  std::string file;

  [[noreturn]] void fail(const std::string& where, const std::string& what) const {
    throw Error(file, where + ": " + what);
  }
  void only(const YAML::Node& n, const std::string& where, std::set<std::string> keys) const {
    if (!n.IsMap()) fail(where, "expected a mapping");
    for (const auto& kv : n) {
      if (!kv.first.IsScalar()) fail(where, "a key that is not a plain name");
      const auto k = kv.first.as<std::string>();
      if (!keys.count(k)) fail(where, "unknown key '" + k + "'");
    }
  }
  double num(const YAML::Node& n, const std::string& key, double def,
             const std::string& where) const {
    if (!n[key]) return def;
    try {
      const double v = n[key].as<double>();
      if (!std::isfinite(v)) fail(where + "." + key, "not a finite number");
      return v;
    } catch (const YAML::Exception&) {
      fail(where + "." + key, "not a number");
    }
  }
  // A whole number in [lo, hi].
  long long integer(const YAML::Node& n, const std::string& key, long long def,
                    const std::string& where, long long lo, long long hi) const {
    const double v = num(n, key, double(def), where);
    if (v != std::floor(v) || v < double(lo) || v > double(hi))
      fail(where + "." + key,
           "must be a whole number in " + std::to_string(lo) + ".." + std::to_string(hi));
    return static_cast<long long>(v);
  }
  // A random seed: a whole number 0..2^64-1, read from its digits (a double would round seeds
  // above 2^53 and overflow the cast above 2^64).
  uint64_t seed(const YAML::Node& n, const std::string& key, uint64_t def,
                const std::string& where) const {
    if (!n[key]) return def;
    if (!n[key].IsScalar()) fail(where + "." + key, "expected a whole number");
    const std::string t = n[key].Scalar();
    uint64_t v = 0;
    const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    if (ec != std::errc() || end != t.data() + t.size())
      fail(where + "." + key, "must be a whole number from 0 to 18446744073709551615");
    return v;
  }
  std::string str(const YAML::Node& n, const std::string& key, const std::string& def,
                  const std::string& where) const {
    if (!n[key]) return def;
    if (!n[key].IsScalar()) fail(where + "." + key, "expected a string");
    return n[key].as<std::string>();
  }
  // A required key: missing -> "<where>: missing key '<key>'".
  const YAML::Node need(const YAML::Node& n, const std::string& key,
                        const std::string& where) const {
    if (!n[key]) fail(where, "missing key '" + key + "'");
    return n[key];
  }
  // A block of numeric settings: the table names the accepted keys and the fields they fill, so
  // the key list is never written twice. `extra` are further keys the caller reads itself.
  using Fields = std::initializer_list<std::pair<const char*, double*>>;
  void numbers(const YAML::Node& n, const std::string& where, Fields fields,
               std::set<std::string> extra = {}) const {
    for (const auto& f : fields) extra.insert(f.first);
    only(n, where, extra);
    for (const auto& [key, field] : fields) *field = num(n, key, *field, where);
  }
  bool flag(const YAML::Node& n, const std::string& key, bool def, const std::string& where) const {
    if (!n[key]) return def;
    try {
      return n[key].as<bool>();
    } catch (const YAML::Exception&) {
      fail(where + "." + key, "expected true or false");
    }
  }
  std::vector<double> list(const YAML::Node& n, const std::string& where) const {
    if (!n.IsSequence()) fail(where, "expected a list of numbers");
    std::vector<double> v;
    try {
      for (const auto& x : n) v.push_back(x.as<double>());
    } catch (const YAML::Exception&) {
      fail(where, "expected a list of numbers");
    }
    for (double x : v)
      if (!std::isfinite(x)) fail(where, "not a finite number");
    return v;
  }
  Pose pose(const YAML::Node& n, const std::string& where) const {
    std::ostringstream s;
    s.precision(17);
    for (double x : list(n, where)) s << x << ' ';
    try {
      return parse_pose(s.str(), where);
    } catch (const Error& e) {
      throw Error(file, e.what());
    }
  }
  // The whole file; unreadable or not YAML -> one clear error naming it.
  YAML::Node load() const {
    try {
      const YAML::Node root = YAML::LoadFile(file);
      if (!root.IsMap()) throw Error(file, "expected a YAML mapping at the top level");
      return root;
    } catch (const YAML::BadFile&) {
      throw Error(file, "cannot read the file");
    } catch (const YAML::Exception& e) {
      throw Error(file, std::string("not valid YAML: ") + e.what());
    }
  }
};

// Runs a loader and turns any yaml-cpp exception it lets through (a list where a name was
// expected, a conversion that does not apply) into laserfit's one-line error naming the file:
// a configuration file is user input, and no shape of it may end the program another way.
template <typename F>
auto guard_yaml(const std::string& file, F&& load) -> decltype(load()) {
  std::error_code ec;  // a folder or a device named as a file: refused before yaml-cpp reads it
  if (std::filesystem::exists(file, ec) && !std::filesystem::is_regular_file(file, ec))
    throw Error(file, "not a regular file");
  try {
    return load();
  } catch (const YAML::Exception& e) {
    throw Error(file, std::string("not a valid file: ") + e.what());
  } catch (const std::ios_base::failure& e) {
    throw Error(file, std::string("cannot read the file: ") + e.what());
  } catch (const std::filesystem::filesystem_error& e) {
    // A path the file names (a cell's scene, a scene's mesh) that the OS refuses: too long, a loop.
    throw Error(file, "cannot use the path '" + shown_path(e.path1().string()) +
                          "': " + e.code().message());
  }
}

}  // namespace laserfit::io
