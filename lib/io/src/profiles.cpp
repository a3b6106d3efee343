#include "laserfit/io/profiles.hpp"

#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>

#include "laserfit/core/error.hpp"
#include "laserfit/core/input_file.hpp"
#include "laserfit/io/cloud_io.hpp"
#include "laserfit/io/header_check.hpp"
#include "laserfit/io/util.hpp"

namespace laserfit::io {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr size_t kMaxLine = 16u << 20;  // 16 MB: 100 000 points per profile, 2 x 80 characters

// Rows of numbers from a text file, one at a time, with the row number for error lines.
struct Rows {
  const std::string& path;
  std::ifstream in{path, std::ios::binary};
  size_t line = 0;
  bool header_allowed = true;  // one row of column names before the first row of numbers

  [[noreturn]] void fail(const std::string& what) const {
    throw Error(path, "row " + std::to_string(line) + ": " + what);
  }
  // The next line without its newline, read in chunks so that a hostile line costs at most
  // kMaxLine bytes; false at the end of the file.
  bool read_line(std::string& text) {
    text.clear();
    char chunk[1 << 16];
    for (;;) {
      in.getline(chunk, sizeof chunk);
      const auto n = static_cast<size_t>(in.gcount());
      if (in.eof()) {  // the last line, without a newline (or nothing left)
        text.append(chunk, n);
        return !text.empty();
      }
      if (in.fail()) {  // the chunk is full and the line goes on
        if (n == 0) fail("unreadable");
        text.append(chunk, n);
        if (text.size() > kMaxLine) fail("longer than 16 MB");
        in.clear();
        continue;
      }
      text.append(chunk, n - 1);  // gcount counted the newline
      return true;
    }
  }
  // The next row's numbers; false at the end of the file. NaN for an empty field or "nan".
  bool next(std::vector<double>& v) {
    std::string text;
    while (read_line(text)) {
      ++line;
      if (!text.empty() && text.back() == '\r') text.pop_back();
      if (text.find_first_not_of(" \t") == std::string::npos || text[0] == '#') continue;
      if (parse(text, v)) return header_allowed = false, true;
      if (!header_allowed) fail("not a row of numbers: '" + one_line(text.substr(0, 40)) + "'");
      header_allowed = false;  // column names, skipped once
    }
    return false;
  }
  bool parse(const std::string& text, std::vector<double>& v) const {
    v.clear();
    const bool fields = text.find_first_of(",;") != std::string::npos;
    const char* seps = fields ? ",;" : " \t";
    size_t at = 0;
    while (at <= text.size()) {
      size_t end = text.find_first_of(seps, at);
      if (end == std::string::npos) end = text.size();
      size_t b = text.find_first_not_of(" \t", at), e = end;
      while (e > at && (text[e - 1] == ' ' || text[e - 1] == '\t')) --e;
      if (b >= e) {
        if (fields) v.push_back(std::nan(""));  // an empty field: no measurement
      } else {
        double x = 0;
        const auto r = std::from_chars(text.data() + b, text.data() + e, x);
        if (r.ec != std::errc() || r.ptr != text.data() + e) return false;
        if (std::isinf(x)) fail("an infinite number");
        v.push_back(x);
      }
      at = end + 1;
    }
    return !v.empty();
  }
};

void check_size(const std::string& path, uint64_t width, uint64_t count) {
  if (width < 1 || width > 100'000) throw Error(path, "points per profile must be 1..100000");
  if (count == 0) throw Error(path, "no profiles");
  if (width * count > kMaxCloudPoints)
    throw Error(path, std::to_string(width * count) + " points: more than " +
                          std::to_string(kMaxCloudPoints));
}

// Appends one profile of 2 W values in the settings' layout, scaled to mm, to `p`.
void add_profile(const double* v, const ProfileFileSettings& s, double to_mm, Profiles& p) {
  for (int j = 0; j < p.width; ++j) {
    const bool blocks = s.layout == ProfileLayout::blocks;
    const double x = blocks ? v[j] : v[2 * j], z = blocks ? v[p.width + j] : v[2 * j + 1];
    const bool none = std::isnan(x) || std::isnan(z) || (s.zero_is_invalid && z == 0);
    p.xz.push_back(
        none ? Eigen::Vector2f(kNaN, kNaN)
             : Eigen::Vector2f(static_cast<float>(x * to_mm), static_cast<float>(z * to_mm)));
  }
  ++p.count;
}

Profiles read_csv(const std::string& path, const ProfileFileSettings& s) {
  Rows rows{path};
  Profiles p;
  p.width = s.width;
  std::vector<double> v;
  while (rows.next(v)) {
    if (p.width == 0) p.width = static_cast<int>(std::min<size_t>(v.size() / 2, 100'001));
    if (v.size() != 2 * size_t(p.width))
      rows.fail(std::to_string(v.size()) + " values, expected " + std::to_string(2 * p.width) +
                " (x and z of " + std::to_string(p.width) + " points)");
    check_size(path, p.width, uint64_t(p.count) + 1);
    add_profile(v.data(), s, unit_to_mm(s.unit), p);
  }
  check_size(path, p.width, p.count);
  return p;
}

Profiles read_binary(const std::string& path, const ProfileFileSettings& s) {
  if (s.width < 1)
    throw Error(path, "a binary profile file needs its points per profile (--width)");
  const size_t scalar = s.scalar == ProfileScalar::f32 ? 4 : 8, row = 2 * scalar * s.width;
  const uint64_t size = std::filesystem::file_size(path);
  if (size % row != 0)
    throw Error(path, std::to_string(size) + " bytes are not whole profiles of " +
                          std::to_string(row) + " bytes");
  check_size(path, s.width, size / row);
  std::ifstream in(path, std::ios::binary);
  std::vector<char> bytes(row);
  std::vector<double> v(2 * s.width);
  Profiles p;
  p.width = s.width;
  for (uint64_t i = 0; i < size / row; ++i) {
    if (!in.read(bytes.data(), static_cast<std::streamsize>(row)))
      throw Error(path, "cannot read profile " + std::to_string(i));
    for (size_t k = 0; k < v.size(); ++k) {
      if (scalar == 4) {
        float f;
        std::memcpy(&f, bytes.data() + 4 * k, 4);
        v[k] = f;
      } else {
        std::memcpy(&v[k], bytes.data() + 8 * k, 8);
      }
      if (std::isinf(v[k]))
        throw Error(path, "profile " + std::to_string(i) + ": an infinite number");
    }
    add_profile(v.data(), s, unit_to_mm(s.unit), p);
  }
  return p;
}

// An organized cloud in the sensor frame (laserfit scan --raw): y must be 0.
Profiles read_sensor_cloud(const std::string& path, const ProfileFileSettings& s) {
  const PointCloud c = read_cloud(path, s.unit);
  if (!c.organized()) throw Error(path, "not an organized cloud (one row per profile)");
  Profiles p;
  p.width = c.width, p.count = c.height;
  p.xz.reserve(c.size());
  for (size_t k = 0; k < c.size(); ++k) {
    const Eigen::Vector3f& q = c.points[k];
    if (q.allFinite() && std::abs(q.y()) > 1e-6f)
      throw Error(path, "point " + std::to_string(k) + " has y = " + std::to_string(q.y()) +
                            " mm: not profiles in the sensor frame (y = 0)");
    const bool none = !q.allFinite() || (s.zero_is_invalid && q.z() == 0);
    p.xz.push_back(none ? Eigen::Vector2f(kNaN, kNaN) : Eigen::Vector2f(q.x(), q.z()));
  }
  return p;
}

}  // namespace

Profiles read_profiles(const std::string& path, const ProfileFileSettings& s) {
  require_input_file(path);
  const std::string ext = lower_extension(path);
  if (ext == ".csv" || ext == ".txt") return read_csv(path, s);
  if (ext == ".bin") return read_binary(path, s);
  if (ext == ".pcd" || ext == ".ply") return read_sensor_cloud(path, s);
  throw Error(path, "unknown profile format '" + ext + "' (use .csv, .bin, .pcd or .ply)");
}

std::vector<Pose> read_pose_list(const std::string& path, Unit unit) {
  require_input_file(path);
  Rows rows{path};
  std::vector<Pose> poses;
  std::vector<double> v;
  const double to_mm = unit_to_mm(unit);
  while (rows.next(v)) {
    if (v.size() != 7 && v.size() != 16)
      rows.fail(std::to_string(v.size()) + " values, expected 7 (x y z qw qx qy qz) or 16 (4x4)");
    for (double x : v)
      if (std::isnan(x)) rows.fail("a pose with an empty or NaN value");
    char b[32];  // parse_pose checks the rotation; it reads text, written here exactly
    std::string row;
    for (double x : v) row += std::string(b, std::to_chars(b, b + sizeof b, x).ptr) + " ";
    Pose T = parse_pose(row, path + ": row " + std::to_string(rows.line));
    T.translation() *= to_mm;
    poses.push_back(T);
    if (poses.size() > kMaxCloudPoints) rows.fail("too many poses");
  }
  if (poses.empty()) throw Error(path, "no poses");
  return poses;
}

}  // namespace laserfit::io
