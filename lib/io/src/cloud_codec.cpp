#include "cloud_codec.hpp"

#include <cstdint>
#include <cstring>

#include "laserfit/core/error.hpp"

namespace laserfit::io {
namespace {

constexpr char kMagic[8] = {'L', 'F', 'C', 'L', 'O', 'U', 'D', '1'};

template <typename T>
void put(std::string& out, const std::vector<T>& v) {
  const uint64_t n = v.size();
  out.append(reinterpret_cast<const char*>(&n), sizeof n);
  if (n > 0) out.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}

struct Reader {
  const std::string& in;
  const std::string& path;
  size_t at = 0;
  [[noreturn]] void fail(const std::string& what) const {
    throw Error(path, "the reader process answered garbage (" + what + ")");
  }
  void bytes(void* p, size_t n) {
    if (n == 0) return;  // an empty vector's data() may be null, which memcpy must not see
    if (n > in.size() - at) fail("truncated");
    std::memcpy(p, in.data() + at, n);
    at += n;
  }
  template <typename T>
  void get(std::vector<T>& v) {
    uint64_t n = 0;
    bytes(&n, sizeof n);
    if (n > (in.size() - at) / sizeof(T)) fail("a count exceeds the message");
    v.resize(static_cast<size_t>(n));
    bytes(v.data(), v.size() * sizeof(T));
  }
};

}  // namespace

std::string encode_cloud(const PointCloud& c) {
  std::string out(kMagic, sizeof kMagic);
  const int32_t grid[2] = {c.width, c.height};
  out.append(reinterpret_cast<const char*>(grid), sizeof grid);
  put(out, c.points);
  put(out, c.normals);
  put(out, c.labels);
  const std::vector<double> origin =
      c.sensor_origin
          ? std::vector<double>{c.sensor_origin->x(), c.sensor_origin->y(), c.sensor_origin->z()}
          : std::vector<double>{};
  put(out, origin);
  return out;
}

PointCloud decode_cloud(const std::string& bytes, const std::string& path) {
  Reader r{bytes, path};
  char magic[sizeof kMagic];
  r.bytes(magic, sizeof magic);
  if (std::memcmp(magic, kMagic, sizeof kMagic) != 0) r.fail("no magic");
  PointCloud c;
  int32_t grid[2];
  r.bytes(grid, sizeof grid);
  c.width = grid[0], c.height = grid[1];
  r.get(c.points);
  r.get(c.normals);
  r.get(c.labels);
  std::vector<double> origin;
  r.get(origin);
  if (!origin.empty()) {
    if (origin.size() != 3) r.fail("a sensor origin that is not x, y, z");
    c.sensor_origin = Eigen::Vector3d(origin[0], origin[1], origin[2]);
  }
  if (r.at != bytes.size()) r.fail("trailing bytes");
  const size_t n = c.points.size();
  if (n == 0 || c.width < 1 || c.height < 1 ||
      static_cast<uint64_t>(c.width) * static_cast<uint64_t>(c.height) != n)
    r.fail("a grid that does not hold its points");
  if ((!c.normals.empty() && c.normals.size() != n) || (!c.labels.empty() && c.labels.size() != n))
    r.fail("normals or labels not one per point");
  return c;
}

}  // namespace laserfit::io
