// The client of the cell protocol: each call with a deadline, each reply read through wire::get
// (shape) before the loop's check_report (range).
#include <grpcpp/grpcpp.h>

#include <chrono>

#include "laserfit/cell/v1/cell.grpc.pb.h"
#include "laserfit/core/error.hpp"
#include "laserfit/remote/client.hpp"
#include "wire.hpp"

namespace laserfit::remote {

namespace pb = laserfit::cell::v1;

struct RemoteCell::Impl {
  ClientSettings s;
  std::shared_ptr<grpc::Channel> channel;
  std::unique_ptr<pb::Cell::Stub> cell;
  std::unique_ptr<pb::Simulation::Stub> sim;
  pb::HelloReply hello;
  bool lost = false;

  // A context whose deadline is the call's own duration plus the timeout.
  std::unique_ptr<grpc::ClientContext> context(double duration_s = 0) const {
    auto c = std::make_unique<grpc::ClientContext>();
    c->set_deadline(std::chrono::system_clock::now() +
                    std::chrono::microseconds(int64_t(1e6 * (duration_s + s.timeout_s))));
    return c;
  }
  // One line naming the peer; the cell is not called again.
  [[noreturn]] void fail(const std::string& call, const std::string& problem) {
    lost = true;
    throw controller::CellFailure("cell " + s.endpoint + ": " + call + ": " + problem);
  }
  void check(const grpc::Status& st, const std::string& call) {
    if (lost) fail(call, "not called after an earlier failure");
    if (st.ok()) return;
    const std::string why = st.error_code() == grpc::StatusCode::DEADLINE_EXCEEDED
                                ? "no answer in time (timeout)"
                            : st.error_code() == grpc::StatusCode::UNAVAILABLE
                                ? "connection lost (" + st.error_message() + ")"
                                : st.error_message();
    fail(call, why);
  }
  template <class F>
  auto read(const std::string& call, F f) {  // a malformed reply is the peer's failure too
    try {
      return f();
    } catch (const Error& e) {
      fail(call, std::string("malformed reply: ") + e.what());
    }
  }
};

RemoteCell::RemoteCell(const ClientSettings& s) : impl_(std::make_unique<Impl>()) {
  auto& m = *impl_;
  m.s = s;
  std::shared_ptr<grpc::ChannelCredentials> creds = grpc::InsecureChannelCredentials();
  if (!s.tls_ca.empty()) {
    grpc::SslCredentialsOptions o;
    o.pem_root_certs = wire::read_pem(s.tls_ca);
    creds = grpc::SslCredentials(o);
  }
  grpc::ChannelArguments args;
  args.SetMaxReceiveMessageSize(64 << 20), args.SetMaxSendMessageSize(64 << 20);
  m.channel = grpc::CreateCustomChannel(s.endpoint, creds, args);
  m.cell = pb::Cell::NewStub(m.channel);
  m.sim = pb::Simulation::NewStub(m.channel);
  pb::HelloRequest req;
  req.set_protocol_version(kProtocolVersion), req.set_client("laserfit-controller");
  auto ctx = m.context();
  ctx->set_wait_for_ready(true);  // a server still starting is waited for, up to the timeout
  m.check(m.cell->Hello(ctx.get(), req, &m.hello), "Hello");
  if (m.hello.protocol_version() != kProtocolVersion)
    m.fail("Hello", "speaks protocol version " + std::to_string(m.hello.protocol_version()) +
                        ", laserfit speaks " + std::to_string(kProtocolVersion));
  if (m.hello.points_per_profile() < 1 || m.hello.points_per_profile() > 100000)
    m.fail("Hello", "malformed reply: points per profile out of range");
}

RemoteCell::~RemoteCell() = default;
bool RemoteCell::simulated() const { return impl_->hello.simulated(); }
int RemoteCell::points_per_profile() const { return int(impl_->hello.points_per_profile()); }

std::pair<int, int> RemoteCell::begin_trial(uint64_t campaign_seed, int trial) {
  auto& m = *impl_;
  if (!simulated()) m.fail("BeginTrial", "the cell is not a simulation");
  pb::TrialRequest req;
  req.set_campaign_seed(campaign_seed), req.set_trial(uint32_t(trial));
  pb::TrialReply rep;
  // The reset prepares the trial's cell (teaching, references): allow it time.
  m.check(m.sim->BeginTrial(m.context(120).get(), req, &rep), "BeginTrial");
  return {int(rep.setting()), int(rep.start())};
}

robot::Joints RemoteCell::joints() {
  auto& m = *impl_;
  pb::ArmStateRequest req;
  req.set_arm(pb::ARM_ASSEMBLING);
  pb::ArmState rep;
  m.check(m.cell->GetArmState(m.context().get(), req, &rep), "GetArmState");
  return m.read("GetArmState", [&] { return wire::get(rep.q(), "arm state"); });
}

controller::MotionReport RemoteCell::move(const controller::MotionCommand& command) {
  auto& m = *impl_;
  pb::Trajectory req;
  wire::put(command, &req);
  pb::MotionResult rep;
  m.check(m.cell->Execute(m.context(command.path.duration_s()).get(), req, &rep), "Execute");
  return m.read("Execute", [&] { return wire::get(rep); });
}

// Profiles as they stream, in order, then the end message; a stream without it is a lost sweep.
controller::Sweep RemoteCell::scan(const controller::SweepRequest& request) {
  auto& m = *impl_;
  pb::SweepRequest req;
  wire::put(request, &req);
  auto ctx = m.context(request.length_mm / request.speed_mm_s);
  auto reader = m.cell->Sweep(ctx.get(), req);
  controller::Sweep out;
  std::optional<pb::SweepEnd> end;
  pb::SweepChunk chunk;
  while (reader->Read(&chunk)) {
    if (end) m.fail("Sweep", "malformed stream: a message after its end");
    if (chunk.has_end())
      end = chunk.end();
    else if (chunk.has_profile())
      m.read("Sweep", [&] { return wire::add(chunk.profile(), points_per_profile(), out), 0; });
    else
      m.fail("Sweep", "malformed stream: an empty message");
  }
  m.check(reader->Finish(), "Sweep");
  if (!end) m.fail("Sweep", "the stream ended without its end message (sweep lost)");
  if (end->profiles() != uint32_t(out.profiles.count))
    m.fail("Sweep", "the end message counts " + std::to_string(end->profiles()) + " profiles, " +
                        std::to_string(out.profiles.count) + " arrived");
  out.fault = end->fault().substr(0, 200), out.duration_s = end->duration_s();
  return out;
}

// Tried once, with a short deadline, even after a failure: the peer may still hear it.
void RemoteCell::stop() {
  auto& m = *impl_;
  pb::StopRequest req;
  req.set_reason("the controller stopped the trial");
  pb::StopReply rep;
  grpc::ClientContext ctx;
  ctx.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(1));
  (void)m.cell->Stop(&ctx, req, &rep);
}

