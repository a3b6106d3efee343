// The only translation unit of io that includes PCL (keeps builds fast).
#include <pcl/PCLPointCloud2.h>
#include <pcl/console/print.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "cloud_codec.hpp"
#include "laserfit/core/error.hpp"
#include "laserfit/core/input_file.hpp"
#include "laserfit/core/isolate.hpp"
#include "laserfit/io/cloud_io.hpp"
#include "laserfit/io/header_check.hpp"
#include "laserfit/io/util.hpp"

namespace laserfit::io {
namespace {

// Offset of a float32 field in a PCLPointCloud2 point, or -1.
int float_field(const pcl::PCLPointCloud2& c, const std::string& name) {
  for (const auto& f : c.fields)
    if (f.name == name && f.datatype == pcl::PCLPointField::FLOAT32 && f.count == 1)
      return static_cast<int>(f.offset);
  return -1;
}

}  // namespace

std::map<std::string, std::string> read_header_metadata(const std::string& path) {
  std::map<std::string, std::string> meta;
  std::ifstream in(path, std::ios::binary);
  std::string line;
  for (int i = 0; i < 200 && std::getline(in, line); ++i) {
    for (const char* prefix : {"# laserfit.", "comment laserfit."}) {
      const size_t n = std::strlen(prefix);
      if (line.compare(0, n, prefix) == 0) {
        const std::string rest = line.substr(n);
        const size_t sp = rest.find(' ');
        meta[rest.substr(0, sp)] = sp == std::string::npos ? "" : rest.substr(sp + 1);
      }
    }
    if (line.rfind("DATA", 0) == 0 || line == "end_header") break;
  }
  return meta;
}

namespace {

// PCL's reader and the conversion to laserfit's cloud; runs in the isolated child (PCL's readers
// have been seen to corrupt their own memory on crafted binary data behind a valid header).
PointCloud read_with_pcl(const std::string& path, const std::string& ext) {
  // PCL reports problems on its console; we report them once, as our own error line.
  pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
  pcl::PCLPointCloud2 blob;
  int rc = -1;
  try {
    if (ext == ".pcd")
      rc = pcl::PCDReader().read(path, blob);
    else
      rc = pcl::PLYReader().read(path, blob);
  } catch (const pcl::PCLException& e) {
    throw Error(path, std::string("cannot parse: ") + e.what());
  }
  if (rc < 0) throw Error(path, "cannot parse (corrupt or truncated " + ext.substr(1) + " file)");
  const size_t n = static_cast<size_t>(blob.width) * blob.height;
  if (n == 0) throw Error(path, "cloud has no points");
  if (blob.data.size() < n * blob.point_step) throw Error(path, "truncated point data");
  const int ox = float_field(blob, "x"), oy = float_field(blob, "y"), oz = float_field(blob, "z");
  if (ox < 0 || oy < 0 || oz < 0) throw Error(path, "no float x, y, z fields");
  int onx = float_field(blob, "normal_x"), ony = float_field(blob, "normal_y"),
      onz = float_field(blob, "normal_z");
  if (onx < 0)
    onx = float_field(blob, "nx"), ony = float_field(blob, "ny"), onz = float_field(blob, "nz");
  const bool normals = onx >= 0 && ony >= 0 && onz >= 0;
  int olabel = -1;
  for (const auto& f : blob.fields)
    if (f.name == "label" && f.count == 1 &&
        (f.datatype == pcl::PCLPointField::INT32 || f.datatype == pcl::PCLPointField::UINT32))
      olabel = static_cast<int>(f.offset);

  PointCloud c;
  c.width = static_cast<int>(blob.width);
  c.height = static_cast<int>(blob.height);
  c.points.resize(n);
  if (normals) c.normals.resize(n);
  if (olabel >= 0) c.labels.resize(n);
  auto get = [&](size_t i, int off) {
    float v;
    std::memcpy(&v, &blob.data[i * blob.point_step + off], sizeof(float));
    return v;
  };
  for (size_t i = 0; i < n; ++i) {
    c.points[i] = {get(i, ox), get(i, oy), get(i, oz)};
    if (normals) c.normals[i] = {get(i, onx), get(i, ony), get(i, onz)};
    if (olabel >= 0) std::memcpy(&c.labels[i], &blob.data[i * blob.point_step + olabel], 4);
  }
  return c;
}

}  // namespace

PointCloud read_cloud(const std::string& path) {
  require_input_file(path);
  const std::string ext = lower_extension(path);
  if (ext != ".pcd" && ext != ".ply")
    throw Error(path, "unsupported cloud format '" + ext + "' (use .pcd or .ply)");
  check_cloud_header(path, ext);
  const std::string reader = ext == ".pcd" ? "the PCD reader (PCL)" : "the PLY reader (PCL)";
  PointCloud c = decode_cloud(
      run_isolated(path, reader, {}, [&] { return encode_cloud(read_with_pcl(path, ext)); }), path);
  c.metadata = read_header_metadata(path);
  if (const auto vp = c.metadata.find("viewpoint"); vp != c.metadata.end()) {
    std::istringstream in(vp->second);
    Eigen::Vector3d v;
    std::string rest;
    if (!(in >> v.x() >> v.y() >> v.z()) || (in >> rest) || !v.allFinite())
      throw Error(path, "laserfit.viewpoint '" + vp->second + "' is not three finite numbers (mm)");
    c.sensor_origin = v;
    c.metadata.erase(vp);
  }
  return c;
}

}  // namespace laserfit::io
