// The benchmark runner: parallel trials, a journal for resuming, atomic final files.
#include "laserfit/bench/runner.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <mutex>
#include <set>

#include "laserfit/bench/checksum.hpp"
#include "laserfit/bench/dataset.hpp"
#include "laserfit/bench/memory.hpp"
#include "laserfit/core/atomic_file.hpp"
#include "laserfit/core/build_info.hpp"
#include "laserfit/core/error.hpp"
#include "laserfit/core/parallel.hpp"

namespace laserfit::bench {
namespace fs = std::filesystem;

namespace {

constexpr const char* kJournal = "journal.jsonl";

io::Json run_header(const Benchmark& b, const RunSettings& s,
                    const std::vector<registration::Method>& methods) {
  std::vector<std::string> names;
  for (const auto m : methods) names.push_back(name_of(m));
  return {{"format", "laserfit.bench/1"},
          {"benchmark", b.name},
          {"file", b.file},
          {"build", build_info()},
          {"trials_selected", select_trials(b, s.only_repetitions, s.only_scenes).size()},
          {"digest", hex32(uint32_t(b.digest))},
          {"seed", b.seed},
          {"methods", names},
          {"shard", s.shard.text()},
          {"repetitions", s.only_repetitions},
          {"scenes", s.only_scenes},
          {"thresholds", s.thresholds_file.empty() ? "" : hex32(crc32_file(s.thresholds_file))},
          {"trials_total", enumerate_trials(b).size()}};
}

// One writer per result directory: a second run into the same --out (a resubmitted array task,
// a mistyped shard index) would repeat every trial and interleave the journal. The lock is the
// kernel's (flock), so it dies with its holder, even on kill -9.
class DirLock {
 public:
  explicit DirLock(const std::string& dir)
      : fd_(::open((dir + "/.lock").c_str(), O_RDWR | O_CREAT, 0644)) {
    if (fd_ < 0) throw Error(dir, "cannot create the run's lock file");
    if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
      char pid[32] = {};
      (void)!::pread(fd_, pid, sizeof pid - 1, 0);
      ::close(fd_);
      throw Error(dir, std::string("another laserfit bench is writing here (pid ") + pid +
                           "); wait for it to finish or choose another --out");
    }
    const std::string me = std::to_string(::getpid());
    (void)!::ftruncate(fd_, 0);
    (void)!::pwrite(fd_, me.data(), me.size(), 0);
  }
  ~DirLock() { ::close(fd_); }
  DirLock(const DirLock&) = delete;
  DirLock& operator=(const DirLock&) = delete;

 private:
  int fd_;
};

// Reads the journal's complete lines (a torn last line from a kill is dropped) and rewrites it
// without the torn tail, so appending continues on a line boundary.
std::map<int, std::vector<io::Json>> resume(const std::string& path, const io::Json& header) {
  std::map<int, std::vector<io::Json>> done;
  std::ifstream in(path);
  if (!in) return done;
  std::string line, kept;
  bool first = true;
  while (std::getline(in, line)) {
    if (in.eof()) break;  // no newline: torn
    io::Json j;
    try {
      j = io::Json::parse(line);
    } catch (const io::Json::exception&) {
      break;
    }
    if (first) {
      if (run_identity(j) != run_identity(header))
        throw Error(path,
                    "a journal of a different run (benchmark content, methods, shard, selection, "
                    "thresholds or build differ); remove it or choose another --out");
      first = false;
    } else {
      done[j.at("trial").get<int>()] = j.at("records").get<std::vector<io::Json>>();
    }
    kept += line + "\n";
  }
  if (first) return done;  // empty or torn header: start afresh
  write_file_atomic(path, kept);
  return done;
}

void progress_line(bool tty, const std::string& name, size_t done, size_t total, double rate,
                   size_t left) {
  const double eta = rate > 0 ? double(left) / rate : 0;
  char buf[200];
  if (tty) {
    const int w = 30, f = total ? int(w * done / total) : w;
    std::snprintf(buf, sizeof buf, "\r%s [%s%s] %zu/%zu trials  %.2f trials/s  ETA %.0f s ",
                  name.c_str(), std::string(f, '#').c_str(), std::string(w - f, '-').c_str(), done,
                  total, rate, eta);
    std::cerr << buf << (done == total ? "\n" : "") << std::flush;
  } else {
    std::snprintf(buf, sizeof buf, "%s: %zu/%zu trials, %.2f trials/s, ETA %.0f s\n", name.c_str(),
                  done, total, rate, eta);
    std::cerr << buf;
  }
}

// A generated dataset's files and their CRC-32s from its manifest (none without a dataset).
std::map<std::string, std::string> dataset_crcs(const Benchmark& b, const std::string& dir) {
  std::map<std::string, std::string> crc;
  if (dir.empty()) return crc;
  const std::string mf = dir + "/manifest.json";
  const io::Json manifest = io::read_json(mf);
  if (manifest.value("digest", "") != hex32(uint32_t(b.digest)))
    throw Error(mf, "generated from a different benchmark file than " + b.file);
  try {
    for (const auto& f : manifest.at("files"))
      crc[manifest_path(mf, f.at("path").get<std::string>())] = f.at("crc32");
  } catch (const io::Json::exception& e) {
    throw Error(mf, std::string("not a laserfit dataset manifest: ") + e.what());
  }
  return crc;
}

// results.jsonl, summary.csv and run.json from every trial's records, in trial order.
void finish_run(const RunSettings& s, const io::Json& header,
                const std::map<int, std::vector<io::Json>>& done, RunSummary& sum) {
  std::vector<io::Json> records;
  for (const auto& [idx, recs] : done)
    for (const auto& r : recs) records.push_back(r);
  sum.records = records.size();
  io::Json run = header;
  run["jobs"] = s.jobs, run["jobs_source"] = s.jobs_source.empty() ? "--jobs" : s.jobs_source;
  run["dataset"] = s.dataset_dir, run["trials"] = sum.trials, run["resumed"] = sum.resumed;
  run["records"] = records.size(), run["wall_s"] = sum.wall_s,
  run["trials_per_s"] = sum.trials_per_s;
  write_results(s.out_dir, records, run);
}

}  // namespace

