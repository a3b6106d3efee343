#pragma once
// The controller's side of the cell protocol (lib/remote/proto/laserfit/cell/v1/cell.proto): a
// CellPort whose calls go over gRPC to a lab's bridge or to `laserfit-controller cell-sim`.
// Every reply is checked before the loop acts on it; a lost peer, a timeout or a malformed reply
// throws laserfit::Error naming the endpoint, which ends the trial as a refusal (the stop is
// still tried, once, with a short deadline). After a failure no further call is made.
#include <memory>
#include <string>

#include "laserfit/controller/cell_port.hpp"

namespace laserfit::remote {

inline constexpr unsigned kProtocolVersion = 1;

struct ClientSettings {
  std::string endpoint;   // HOST:PORT
  double timeout_s = 10;  // per call, on top of a motion's or sweep's own duration
  std::string tls_ca;     // PEM file of the CA that signed the server's certificate: TLS
};

class RemoteCell : public controller::CellPort {
 public:
  // Connects and says Hello: a peer that does not answer in time or speaks another protocol
  // version throws.
  explicit RemoteCell(const ClientSettings& s);
  ~RemoteCell() override;
  bool simulated() const;
  int points_per_profile() const;
  // A simulated cell's reset to trial `trial` of the campaign `campaign_seed` (Simulation
  // service); the setting and start configuration it put the arm in.
  std::pair<int, int> begin_trial(uint64_t campaign_seed, int trial);

  robot::Joints joints() override;
  controller::MotionReport move(const controller::MotionCommand& command) override;
  controller::Sweep scan(const controller::SweepRequest& request) override;
  void stop() override;
  std::optional<cell::Insertion> judge() override;
  std::optional<Eigen::Vector2d> true_error(const Pose& T_target_part_goal) override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace laserfit::remote
