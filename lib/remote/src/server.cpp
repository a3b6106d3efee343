// cell-sim: controller::SimCell behind the cell protocol, one trial at a time (a cell has one
// pair of arms: calls are served one after another), requests read and checked before the
// simulated arms act on them, faults injected on request.
#include "laserfit/remote/server.hpp"

#include <grpcpp/grpcpp.h>

#include <mutex>
#include <thread>

#include "laserfit/cell/v1/cell.grpc.pb.h"
#include "laserfit/controller/sim.hpp"
#include "laserfit/core/enum_names.hpp"
#include "laserfit/core/error.hpp"
#include "laserfit/remote/client.hpp"
#include "wire.hpp"

namespace laserfit {
template <>
struct EnumNames<remote::FaultKind> {
  static constexpr const char* what = "injected fault";
  static constexpr std::pair<remote::FaultKind, const char*> table[] = {
      {remote::FaultKind::motion_fault, "motion-fault"},
      {remote::FaultKind::malformed, "malformed"},
      {remote::FaultKind::out_of_range, "out-of-range"},
      {remote::FaultKind::empty_sweep, "empty-sweep"},
      {remote::FaultKind::truncated_sweep, "truncated-sweep"},
      {remote::FaultKind::stall, "stall"},
      {remote::FaultKind::disconnect, "disconnect"}};
};
}  // namespace laserfit

namespace laserfit::remote {

namespace pb = laserfit::cell::v1;
using grpc::ServerContext;
using grpc::Status;
using grpc::StatusCode;

Injection parse_injection(const std::string& text) {
  const auto at = text.find('@');
  Injection in;
  try {
    in.kind = parse_enum<FaultKind>(text.substr(0, at));
    in.at = at == std::string::npos ? 1 : std::stoi(text.substr(at + 1));
  } catch (const std::exception&) {
    throw Error("--inject " + text + ": not KIND@N (KIND: " + injection_kinds() + ")");
  }
  if (in.at < 1) throw Error("--inject " + text + ": N counts calls from 1");
  return in;
}

std::string injection_kinds() {
  std::string s;
  for (const auto& [k, name] : EnumNames<FaultKind>::table)
    s += (s.empty() ? "" : ", ") + std::string(name);
  return s;
}

// A request read through wire::get; a malformed one is INVALID_ARGUMENT with the reason.
template <class T, class F>
Status read(F get, T& out) {
  try {
    out = get();
    return Status::OK;
  } catch (const Error& e) {
    return Status(StatusCode::INVALID_ARGUMENT, e.what());
  }
}

// What the two services share: the campaign's cells, the trial's simulated cell, the counters.
struct State {
  cell::CellSettings cs;
  controller::ControllerSettings s;
  ServerSettings ss;
  mutable std::mutex m;
  std::unique_ptr<controller::Campaign> campaign;
  std::unique_ptr<controller::SimCell> sim;
  int robot = 0, calls = 0, moves = 0, sweeps = 0;
  std::atomic<int> stops{0};
  std::atomic<bool> down{false};

  bool fault(FaultKind k, int count) const {
    for (const auto& i : ss.inject)
      if (i.kind == k && i.at == count) return true;
    return false;
  }
  // Counts a Cell call; a stall holds it until the server goes down, a disconnect takes it down.
  Status enter() {
    ++calls;
    if (fault(FaultKind::disconnect, calls)) {
      if (ss.on_disconnect) ss.on_disconnect();
      return Status(StatusCode::UNAVAILABLE, "cell-sim: disconnected (injected)");
    }
    if (fault(FaultKind::stall, calls)) {  // held until the server goes down, never acted on
      while (!down) std::this_thread::sleep_for(std::chrono::milliseconds(20));
      return Status(StatusCode::UNAVAILABLE, "cell-sim: stalled (injected)");
    }
    if (!sim)
      return Status(StatusCode::FAILED_PRECONDITION, "no trial begun (Simulation.BeginTrial)");
    return Status::OK;
  }
};

class CellService final : public pb::Cell::Service {
 public:
  explicit CellService(State& st) : st_(st) {}

  Status Hello(ServerContext*, const pb::HelloRequest* req, pb::HelloReply* rep) override {
    rep->set_protocol_version(kProtocolVersion);
    rep->set_cell(st_.cs.task + " (laserfit cell-sim)");
    rep->set_points_per_profile(uint32_t(st_.cs.scene.settings.sensor.points_per_profile));
    rep->set_simulated(true);
    if (req->protocol_version() != kProtocolVersion)
      return Status(StatusCode::FAILED_PRECONDITION, "protocol version " +
                                                         std::to_string(req->protocol_version()) +
                                                         " is not spoken here (1 is)");
    return Status::OK;
  }