RunSummary run_benchmark(const Benchmark& b, const RunSettings& s) {
  const auto t_start = std::chrono::steady_clock::now();
  const auto methods = s.methods.empty() ? b.methods : s.methods;
  std::optional<registration::Thresholds> thresholds;
  if (!s.thresholds_file.empty()) thresholds = registration::load_thresholds(s.thresholds_file);
  fs::create_directories(s.out_dir);
  const DirLock lock(s.out_dir);
  const io::Json header = run_header(b, s, methods);
  const std::string journal = s.out_dir + "/" + kJournal;
  std::map<int, std::vector<io::Json>> done = resume(journal, header);

  std::vector<Trial> pending;
  size_t mine = 0;
  for (const auto& t : select_trials(b, s.only_repetitions, s.only_scenes)) {
    if (!s.shard.contains(t)) continue;
    ++mine;
    if (!done.count(t.index)) pending.push_back(t);
  }
  RunSummary sum;
  sum.resumed = mine - pending.size();
  if (sum.resumed && s.progress)
    std::cerr << b.name << ": resuming, " << sum.resumed << " trials already done\n";

  std::map<int, PreparedScene> scenes;  // only the scenes this run needs
  for (const auto& t : pending)
    if (!scenes.count(t.scene)) scenes.emplace(t.scene, prepare_scene(b, t.scene));
  const std::map<std::string, std::string> crc = dataset_crcs(b, s.dataset_dir);
  // A dataset file is used only if it still matches its manifest.
  auto checked = [&](const std::string& rel) {
    const std::string path = s.dataset_dir + "/" + rel;
    const auto it = crc.find(rel);
    if (it == crc.end()) throw Error(path, "not in the dataset's manifest");
    if (hex32(crc32_file(path)) != it->second)
      throw Error(path, "differs from the dataset's manifest (CRC-32)");
    return path;
  };

  std::ofstream jout(journal, std::ios::app);
  if (done.empty()) jout << header.dump() << "\n" << std::flush;
  if (!jout) throw Error(journal, "cannot write the journal");
  MemoryProbe::set_exclusive(s.jobs <= 1);
  TrialOptions opt;
  opt.methods = methods;
  opt.thresholds = thresholds ? &*thresholds : nullptr;
  if (s.overlays) fs::create_directories(opt.overlay_dir = s.out_dir + "/overlays");

  size_t finished = 0;
  std::mutex m;  // the journal, `done` and the progress line
  const bool tty = isatty(fileno(stderr));
  // On an error no new trial starts; the journal keeps every finished one for the next run.
  parallel_for(pending.size(), s.jobs, [&](size_t i) {
    const Trial& t = pending[i];
    const PreparedScene& p = scenes.at(t.scene);
    const std::string id = std::to_string(t.index);
    const TrialInput in = s.dataset_dir.empty() ? trial_input(b, p, t)
                                                : read_trial(p, checked("scans/" + id + ".pcd"),
                                                             checked("gt/" + id + ".json"));
    auto recs = run_trial(b, p, t, in, opt);
    std::lock_guard<std::mutex> l(m);
    jout << io::Json{{"trial", t.index}, {"records", recs}}.dump() << "\n" << std::flush;
    done[t.index] = std::move(recs);
    const size_t f = ++finished;
    const double el =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
    if (s.progress)
      progress_line(tty, b.name, sum.resumed + f, mine, f / el, mine - sum.resumed - f);
  });
  jout.close();

  sum.trials = mine;
  sum.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  sum.trials_per_s = pending.empty() ? 0 : double(pending.size()) / sum.wall_s;
  finish_run(s, header, done, sum);
  fs::remove(journal);
  return sum;
}

}  // namespace laserfit::bench
