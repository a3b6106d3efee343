// The on-line loop over the cell protocol (gRPC on loopback) against the simulated cell served
// in this process: it gives what `sim` gives, and every fault the server injects stops the loop
// with the stop sent and no motion command after the fault.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>

#include "laserfit/controller/sim.hpp"
#include "laserfit/core/error.hpp"
#include "laserfit/remote/client.hpp"
#include "laserfit/remote/server.hpp"

using namespace laserfit;

namespace {
const std::string kSource = LASERFIT_SOURCE_DIR;

// A short needle trial (no intermediate stages, one correction round): trial 0 of seed 1.
struct Bench {
  cell::CellSettings cs = [] {
    auto cs = cell::load_cell(kSource + "/cells/needle.yaml");
    cs.stages.clear();
    return cs;
  }();
  controller::ControllerSettings s = [this] {
    auto s = controller::settings_for(cs);
    s.thresholds = registration::load_thresholds(kSource + "/reports/paper/thresholds_needle.yaml");
    s.max_rounds = 1;
    return s;
  }();
  controller::TrialPlan t = controller::plan_trial(cs, 1, 0);
  controller::Campaign campaign{cs, s, 1};
  Bench() { campaign.prepare(t); }
  controller::Outcome run(controller::CellPort& cell) {
    return controller::run_insertion(cell, campaign.cell(t.robot),
                                     campaign.setup(t.robot, t.setting),
                                     controller::Strategy::Laser, t.start, t.seed, s);
  }
  std::unique_ptr<remote::CellSimServer> serve(std::vector<std::string> inject = {}) {
    remote::ServerSettings ss;
    ss.listen = "127.0.0.1:0";
    for (const auto& x : inject) ss.inject.push_back(remote::parse_injection(x));
    return std::make_unique<remote::CellSimServer>(cs, s, ss);
  }
  remote::ClientSettings client(int port) const {
    return {"127.0.0.1:" + std::to_string(port), 10, ""};  // ASan builds are slow
  }
};
}  // namespace

// Over the wire the outcome is sim's: result, log, scans and the insertion, exact (the path
// samples, profiles and poses cross the wire bit for bit).
TEST(Remote, RunOverTheWireIsSim) {
  Bench u;
  auto server = u.serve();
  remote::RemoteCell cell(u.client(server->port()));
  ASSERT_TRUE(cell.simulated());
  EXPECT_EQ(cell.points_per_profile(), 2048);
  const auto [setting, start] = cell.begin_trial(1, 0);
  EXPECT_EQ(setting, u.t.setting);
  EXPECT_EQ(start, u.t.start);
  const auto a = u.run(cell);
  const auto b = controller::run_insertion(u.campaign.cell(u.t.robot),
                                           u.campaign.setup(u.t.robot, u.t.setting),
                                           controller::Strategy::Laser, u.t.start, u.t.seed, u.s);
  EXPECT_EQ(a.result, b.result);
  EXPECT_EQ(a.log, b.log);
  EXPECT_EQ(a.scans, b.scans);
  EXPECT_EQ(a.insertion.x_mm, b.insertion.x_mm);
  EXPECT_EQ(a.insertion.depth_mm, b.insertion.depth_mm);
  EXPECT_FALSE(a.cell_fault);
  EXPECT_EQ(server->counts().stops, 0);
}

// Each injected fault: the trial is refused for the cell's reason, the stop is sent (but to a
// server that went away), and the server saw no Execute or Sweep after the faulty call. The
// motion faults strike the approach, before any scan, to keep the sanitizer run short; a fault
// on a correction is test_cell_port's.
TEST(Remote, EveryInjectedFaultStopsWithNoCommandAfterIt) {
  struct Case {
    std::string inject, reason;
    int moves, sweeps;  // the server's Execute and Sweep calls, the faulty one included
  };
  const std::vector<Case> cases = {
      {"motion-fault@1", "the assembling arm reported a fault: cartesian_reflex", 1, 0},
      {"malformed@1", "Execute: malformed reply: motion result: 6 joint values", 1, 0},
      {"out-of-range@1", "the assembling arm's report: reported joint 1 at 4 rad", 1, 0},
      {"empty-sweep@1", "the cell returned a scan with no data", 1, 1},
      {"truncated-sweep@1", "Sweep: the stream ended without its end message", 1, 1},
      {"stall@3", "Sweep: no answer in time (timeout)", 1, 0},
      {"disconnect@3", "Sweep: connection lost", 1, 0},
  };
  Bench u;  // the client's model and taught poses, prepared once
  for (const auto& c : cases) {
    SCOPED_TRACE(c.inject);
    auto server = u.serve({c.inject});
    auto settings = u.client(server->port());
    if (c.inject.rfind("stall", 0) == 0) settings.timeout_s = 3;  // what the stall waits for
    remote::RemoteCell cell(settings);
    cell.begin_trial(1, 0);
    const auto o = u.run(cell);
    EXPECT_TRUE(o.cell_fault);
    EXPECT_FALSE(o.success);
    EXPECT_NE(o.result.find(c.reason), std::string::npos) << o.result;
    server->shutdown();  // releases a stalled call
    const auto n = server->counts();
    EXPECT_EQ(n.moves, c.moves);
    EXPECT_EQ(n.sweeps, c.sweeps);
    if (c.inject.rfind("disconnect", 0) != 0) {
      EXPECT_EQ(n.stops, 1);
    }
  }
}

// A peer that is not there, or a bad injection text: one error naming it.
TEST(Remote, NoPeerAndBadInjectionAreOneError) {
  Bench u;
  auto nobody = u.client(1);
  nobody.timeout_s = 1;
  EXPECT_THROW(remote::RemoteCell{nobody}, controller::CellFailure);
  EXPECT_THROW(remote::parse_injection("explode@1"), Error);
  EXPECT_THROW(remote::parse_injection("stall@0"), Error);
}

// With a certificate the channel is TLS: a client that trusts it is served, a plaintext client
// is not (it times out on Hello). The certificate is made here (openssl, for 127.0.0.1).
TEST(Remote, TlsWhenACertificateIsGiven) {
  const std::string dir = ::testing::TempDir() + "laserfit_tls_" + std::to_string(::getpid());
  ASSERT_EQ(std::system(("mkdir -p " + dir +
                         " && openssl req -x509 -newkey rsa:2048 -nodes "
                         "-keyout " +
                         dir + "/key.pem -out " + dir +
                         "/cert.pem -days 1 "
                         "-subj /CN=localhost -addext subjectAltName=IP:127.0.0.1 2>/dev/null")
                            .c_str()),
            0);
  Bench u;
  remote::ServerSettings ss;
  ss.listen = "127.0.0.1:0", ss.tls_cert = dir + "/cert.pem", ss.tls_key = dir + "/key.pem";
  remote::CellSimServer server(u.cs, u.s, ss);
  auto c = u.client(server.port());
  c.tls_ca = dir + "/cert.pem";
  remote::RemoteCell cell(c);
  cell.begin_trial(1, 0);
  EXPECT_TRUE(cell.joints().allFinite());
  auto plain = u.client(server.port());
  plain.timeout_s = 1;
  EXPECT_THROW(remote::RemoteCell{plain}, Error);
  ss.tls_key.clear();  // a certificate without its key: one error
  EXPECT_THROW(remote::CellSimServer(u.cs, u.s, ss), Error);
}
