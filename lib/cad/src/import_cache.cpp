// import_cad memoised by content: the key is a 64-bit FNV-1a hash of the file's bytes, its size
// and every setting that changes the result (not the reader's limits: a result is a result).
// File times are not trusted for this: the kernel stamps them at a few milliseconds' resolution,
// and a file rewritten within that tick would hand back the old mesh.
#include <cstdint>
#include <deque>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>

#include "laserfit/cad/import.hpp"

namespace laserfit::cad {
namespace {

constexpr size_t kEntries = 32;

// The file's bytes hashed; "" when it is not a regular file of at most 1 GiB (a device or a pipe
// could be read forever; import_cad refuses those itself).
std::string content_key(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec) ||
      std::filesystem::file_size(path, ec) > (size_t(1) << 30) || ec)
    return {};
  std::ifstream in(path, std::ios::binary);
  if (!in) return {};
  uint64_t h = 1469598103934665603ull, size = 0;
  char buf[1 << 16];
  while (in.read(buf, sizeof buf) || in.gcount() > 0) {
    const auto n = static_cast<size_t>(in.gcount());
    for (size_t i = 0; i < n; ++i) h = (h ^ static_cast<unsigned char>(buf[i])) * 1099511628211ull;
    size += n;
  }
  std::ostringstream k;
  k << path << '\n' << size << '\n' << h;
  return k.str();
}

std::string settings_key(const ImportSettings& s) {
  std::ostringstream k;
  k.precision(17);
  k << unit_name(s.unit) << ' ' << s.deflection_mm << ' ' << s.angular_deflection_rad << ' '
    << s.part << ' ' << s.repair.repair << s.repair.fill_holes << s.repair.check_self_intersections
    << ' ' << s.max_triangles;
  return k.str();
}

struct Cache {
  std::mutex m;
  std::map<std::string, ImportResult> results;
  std::deque<std::string> order;  // oldest first
};

Cache& cache() {
  static Cache c;
  return c;
}

}  // namespace

ImportResult import_cad(const std::string& path, const ImportSettings& s) {
  const std::string content = content_key(path);
  if (content.empty()) return import_cad_uncached(path, s);
  const std::string key = content + '\n' + settings_key(s);
  Cache& c = cache();
  {
    std::lock_guard<std::mutex> l(c.m);
    const auto it = c.results.find(key);
    if (it != c.results.end()) return it->second;
  }
  ImportResult r = import_cad_uncached(path, s);
  std::lock_guard<std::mutex> l(c.m);
  if (c.results.emplace(key, r).second) c.order.push_back(key);
  while (c.order.size() > kEntries) c.results.erase(c.order.front()), c.order.pop_front();
  return r;
}

}  // namespace laserfit::cad
