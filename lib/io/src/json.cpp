#include "laserfit/io/json.hpp"

#include <cmath>
#include <fstream>

#include "laserfit/core/error.hpp"

namespace laserfit::io {

Json pose_to_json(const Pose& T) {
  const auto v = pose_to_tq(T);
  Json m = Json::array();
  for (int r = 0; r < 4; ++r) m.push_back({T(r, 0), T(r, 1), T(r, 2), T(r, 3)});
  return Json{{"t_mm", {v[0], v[1], v[2]}}, {"q_wxyz", {v[3], v[4], v[5], v[6]}}, {"matrix", m}};
}

Pose pose_from_json(const Json& j, const std::string& what) {
  try {
    if (j.contains("matrix")) {  // exact (the quaternion is a rounded copy of it)
      const auto m = j.at("matrix").get<std::vector<std::vector<double>>>();
      if (m.size() != 4) throw Error(what, "matrix needs 4 rows");
      Eigen::Matrix4d M;
      for (int r = 0; r < 4; ++r) {
        if (m[r].size() != 4) throw Error(what, "matrix needs 4 columns");
        for (int c = 0; c < 4; ++c) M(r, c) = m[r][c];
      }
      const Eigen::Matrix3d R = M.topLeftCorner<3, 3>();
      if (!M.allFinite() || (R * R.transpose() - Eigen::Matrix3d::Identity()).norm() > 1e-6 ||
          R.determinant() < 0 || (M.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).norm() > 1e-12)
        throw Error(what, "matrix is not a rigid transform");
      Pose T = Pose::Identity();
      T.matrix() = M;
      return T;
    }
    if (j.contains("t_mm") && j.contains("q_wxyz")) {
      const auto t = j.at("t_mm").get<std::vector<double>>();
      const auto q = j.at("q_wxyz").get<std::vector<double>>();
      if (t.size() != 3 || q.size() != 4) throw Error(what, "t_mm needs 3 numbers, q_wxyz 4");
      const Eigen::Quaterniond qq(q[0], q[1], q[2], q[3]);
      if (std::abs(qq.norm() - 1.0) > 1e-3) throw Error(what, "q_wxyz is not a unit quaternion");
      return pose_from_tq({t[0], t[1], t[2]}, qq);
    }
  } catch (const nlohmann::json::exception& e) {
    throw Error(what, std::string("bad pose: ") + e.what());
  }
  throw Error(what, "pose needs t_mm and q_wxyz");
}

}  // namespace laserfit::io

namespace laserfit::io {

Json read_json(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw Error(path, "cannot read the file");
  try {
    return Json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw Error(path, std::string("not valid JSON: ") + e.what());
  }
}

}  // namespace laserfit::io
