#include "wire.hpp"

#include <cmath>
#include <fstream>
#include <sstream>

#include "laserfit/core/error.hpp"

namespace laserfit::remote::wire {
namespace {

void require(bool ok, const std::string& what, const std::string& problem) {
  if (!ok) throw Error(what + ": " + problem);
}

bool finite(const google::protobuf::RepeatedField<double>& v) {
  for (double x : v)
    if (!std::isfinite(x)) return false;
  return true;
}

}  // namespace

std::string read_pem(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  if (!(in && s << in.rdbuf())) throw Error(path + ": cannot read the TLS certificate or key");
  return s.str();
}

void put(const Pose& T, pb::Pose* m) {
  m->clear_m();
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m->add_m(T.matrix()(r, c));
}

Pose get(const pb::Pose& m, const std::string& what) {
  require(m.m_size() == 16 && finite(m.m()), what, "a pose is 16 finite values");
  Pose T = Pose::Identity();
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) T.matrix()(r, c) = m.m(4 * r + c);
  const Eigen::Matrix3d R = T.linear();
  require(m.m(12) == 0 && m.m(13) == 0 && m.m(14) == 0 && m.m(15) == 1, what,
          "a pose's last row is 0 0 0 1");
  require((R.transpose() * R - Eigen::Matrix3d::Identity()).norm() < 1e-6 && R.determinant() > 0,
          what, "a pose's rotation is not a rotation");
  return T;
}

void put(const robot::Joints& q, pb::Joints* m) {
  m->clear_q();
  for (int j = 0; j < 7; ++j) m->add_q(q[j]);
}

robot::Joints get(const pb::Joints& m, const std::string& what) {
  require(m.q_size() == 7 && finite(m.q()), what,
          std::to_string(m.q_size()) + " joint values, a Panda has 7 (finite, rad)");
  robot::Joints q;
  for (int j = 0; j < 7; ++j) q[j] = m.q(j);
  return q;
}

void put(const controller::MotionCommand& c, pb::Trajectory* m) {
  m->set_rate_hz(c.path.rate_hz);
  auto* v = m->mutable_samples();
  v->Reserve(int(7 * c.path.size()));
  for (size_t i = 0; i < c.path.size(); ++i) {
    const auto& t = c.path.t[i];
    const auto& q = c.path.q[i];
    for (double x : {t.x(), t.y(), t.z(), q.w(), q.x(), q.y(), q.z()}) v->Add(x);
  }
  put(c.q_ref, m->mutable_q_ref());
  m->set_guarded(c.guarded);
}

controller::MotionCommand get(const pb::Trajectory& m) {
  require(m.samples_size() % 7 == 0, "trajectory", "7 values per sample");
  controller::MotionCommand c;
  c.path.rate_hz = m.rate_hz();
  const auto& v = m.samples();
  for (int i = 0; i + 6 < v.size(); i += 7) {
    c.path.t.emplace_back(v[i], v[i + 1], v[i + 2]);
    c.path.q.emplace_back(v[i + 3], v[i + 4], v[i + 5], v[i + 6]);
  }
  c.q_ref = get(m.q_ref(), "trajectory's elbow reference");
  c.guarded = m.guarded();
  return c;
}

void put(const controller::MotionReport& r, pb::MotionResult* m) {
  m->set_ok(r.ok), m->set_fault(r.reason), m->set_duration_s(r.duration_s);
  m->set_contact(r.contact);
  put(r.q, m->mutable_q());
}

controller::MotionReport get(const pb::MotionResult& m) {
  controller::MotionReport r;
  r.ok = m.ok(), r.reason = m.fault().substr(0, 200), r.duration_s = m.duration_s();
  r.contact = m.contact();
  r.q = get(m.q(), "motion result");
  require(r.ok || !r.reason.empty(), "motion result", "a fault without its reason");
  require(r.ok || !r.contact, "motion result", "a contact reported with a fault");
  return r;
}

void put(const controller::SweepRequest& r, pb::SweepRequest* m) {
  put(r.q_start, m->mutable_q_start());
  m->clear_direction();
  for (int k = 0; k < 3; ++k) m->add_direction(r.direction[k]);
  m->set_lead_mm(r.lead_mm), m->set_length_mm(r.length_mm), m->set_speed_mm_s(r.speed_mm_s);
}

controller::SweepRequest get(const pb::SweepRequest& m) {
  require(m.direction_size() == 3, "sweep request", "the direction has 3 values");
  controller::SweepRequest r;
  r.q_start = get(m.q_start(), "sweep request's start");
  r.direction = {m.direction(0), m.direction(1), m.direction(2)};
  r.lead_mm = m.lead_mm(), r.length_mm = m.length_mm(), r.speed_mm_s = m.speed_mm_s();
  return r;
}

void put(const controller::Sweep& s, size_t i, pb::Profile* m) {
  const size_t W = size_t(s.profiles.width);
  m->Clear();
  m->set_index(uint32_t(i));
  put(s.T_world_flange.at(i), m->mutable_t_world_flange());
  m->mutable_x()->Reserve(int(W)), m->mutable_z()->Reserve(int(W));
  for (size_t j = 0; j < W; ++j) {
    m->add_x(s.profiles.xz[i * W + j].x());
    m->add_z(s.profiles.xz[i * W + j].y());
  }
}

void add(const pb::Profile& m, int width, controller::Sweep& s) {
  const std::string what = "profile " + std::to_string(m.index());
  require(m.index() == uint32_t(s.profiles.count), what,
          "out of order (expected " + std::to_string(s.profiles.count) + ")");
  require(m.x_size() == width && m.z_size() == width, what,
          std::to_string(m.x_size()) + " x and " + std::to_string(m.z_size()) +
              " z values, the scanner has " + std::to_string(width) + " points");
  require(s.profiles.count < 100000, what, "more than 100000 profiles");
  s.T_world_flange.push_back(get(m.t_world_flange(), what + "'s flange pose"));
  for (int j = 0; j < width; ++j) s.profiles.xz.emplace_back(m.x(j), m.z(j));
  s.profiles.width = width, ++s.profiles.count;
}

}  // namespace laserfit::remote::wire
