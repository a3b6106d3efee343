#pragma once
// What a line scanner and its arm deliver, before they are a cloud: profiles (x along the laser
// line, z the depth, per point, in the sensor frame) and one flange pose per profile. laserfit
// assemble turns them into an organized cloud in the arm's base frame
// (laserfit/sensor/assemble.hpp).
#include <Eigen/Core>
#include <string>
#include <vector>

#include "laserfit/core/enum_names.hpp"
#include "laserfit/core/pose.hpp"
#include "laserfit/core/units.hpp"

namespace laserfit::io {

// How the x and z of one profile follow each other in a row.
enum class ProfileLayout {
  interleaved,  // x0 z0 x1 z1 ... (point by point)
  blocks,       // x0 x1 ... x(W-1) z0 z1 ... z(W-1) (the x array, then the z array)
};
enum class ProfileScalar { f32, f64 };  // the binary file's number type (little endian)

struct ProfileFileSettings {
  ProfileLayout layout = ProfileLayout::interleaved;
  ProfileScalar scalar = ProfileScalar::f64;  // .bin only
  int width = 0;                 // points per profile; .bin needs it, CSV checks it (0: any)
  Unit unit = Unit::Millimetre;  // of x and z; profiles read from a .pcd/.ply state their own
  bool zero_is_invalid = false;  // z == 0 marks "no measurement" (some drivers' convention)
};

struct Profiles {
  int width = 0;                    // points per profile
  int count = 0;                    // profiles
  std::vector<Eigen::Vector2f> xz;  // count x width, mm; NaN = no measurement
};

// .csv (one profile per row; separators , ; tab or space; an empty field or "nan" is no
// measurement; '#' lines and one header row of names are skipped), .bin (rows of `width` points,
// no header) or .pcd/.ply (an organized cloud in the sensor frame, y = 0, as `laserfit scan
// --raw` writes). Throws laserfit::Error naming the file and the row.
Profiles read_profiles(const std::string& path, const ProfileFileSettings& s);

// One pose per row: "x y z qw qx qy qz" or a row-major 4x4, commas or spaces, translations in
// `unit`; '#' lines and one header row of names are skipped.
std::vector<Pose> read_pose_list(const std::string& path, Unit unit);

}  // namespace laserfit::io

namespace laserfit {
template <>
struct EnumNames<io::ProfileLayout> {
  static constexpr const char* what = "profile layout";
  static constexpr std::pair<io::ProfileLayout, const char*> table[] = {
      {io::ProfileLayout::interleaved, "interleaved"}, {io::ProfileLayout::blocks, "blocks"}};
};
template <>
struct EnumNames<io::ProfileScalar> {
  static constexpr const char* what = "profile number type";
  static constexpr std::pair<io::ProfileScalar, const char*> table[] = {
      {io::ProfileScalar::f32, "f32"}, {io::ProfileScalar::f64, "f64"}};
};
}  // namespace laserfit
