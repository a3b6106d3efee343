#pragma once
// JSON helpers for --json output and ground-truth files (nlohmann::json).
#include <nlohmann/json.hpp>

#include "laserfit/core/pose.hpp"

namespace laserfit::io {

using Json = nlohmann::ordered_json;

Json pose_to_json(const Pose& T);  // {"t_mm": [x,y,z], "q_wxyz": [w,x,y,z], "matrix": 4x4}
Pose pose_from_json(const Json& j,
                    const std::string& what);  // "matrix" if given (exact), else t + q
Json read_json(const std::string& path);       // throws laserfit::Error naming the file

}  // namespace laserfit::io