  Status GetArmState(ServerContext*, const pb::ArmStateRequest* req, pb::ArmState* rep) override {
    std::lock_guard<std::mutex> l(st_.m);
    if (Status e = st_.enter(); !e.ok()) return e;
    if (req->arm() != pb::ARM_ASSEMBLING)
      return Status(StatusCode::INVALID_ARGUMENT, "only the assembling arm's state is served");
    const robot::Joints q = st_.sim->joints();
    wire::put(q, rep->mutable_q());
    wire::put(st_.campaign->cell(st_.robot).nominal.fk(q), rep->mutable_t_base_flange());
    return Status::OK;
  }

  Status Execute(ServerContext*, const pb::Trajectory* req, pb::MotionResult* rep) override;
  Status Sweep(ServerContext*, const pb::SweepRequest* req,
               grpc::ServerWriter<pb::SweepChunk>* out) override;

  // Not behind the lock: a stop is heard even while another call hangs. The simulated arms
  // hold still between calls; a bridge would stop its arms here.
  Status Stop(ServerContext*, const pb::StopRequest*, pb::StopReply*) override {
    ++st_.stops;
    return Status::OK;
  }

 private:
  State& st_;
};

Status CellService::Execute(ServerContext*, const pb::Trajectory* req, pb::MotionResult* rep) {
  std::lock_guard<std::mutex> l(st_.m);
  if (Status e = st_.enter(); !e.ok()) return e;
  controller::MotionCommand cmd;
  if (Status e = read([&] { return wire::get(*req); }, cmd); !e.ok()) return e;
  ++st_.moves;
  controller::MotionReport r;
  if (st_.fault(FaultKind::motion_fault, st_.moves)) {  // the arm stops halfway: a reflex
    cmd.path.t.resize(cmd.path.size() / 2), cmd.path.q.resize(cmd.path.t.size());
    if (cmd.path.size() > 0) r = st_.sim->move(cmd);
    r.ok = false, r.reason = "cartesian_reflex (injected)";
  } else {
    r = st_.sim->move(cmd);  // SimCell checks the path and reports what it refuses as a fault
  }
  wire::put(r, rep);
  if (st_.fault(FaultKind::malformed, st_.moves)) rep->mutable_q()->mutable_q()->RemoveLast();
  if (st_.fault(FaultKind::out_of_range, st_.moves)) rep->mutable_q()->set_q(0, 4.0);
  return Status::OK;
}

Status CellService::Sweep(ServerContext* ctx, const pb::SweepRequest* req,
                          grpc::ServerWriter<pb::SweepChunk>* out) {
  std::lock_guard<std::mutex> l(st_.m);
  if (Status e = st_.enter(); !e.ok()) return e;
  controller::SweepRequest r;
  if (Status e = read([&] { return wire::get(*req); }, r); !e.ok()) return e;
  ++st_.sweeps;
  controller::Sweep sw = st_.sim->scan(r);
  const bool empty = st_.fault(FaultKind::empty_sweep, st_.sweeps);
  const size_t n = empty ? 0 : size_t(sw.profiles.count);
  const size_t sent = st_.fault(FaultKind::truncated_sweep, st_.sweeps) ? n / 2 : n;
  pb::SweepChunk chunk;
  for (size_t i = 0; i < sent; ++i) {
    if (ctx->IsCancelled()) return Status(StatusCode::CANCELLED, "the client went away");
    wire::put(sw, i, chunk.mutable_profile());
    if (!out->Write(chunk)) return Status(StatusCode::CANCELLED, "the client went away");
  }
  if (sent < n) return Status::OK;  // the stream ends without its end message
  auto* end = chunk.mutable_end();
  end->set_profiles(uint32_t(n)), end->set_duration_s(sw.duration_s), end->set_fault(sw.fault);
  out->Write(chunk);
  return Status::OK;
}

class SimulationService final : public pb::Simulation::Service {
 public:
  explicit SimulationService(State& st) : st_(st) {}

