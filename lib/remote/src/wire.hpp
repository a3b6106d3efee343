#pragma once
// Between the port's types and the protocol's messages. Reading a message checks its shape
// (counts, finiteness) and throws laserfit::Error("<what>: ...") when it is malformed; whether
// the values are in range is the port's check_request / check_report.
#include "laserfit/cell/v1/cell.pb.h"
#include "laserfit/controller/cell_port.hpp"

namespace laserfit::remote::wire {

namespace pb = laserfit::cell::v1;

// A TLS certificate or key (PEM); throws laserfit::Error naming the file.
std::string read_pem(const std::string& path);

void put(const Pose& T, pb::Pose* m);
Pose get(const pb::Pose& m, const std::string& what);
void put(const robot::Joints& q, pb::Joints* m);
robot::Joints get(const pb::Joints& m, const std::string& what);

void put(const controller::MotionCommand& c, pb::Trajectory* m);
controller::MotionCommand get(const pb::Trajectory& m);
void put(const controller::MotionReport& r, pb::MotionResult* m);
controller::MotionReport get(const pb::MotionResult& m);
void put(const controller::SweepRequest& r, pb::SweepRequest* m);
controller::SweepRequest get(const pb::SweepRequest& m);
// Profile i of a sweep, and back into the sweep being gathered (its index must be the next).
void put(const controller::Sweep& s, size_t i, pb::Profile* m);
void add(const pb::Profile& m, int points_per_profile, controller::Sweep& s);

}  // namespace laserfit::remote::wire
