// laserfit-controller cell-sim --listen HOST:PORT --cell C.yaml [--inject KIND@N ...]
#include <csignal>
#include <cstdlib>
#include <iostream>

#include "commands.hpp"
#include "laserfit/core/error.hpp"
#include "laserfit/remote/server.hpp"

namespace laserfit::ctl {
namespace {

struct Options {
  std::string cell, listen = "127.0.0.1:50051", tls_cert, tls_key;
  std::vector<std::string> inject;
};

int run(const Options& o) {
  const cell::CellSettings cs = cell::load_cell(o.cell);
  remote::ServerSettings ss;
  ss.listen = o.listen, ss.tls_cert = o.tls_cert, ss.tls_key = o.tls_key;
  for (const auto& x : o.inject) ss.inject.push_back(remote::parse_injection(x));
  // A disconnect is the process going away mid-call, as a crashed bridge would.
  ss.on_disconnect = [] { std::_Exit(3); };
  remote::CellSimServer server(cs, controller::settings_for(cs), ss);
  std::signal(SIGINT, [](int) { std::_Exit(0); });
  std::signal(SIGTERM, [](int) { std::_Exit(0); });
  // The port on stdout (one line) for a script that asked for port 0.
  std::cout << "cell-sim: " << cs.task << " cell listening on port " << server.port() << std::endl;
  server.wait();
  return 0;
}

}  // namespace

Command add_cell_sim(CLI::App& root) {
  auto o = std::make_shared<Options>();
  auto* app = root.add_subcommand(
      "cell-sim", "Serve the simulated dual-arm cell over the cell protocol (gRPC, version 1)");
  app->add_option("--cell", o->cell, "cell definition (YAML, cells/*.yaml)")->required();
  app->add_option("--listen", o->listen,
                  "HOST:PORT to listen on (loopback unless told otherwise; port 0: any free)")
      ->capture_default_str();
  app->add_option("--tls-cert", o->tls_cert, "PEM certificate: serve TLS (with --tls-key)");
  app->add_option("--tls-key", o->tls_key, "PEM private key of --tls-cert");
  app->add_option(
      "--inject", o->inject,
      "inject a fault at the N-th call of its kind, KIND@N; KIND: " + remote::injection_kinds());
  return {app, [o] { return run(*o); }};
}

}  // namespace laserfit::ctl