  Status BeginTrial(ServerContext*, const pb::TrialRequest* req, pb::TrialReply* rep) override {
    std::lock_guard<std::mutex> l(st_.m);
    if (!st_.campaign || st_.campaign->seed() != req->campaign_seed())
      st_.campaign = std::make_unique<controller::Campaign>(st_.cs, st_.s, req->campaign_seed());
    if (req->trial() > 10000000) return Status(StatusCode::INVALID_ARGUMENT, "trial out of range");
    const auto t = controller::plan_trial(st_.cs, req->campaign_seed(), int(req->trial()));
    try {
      st_.campaign->prepare(t);
    } catch (const Error& e) {
      return Status(StatusCode::INVALID_ARGUMENT, e.what());
    }
    st_.sim = std::make_unique<controller::SimCell>(st_.campaign->cell(t.robot),
                                                    st_.campaign->setup(t.robot, t.setting),
                                                    t.start, t.seed, st_.s.motion);
    st_.robot = t.robot;
    rep->set_setting(uint32_t(t.setting)), rep->set_start(uint32_t(t.start));
    return Status::OK;
  }

  Status Judge(ServerContext*, const pb::JudgeRequest* req, pb::Judgement* rep) override {
    std::lock_guard<std::mutex> l(st_.m);
    if (!st_.sim) return Status(StatusCode::FAILED_PRECONDITION, "no trial begun");
    if (req->has_t_target_part_goal()) {
      Pose goal;
      const auto get = [&] { return wire::get(req->t_target_part_goal(), "judge request"); };
      if (Status e = read(get, goal); !e.ok()) return e;
      const auto e = st_.sim->true_error(goal);
      rep->set_moved(bool(e));
      if (e) rep->set_lateral_error_mm(e->x()), rep->set_axial_error_mm(e->y());
      return Status::OK;
    }
    const auto j = st_.sim->judge();
    rep->set_moved(bool(j));
    if (!j) return Status::OK;
    rep->set_success(j->success), rep->set_x_mm(j->x_mm), rep->set_y_mm(j->y_mm);
    rep->set_angle_deg(j->angle_deg), rep->set_depth_mm(j->depth_mm);
    return Status::OK;
  }

 private:
  State& st_;
};

struct CellSimServer::Impl {
  State st;
  CellService cell{st};
  SimulationService sim{st};
  std::unique_ptr<grpc::Server> server;
  int port = 0;
  std::thread disconnect;  // the default disconnect's shutdown, joined before the server goes
};

CellSimServer::CellSimServer(const cell::CellSettings& cs, const controller::ControllerSettings& s,
                             const ServerSettings& ss)
    : impl_(std::make_unique<Impl>()) {
  auto& m = *impl_;
  m.st.cs = cs, m.st.s = s, m.st.ss = ss;
  if (!m.st.ss.on_disconnect)
    m.st.ss.on_disconnect = [this] {
      if (!impl_->disconnect.joinable()) impl_->disconnect = std::thread([this] { shutdown(); });
    };
  if (ss.tls_cert.empty() != ss.tls_key.empty())
    throw Error("TLS needs both a certificate and its key (--tls-cert, --tls-key)");
  std::shared_ptr<grpc::ServerCredentials> creds = grpc::InsecureServerCredentials();
  if (!ss.tls_cert.empty()) {
    grpc::SslServerCredentialsOptions o;
    o.pem_key_cert_pairs.push_back({wire::read_pem(ss.tls_key), wire::read_pem(ss.tls_cert)});
    creds = grpc::SslServerCredentials(o);
  }
  grpc::ServerBuilder b;
  b.AddListeningPort(ss.listen, creds, &m.port);
  b.SetMaxReceiveMessageSize(64 << 20), b.SetMaxSendMessageSize(64 << 20);
  b.RegisterService(&m.cell), b.RegisterService(&m.sim);
  m.server = b.BuildAndStart();
  if (!m.server || m.port == 0) throw Error(ss.listen + ": cannot listen there");
}

CellSimServer::~CellSimServer() {
  shutdown();
  if (impl_->disconnect.joinable()) impl_->disconnect.join();
}
int CellSimServer::port() const { return impl_->port; }

CellSimServer::Counts CellSimServer::counts() const {
  std::lock_guard<std::mutex> l(impl_->st.m);
  return {impl_->st.calls, impl_->st.moves, impl_->st.sweeps, impl_->st.stops};
}
void CellSimServer::wait() { impl_->server->Wait(); }

void CellSimServer::shutdown() {
  auto& m = *impl_;
  if (m.st.down.exchange(true)) return;
  m.server->Shutdown(std::chrono::system_clock::now() + std::chrono::milliseconds(200));
}

}  // namespace laserfit::remote