std::optional<cell::Insertion> RemoteCell::judge() {
  auto& m = *impl_;
  if (m.lost || !simulated()) return std::nullopt;
  pb::JudgeRequest req;
  pb::Judgement rep;
  try {
    m.check(m.sim->Judge(m.context().get(), req, &rep), "Judge");
  } catch (const Error&) {
    return std::nullopt;  // asked after the trial ended: the outcome stays unjudged
  }
  if (!rep.moved()) return std::nullopt;
  cell::Insertion in;
  in.success = rep.success(), in.x_mm = rep.x_mm(), in.y_mm = rep.y_mm();
  in.angle_deg = rep.angle_deg(), in.depth_mm = rep.depth_mm();
  return in;
}

std::optional<Eigen::Vector2d> RemoteCell::true_error(const Pose& T_target_part_goal) {
  auto& m = *impl_;
  if (!simulated()) return std::nullopt;
  pb::JudgeRequest req;
  wire::put(T_target_part_goal, req.mutable_t_target_part_goal());
  pb::Judgement rep;
  m.check(m.sim->Judge(m.context().get(), req, &rep), "Judge");
  if (!rep.moved()) return std::nullopt;
  return Eigen::Vector2d(rep.lateral_error_mm(), rep.axial_error_mm());
}

}  // namespace laserfit::remote
