#pragma once
// The simulated dual-arm cell served over the cell protocol (`laserfit-controller cell-sim`): the
// Cell service (arms, scanner, stop) over controller::SimCell, and the Simulation service (a
// trial's reset, the judged insertion). Faults can be injected to test a client's safety.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "laserfit/cell/cell.hpp"
#include "laserfit/controller/controller.hpp"

namespace laserfit::remote {

// A fault the server injects at the `at`-th call (from 1) of its kind: motion faults count
// Execute calls, sweep faults Sweep calls, stall and disconnect every Cell call.
enum class FaultKind {
  motion_fault,     // the arm stops halfway and reports a reflex
  malformed,        // the motion's reply reports 6 joints
  out_of_range,     // the motion's reply reports joint 1 beyond its limit
  empty_sweep,      // the sweep streams no profile
  truncated_sweep,  // the sweep stream ends halfway, without its end message
  stall,            // the call never answers
  disconnect,       // the server goes away during the call
};
struct Injection {
  FaultKind kind = FaultKind::motion_fault;
  int at = 1;
};
// "motion-fault@2", "stall@5", ...: throws laserfit::Error naming the text.
Injection parse_injection(const std::string& text);
std::string injection_kinds();  // the accepted names, for --help

struct ServerSettings {
  std::string listen = "127.0.0.1:50051";  // port 0: any free port (see CellSimServer::port)
  std::string tls_cert, tls_key;           // PEM files: serve TLS (both or neither)
  std::vector<Injection> inject;
  // What a `disconnect` does; by default the server shuts down (cell-sim exits the process).
  std::function<void()> on_disconnect;
};

class CellSimServer {
 public:
  // Starts serving; throws laserfit::Error when the address cannot be bound.
  CellSimServer(const cell::CellSettings& cs, const controller::ControllerSettings& s,
                const ServerSettings& ss);
  ~CellSimServer();
  int port() const;
  // The Cell calls served so far: all of them, Execute, Sweep, Stop.
  struct Counts {
    int calls = 0, moves = 0, sweeps = 0, stops = 0;
  };
  Counts counts() const;
  void wait();      // until shutdown()
  void shutdown();  // cancels calls in flight

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace laserfit::remote
