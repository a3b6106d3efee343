#include "laserfit/io/header_check.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <vector>

#include "laserfit/core/error.hpp"
#include "off_header.hpp"

namespace laserfit::io {
namespace {

constexpr size_t kMaxHeaderLines = 10000, kMaxLine = 65536, kMaxFields = 1024;

// A whole non-negative integer of at most 15 digits (no sign, no exponent, no trailing text).
bool parse_count(const std::string& s, size_t& out) {
  if (s.empty() || s.size() > 15) return false;
  out = 0;
  for (char c : s) {
    if (c < '0' || c > '9') return false;
    out = out * 10 + static_cast<size_t>(c - '0');
  }
  return true;
}

std::vector<std::string> words(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> w;
  for (std::string s; in >> s;) w.push_back(s);
  return w;
}

struct Lines {
  std::ifstream in;
  const std::string& path;
  size_t count = 0;
  bool next(std::string& line) {
    if (!std::getline(in, line)) return false;
    if (++count > kMaxHeaderLines) throw Error(path, "header longer than 10000 lines");
    if (line.size() > kMaxLine) throw Error(path, "header line longer than 64 KiB");
    if (!line.empty() && line.back() == '\r') line.pop_back();
    return true;
  }
};

size_t count_field(const std::string& path, const std::vector<std::string>& w) {
  size_t n = 0;
  if (w.size() != 2 || !parse_count(w[1], n)) throw Error(path, "bad " + w[0] + " line");
  return n;
}

// Bytes of one point of a PCD file: SIZE x COUNT over the FIELDS, all lists of one length.
size_t pcd_point_step(const std::string& path,
                      const std::map<std::string, std::vector<std::string>>& h) {
  const size_t n = h.at("FIELDS").size() - 1;
  if (n == 0 || n > kMaxFields) throw Error(path, "FIELDS lists no or too many fields");
  for (const char* key : {"SIZE", "TYPE", "COUNT"}) {
    const auto it = h.find(key);
    if (it == h.end() && std::strcmp(key, "COUNT") == 0) continue;
    if (it == h.end()) throw Error(path, std::string("PCD header has no ") + key);
    if (it->second.size() - 1 != n)
      throw Error(path, std::string(key) + " lists " + std::to_string(it->second.size() - 1) +
                            " entries for " + std::to_string(n) + " fields");
  }
  size_t step = 0;
  for (size_t i = 1; i <= n; ++i) {
    size_t size = 0, count = 1;
    const std::string& type = h.at("TYPE")[i];
    if (!parse_count(h.at("SIZE")[i], size) || (size != 1 && size != 2 && size != 4 && size != 8))
      throw Error(path, "SIZE entries must be 1, 2, 4 or 8");
    if (type != "F" && type != "I" && type != "U")
      throw Error(path, "TYPE entries must be F, I or U");
    if (type == "F" && size != 4 && size != 8)
      throw Error(path, "a float field of size " + h.at("SIZE")[i]);
    if (h.count("COUNT") &&
        (!parse_count(h.at("COUNT")[i], count) || count == 0 || count > 1'000'000))
      throw Error(path, "COUNT entries must be 1 to 1000000");
    step += size * count;
  }
  if (step > (1u << 20)) throw Error(path, "points of more than 1 MiB each");
  return step;
}

void check_points(const std::string& path, size_t points, size_t limit = kMaxCloudPoints,
                  const char* what = "points") {
  if (points > limit)
    throw Error(path, "header claims " + std::to_string(points) + " " + what +
                          ", more than the limit of " + std::to_string(limit));
}

void check_pcd(const std::string& path, size_t file_size) {
  Lines lines{std::ifstream(path, std::ios::binary), path};
  std::map<std::string, std::vector<std::string>> h;
  std::string line;
  while (lines.next(line)) {
    if (line.empty() || line[0] == '#') continue;
    const auto w = words(line);
    if (w.empty()) continue;
    static const char* kKeys[] = {"VERSION", "FIELDS", "SIZE",      "TYPE",   "COUNT",
                                  "WIDTH",   "HEIGHT", "VIEWPOINT", "POINTS", "DATA"};
    if (std::find_if(std::begin(kKeys), std::end(kKeys),
                     [&](const char* k) { return w[0] == k; }) == std::end(kKeys))
      throw Error(path, "not a PCD file (unexpected header line '" + line.substr(0, 40) + "')");
    if (h.count(w[0])) throw Error(path, "PCD header repeats " + w[0]);
    h[w[0]] = w;
    if (w[0] == "DATA") break;
  }
  for (const char* key : {"FIELDS", "WIDTH", "POINTS", "DATA"})
    if (!h.count(key))
      throw Error(path, "PCD header incomplete (needs FIELDS, WIDTH, POINTS and DATA)");
  const size_t step = pcd_point_step(path, h);
  const size_t width = count_field(path, h["WIDTH"]);
  const size_t height = h.count("HEIGHT") ? count_field(path, h["HEIGHT"]) : 1;
  const size_t points = count_field(path, h["POINTS"]);
  check_points(path, points);
  if (height == 0 || width > kMaxCloudPoints || width * height != points)
    throw Error(path, "WIDTH x HEIGHT does not equal POINTS");
  if (h.count("VIEWPOINT") && h["VIEWPOINT"].size() != 8)
    throw Error(path, "VIEWPOINT needs 7 numbers (x y z qw qx qy qz)");
  const auto& data = h["DATA"];
  if (data.size() != 2) throw Error(path, "bad DATA line");
  const std::streamoff at = lines.in.tellg();
  const size_t left = at < 0 ? 0 : file_size - static_cast<size_t>(at);
  if (data[1] == "ascii") {
    if (points > left / 2) throw Error(path, "truncated: fewer ascii lines than POINTS");
  } else if (data[1] == "binary") {
    if (points * step > left) throw Error(path, "truncated: binary data shorter than POINTS");
  } else if (data[1] == "binary_compressed") {
    uint32_t sizes[2] = {0, 0};  // compressed, uncompressed
    if (left < 8 || !lines.in.read(reinterpret_cast<char*>(sizes), 8))
      throw Error(path, "truncated: no compressed block");
    // LZF expands at most ~88x (a 264-byte back-reference in 3 bytes).
    if (sizes[0] > left - 8 || sizes[1] != points * step || sizes[1] > 100.0 * sizes[0] + 1024)
      throw Error(path, "compressed block sizes do not match the header or the file");
  } else {
    throw Error(path, "DATA must be ascii, binary or binary_compressed");
  }
}

size_t ply_type_size(const std::string& t) {
  static const std::map<std::string, size_t> kSizes = {
      {"char", 1},  {"uchar", 1},   {"int8", 1},   {"uint8", 1},  {"short", 2}, {"ushort", 2},
      {"int16", 2}, {"uint16", 2},  {"int", 4},    {"uint", 4},   {"int32", 4}, {"uint32", 4},
      {"float", 4}, {"float32", 4}, {"double", 8}, {"float64", 8}};
  const auto it = kSizes.find(t);
  return it == kSizes.end() ? 0 : it->second;
}

void check_ply(const std::string& path, size_t file_size, size_t limit, const char* what) {
  Lines lines{std::ifstream(path, std::ios::binary), path};
  std::string line;
  if (!lines.next(line) || line != "ply") throw Error(path, "not a PLY file (no 'ply' magic)");
  std::string format;
  size_t min_bytes = 0, elements_count = 0, element_count = 0;  // a lower bound of the body's size
  size_t cols = 0, rows = 0, vertices = 0;  // PCL's organized-cloud convention (obj_info)
  bool ended = false, organized = false;
  while (!ended && lines.next(line)) {
    const auto w = words(line);
    if (w.size() == 3 && w[0] == "obj_info" && (w[1] == "num_cols" || w[1] == "num_rows")) {
      if (!parse_count(w[2], w[1] == "num_cols" ? cols : rows))
        throw Error(path, "bad obj_info " + w[1] + " line");
      organized = true;
    }
    if (w.empty() || w[0] == "comment" || w[0] == "obj_info") continue;
    if (w[0] == "format") {
      if (w.size() != 3 ||
          (w[1] != "ascii" && w[1] != "binary_little_endian" && w[1] != "binary_big_endian"))
        throw Error(path, "bad PLY format line");
      format = w[1];
    } else if (w[0] == "element") {
      if (w.size() != 3 || !parse_count(w[2], element_count)) throw Error(path, "bad element line");
      check_points(path, element_count, limit, what);
      if (w[1] == "vertex") vertices = element_count;
      if (++elements_count > kMaxFields) throw Error(path, "too many PLY elements");
    } else if (w[0] == "property") {
      if (elements_count == 0) throw Error(path, "a PLY property before any element");
      const bool list = w.size() == 5 && w[1] == "list";
      if (!(list ? ply_type_size(w[2]) && ply_type_size(w[3])
                 : w.size() == 3 && ply_type_size(w[1])))
        throw Error(path, "bad PLY property line '" + line.substr(0, 60) + "'");
      // At least the list's count (binary) or one character and a separator (ascii) per row.
      const size_t row = format == "ascii" ? 2 : ply_type_size(list ? w[2] : w[1]);
      min_bytes += element_count * row;
    } else if (w[0] == "end_header") {
      ended = true;
    } else {
      throw Error(path, "unexpected PLY header line '" + line.substr(0, 40) + "'");
    }
  }
  if (!ended) throw Error(path, "PLY header has no end_header (truncated or corrupt)");
  if (format.empty()) throw Error(path, "PLY header has no format line");
  // PCL asserts (aborts) when an organized PLY's grid does not hold its vertices.
  if (organized && (cols > vertices || rows > vertices || cols * rows != vertices))
    throw Error(path, "obj_info num_cols x num_rows (" + std::to_string(cols) + " x " +
                          std::to_string(rows) + ") does not equal the " +
                          std::to_string(vertices) + " vertices");
  const std::streamoff at = lines.in.tellg();
  const size_t left = at < 0 ? 0 : file_size - static_cast<size_t>(at);
  if (min_bytes > left)
    throw Error(path, "truncated: the data is shorter than the header announces");
}

}  // namespace

void check_cloud_header(const std::string& path, const std::string& ext) {
  const size_t size = std::filesystem::file_size(path);
  if (ext == ".ply")
    check_ply(path, size, kMaxCloudPoints, "points");
  else
    check_pcd(path, size);
}

void check_mesh_header(const std::string& path, const std::string& ext, size_t max_elements) {
  const size_t size = std::filesystem::file_size(path);
  if (ext == ".ply") return check_ply(path, size, max_elements, "vertices or faces");
  if (ext == ".off") return check_off_header(path, size, max_elements);
  if (ext != ".stl") return;
  std::ifstream in(path, std::ios::binary);
  char head[84] = {};
  in.read(head, sizeof head);
  if (in.gcount() < 84) return;  // too short for binary STL: ASCII or garbage, for the parser
  uint32_t n = 0;
  std::memcpy(&n, head + 80, 4);
  // An ASCII STL starts with "solid" too; only a file whose size fits the count is binary.
  if (std::strncmp(head, "solid", 5) == 0 && size != 84 + 50ull * n) return;
  check_points(path, n, max_elements, "triangles");
  if (size < 84 + 50ull * n)
    throw Error(path, "truncated binary STL: " + std::to_string(n) + " triangles need " +
                          std::to_string(84 + 50ull * n) + " bytes, the file has " +
                          std::to_string(size));
}

}  // namespace laserfit::io
