#include <cmath>
#include <vector>

#include "laserfit/core/atomic_file.hpp"
#include "laserfit/core/error.hpp"
#include "laserfit/io/cloud_io.hpp"
#include "laserfit/io/util.hpp"

namespace laserfit::io {
namespace {

// Interleaved x y z [nx ny nz] rows, the on-disk layout of both formats.
std::vector<float> interleave(const PointCloud& c) {
  const int stride = c.has_normals() ? 6 : 3;
  std::vector<float> buf(c.size() * stride);
  for (size_t i = 0; i < c.size(); ++i) {
    std::copy_n(c.points[i].data(), 3, &buf[i * stride]);
    if (c.has_normals()) std::copy_n(c.normals[i].data(), 3, &buf[i * stride + 3]);
  }
  return buf;
}

void write_pcd(std::ostream& out, const PointCloud& c) {
  const bool n = c.has_normals();
  out << "# .PCD v0.7 - Point Cloud Data file format\n";
  for (const auto& [k, v] : c.metadata) out << "# laserfit." << k << " " << one_line(v) << "\n";
  out << "VERSION 0.7\n"
      << (n ? "FIELDS x y z normal_x normal_y normal_z\nSIZE 4 4 4 4 4 4\nTYPE F F F F F F\n"
              "COUNT 1 1 1 1 1 1\n"
            : "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n")
      << "WIDTH " << c.width << "\nHEIGHT " << c.height << "\n"
      << "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS " << c.size() << "\nDATA binary\n";
}

void write_ply(std::ostream& out, const PointCloud& c) {
  out << "ply\nformat binary_little_endian 1.0\n";
  for (const auto& [k, v] : c.metadata) out << "comment laserfit." << k << " " << one_line(v) << "\n";
  if (c.organized()) out << "obj_info width " << c.width << " height " << c.height << "\n";
  out << "element vertex " << c.size() << "\n"
      << "property float x\nproperty float y\nproperty float z\n";
  if (c.has_normals()) out << "property float nx\nproperty float ny\nproperty float nz\n";
  out << "end_header\n";
}

}  // namespace

void write_cloud(const std::string& path, const PointCloud& cloud) {
  const std::string ext = lower_extension(path);
  if (ext != ".pcd" && ext != ".ply")
    throw Error(path, "unsupported cloud output format '" + ext + "' (use .pcd or .ply)");
  if (cloud.points.empty()) throw Error(path, "refusing to write an empty point cloud");
  if (cloud.has_normals() && cloud.normals.size() != cloud.points.size())
    throw Error(path, "internal: normals and points differ in count");
  if (static_cast<size_t>(cloud.width) * cloud.height != cloud.size())
    throw Error(path, "internal: width x height does not match the point count");
  AtomicFile f(path);
  if (ext == ".pcd")
    write_pcd(f.stream(), cloud);
  else
    write_ply(f.stream(), cloud);
  const auto buf = interleave(cloud);
  write_pod(f.stream(), buf.data(), buf.size());
  f.commit();
}

}  // namespace laserfit::io
