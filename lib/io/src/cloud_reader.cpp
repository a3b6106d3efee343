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
#include "laserfit/core/units.hpp"
#include "laserfit/io/cloud_io.hpp"
#include "laserfit/io/header_check.hpp"
#include "laserfit/io/util.hpp"

namespace laserfit::io {
namespace {

// A scalar float field of a PCLPointCloud2 point: float32 (PCL, laserfit) or float64 (Open3D).
struct Field {
  int offset = -1;
  bool is_double = false;
  bool found() const { return offset >= 0; }
};

Field float_field(const pcl::PCLPointCloud2& c, const std::string& name) {
  for (const auto& f : c.fields)
    if (f.name == name && f.count == 1 &&
        (f.datatype == pcl::PCLPointField::FLOAT32 || f.datatype == pcl::PCLPointField::FLOAT64))
      return {static_cast<int>(f.offset), f.datatype == pcl::PCLPointField::FLOAT64};
  return {};
}

// The field's value times `scale`, rounded once to float (a double metre value scaled in float
// would lose up to 0.06 um at 0.5 m; scaled in double it reads back as the float it was written
// from).
float value(const pcl::PCLPointCloud2& c, size_t i, Field f, double scale = 1.0) {
  const uint8_t* at = &c.data[i * c.point_step + f.offset];
  if (!f.is_double) {
    float v;
    std::memcpy(&v, at, sizeof v);
    return scale == 1.0 ? v : static_cast<float>(v * scale);
  }
  double v;
  std::memcpy(&v, at, sizeof v);
  return static_cast<float>(v * scale);
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
PointCloud read_with_pcl(const std::string& path, const std::string& ext, double to_mm) {
  // PCL reports problems on its console; we report them once, as our own error line.
  pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
  pcl::PCLPointCloud2 blob;
  Eigen::Vector4f origin = Eigen::Vector4f::Zero();  // PCD VIEWPOINT, PLY camera element
  Eigen::Quaternionf orientation = Eigen::Quaternionf::Identity();
  int version = 0, rc = -1;
  try {
    if (ext == ".pcd")
      rc = pcl::PCDReader().read(path, blob, origin, orientation, version);
    else
      rc = pcl::PLYReader().read(path, blob, origin, orientation, version);
  } catch (const pcl::PCLException& e) {
    throw Error(path, std::string("cannot parse: ") + e.what());
  }
  if (rc < 0) throw Error(path, "cannot parse (corrupt or truncated " + ext.substr(1) + " file)");
  const size_t n = static_cast<size_t>(blob.width) * blob.height;
  if (n == 0) throw Error(path, "cloud has no points");
  if (blob.data.size() < n * blob.point_step) throw Error(path, "truncated point data");
  const Field x = float_field(blob, "x"), y = float_field(blob, "y"), z = float_field(blob, "z");
  if (!x.found() || !y.found() || !z.found())
    throw Error(path, "no x, y, z fields of type float or double");
  Field nx = float_field(blob, "normal_x"), ny = float_field(blob, "normal_y"),
        nz = float_field(blob, "normal_z");
  if (!nx.found())
    nx = float_field(blob, "nx"), ny = float_field(blob, "ny"), nz = float_field(blob, "nz");
  const bool normals = nx.found() && ny.found() && nz.found();
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
  for (size_t i = 0; i < n; ++i) {
    c.points[i] = {value(blob, i, x, to_mm), value(blob, i, y, to_mm), value(blob, i, z, to_mm)};
    if (normals) c.normals[i] = {value(blob, i, nx), value(blob, i, ny), value(blob, i, nz)};
    if (olabel >= 0) std::memcpy(&c.labels[i], &blob.data[i * blob.point_step + olabel], 4);
  }
  // PCL's default VIEWPOINT is the origin, which also stands for "not recorded"; a sensor placed
  // exactly at the cloud frame's origin is given by laserfit.viewpoint or --viewpoint instead.
  if (origin.head<3>().allFinite() && !origin.head<3>().isZero())
    c.sensor_origin = origin.head<3>().cast<double>() * to_mm;
  return c;
}

}  // namespace

namespace {

// The laserfit.viewpoint comment: the sensor origin as laserfit wrote it (exact, unlike the float
// VIEWPOINT), so it wins over the header field.
void take_viewpoint_comment(const std::string& path, double to_mm, PointCloud& c) {
  const auto vp = c.metadata.find("viewpoint");
  if (vp == c.metadata.end()) return;
  std::istringstream in(vp->second);
  Eigen::Vector3d v;
  std::string rest;
  if (!(in >> v.x() >> v.y() >> v.z()) || (in >> rest) || !v.allFinite())
    throw Error(path, "laserfit.viewpoint '" + vp->second + "' is not three finite numbers");
  c.sensor_origin = v * to_mm;  // written in the file's unit
  c.metadata.erase(vp);
}

// The unit the file is in: its own laserfit.unit, else the caller's `unstated`.
Unit file_unit(const std::string& path, const std::map<std::string, std::string>& meta,
               Unit unstated) {
  Unit unit = unstated;
  if (const auto u = meta.find("unit"); u != meta.end()) {
    try {
      unit = parse_unit(u->second);
    } catch (const Error& e) {
      throw Error(path, std::string("laserfit.unit: ") + e.what());
    }
  }
  if (unit == Unit::Auto)
    throw Error(path, "the file does not state its unit; give it (--unit mm|m|um|cm|in)");
  return unit;
}

}  // namespace

PointCloud read_cloud(const std::string& path, Unit unstated) {
  require_input_file(path);
  const std::string ext = lower_extension(path);
  if (ext != ".pcd" && ext != ".ply")
    throw Error(path, "unsupported cloud format '" + ext + "' (use .pcd or .ply)");
  check_cloud_header(path, ext);
  auto meta = read_header_metadata(path);
  const Unit unit = file_unit(path, meta, unstated);
  const double to_mm = unit_to_mm(unit);  // applied in the reader, in double
  const std::string reader = ext == ".pcd" ? "the PCD reader (PCL)" : "the PLY reader (PCL)";
  PointCloud c = decode_cloud(
      run_isolated(path, reader, {}, [&] { return encode_cloud(read_with_pcl(path, ext, to_mm)); }),
      path);
  c.metadata = std::move(meta);
  take_viewpoint_comment(path, to_mm, c);
  c.metadata["unit"] = "mm";
  if (unit != Unit::Millimetre) c.metadata["unit_converted_from"] = unit_name(unit);
  return c;
}

}  // namespace laserfit::io
