#include <charconv>
#include <cmath>
#include <cstring>
#include <map>
#include <vector>

#include "laserfit/core/atomic_file.hpp"
#include "laserfit/core/error.hpp"
#include "laserfit/io/cloud_io.hpp"
#include "laserfit/io/util.hpp"

namespace laserfit::io {
namespace {

// Interleaved x y z [nx ny nz] [label] rows of 4-byte values, the on-disk layout of both formats.
std::vector<float> interleave(const PointCloud& c) {
  const bool n = c.has_normals(), l = !c.labels.empty();
  const size_t stride = 3 + (n ? 3 : 0) + (l ? 1 : 0);
  std::vector<float> buf(c.size() * stride);
  for (size_t i = 0; i < c.size(); ++i) {
    float* row = &buf[i * stride];
    std::copy_n(c.points[i].data(), 3, row);
    if (n) std::copy_n(c.normals[i].data(), 3, row + 3);
    if (l) std::memcpy(row + stride - 1, &c.labels[i], sizeof(int32_t));
  }
  return buf;
}

std::string shortest(double v) {  // the shortest decimal that reads back as the same double
  char b[32];
  const auto r = std::to_chars(b, b + sizeof b, v);
  return std::string(b, r.ptr);
}

// The header's laserfit.* lines: the metadata and the sensor origin (shortest round-trip decimal).
// The unit is always stated (a cloud is millimetres inside), so that whoever reads the file back
// with another --unit does not rescale it.
std::map<std::string, std::string> header_metadata(const PointCloud& c) {
  std::map<std::string, std::string> m = {{"unit", "mm"}};
  for (const auto& [k, v] : c.metadata) m[k] = one_line(v);
  if (c.sensor_origin) {
    const Eigen::Vector3d& o = *c.sensor_origin;
    m["viewpoint"] = shortest(o.x()) + " " + shortest(o.y()) + " " + shortest(o.z());
  }
  return m;
}

void write_pcd(std::ostream& out, const PointCloud& c) {
  const bool n = c.has_normals(), l = !c.labels.empty();
  const int fields = 3 + (n ? 3 : 0) + (l ? 1 : 0);
  out << "# .PCD v0.7 - Point Cloud Data file format\n";
  for (const auto& [k, v] : header_metadata(c)) out << "# laserfit." << k << " " << v << "\n";
  out << "VERSION 0.7\nFIELDS x y z" << (n ? " normal_x normal_y normal_z" : "")
      << (l ? " label" : "") << "\nSIZE";
  for (int i = 0; i < fields; ++i) out << " 4";
  out << "\nTYPE";
  for (int i = 0; i < fields; ++i) out << (l && i == fields - 1 ? " I" : " F");
  out << "\nCOUNT";
  for (int i = 0; i < fields; ++i) out << " 1";
  // VIEWPOINT carries the sensor origin for PCL and other readers (PCL's sensor_origin_); the
  // laserfit.viewpoint comment above keeps it exact.
  const Eigen::Vector3d o = c.sensor_origin.value_or(Eigen::Vector3d::Zero());
  out << "\nWIDTH " << c.width << "\nHEIGHT " << c.height << "\nVIEWPOINT " << shortest(o.x())
      << " " << shortest(o.y()) << " " << shortest(o.z()) << " 1 0 0 0\nPOINTS " << c.size()
      << "\nDATA binary\n";
}

void write_ply(std::ostream& out, const PointCloud& c) {
  out << "ply\nformat binary_little_endian 1.0\n";
  for (const auto& [k, v] : header_metadata(c)) out << "comment laserfit." << k << " " << v << "\n";
  // PCL's convention for an organized PLY (PLYReader restores width x height from it).
  if (c.organized())
    out << "obj_info num_cols " << c.width << "\nobj_info num_rows " << c.height << "\n";
  out << "element vertex " << c.size() << "\n"
      << "property float x\nproperty float y\nproperty float z\n";
  if (c.has_normals()) out << "property float nx\nproperty float ny\nproperty float nz\n";
  if (!c.labels.empty()) out << "property int label\n";
  out << "end_header\n";
}

}  // namespace

void write_cloud(AtomicFile& f, const PointCloud& cloud) {
  const std::string& path = f.path();
  const std::string ext = lower_extension(path);
  if (ext != ".pcd" && ext != ".ply")
    throw Error(path, "unsupported cloud output format '" + ext + "' (use .pcd or .ply)");
  if (cloud.points.empty()) throw Error(path, "refusing to write an empty point cloud");
  if (cloud.has_normals() && cloud.normals.size() != cloud.points.size())
    throw Error(path, "internal: normals and points differ in count");
  if (!cloud.labels.empty() && cloud.labels.size() != cloud.points.size())
    throw Error(path, "internal: labels and points differ in count");
  if (static_cast<size_t>(cloud.width) * cloud.height != cloud.size())
    throw Error(path, "internal: width x height does not match the point count");
  if (ext == ".pcd")
    write_pcd(f.stream(), cloud);
  else
    write_ply(f.stream(), cloud);
  const auto buf = interleave(cloud);
  write_pod(f.stream(), buf.data(), buf.size());
}

void write_cloud(const std::string& path, const PointCloud& cloud) {
  const std::string ext = lower_extension(path);
  if (ext != ".pcd" && ext != ".ply")  // before creating any temporary file
    throw Error(path, "unsupported cloud output format '" + ext + "' (use .pcd or .ply)");
  AtomicFile f(path);
  write_cloud(f, cloud);
  f.commit();
}

}  // namespace laserfit::io
