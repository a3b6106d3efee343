#include "laserfit/bench/dataset.hpp"

#include <algorithm>
#include <chrono>
#include <filesystem>

#include "laserfit/bench/checksum.hpp"
#include "laserfit/bench/trial.hpp"
#include "laserfit/core/atomic_file.hpp"
#include "laserfit/core/error.hpp"
#include "laserfit/core/input_file.hpp"
#include "laserfit/core/parallel.hpp"
#include "laserfit/io/cloud_io.hpp"

namespace laserfit::bench {
namespace fs = std::filesystem;

DatasetSummary generate_dataset(const Benchmark& b, const std::string& dir, int jobs,
                                const std::vector<int>& repetitions,
                                const std::vector<std::string>& scene_names) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::vector<Trial> trials = select_trials(b, repetitions, scene_names);
  fs::create_directories(dir + "/scans");
  fs::create_directories(dir + "/gt");
  std::map<int, PreparedScene> scenes;
  for (const auto& t : trials)
    if (!scenes.count(t.scene)) scenes.emplace(t.scene, prepare_scene(b, t.scene));
  fs::create_directories(dir + "/refs");
  io::Json ref_files = io::Json::array();
  for (const auto& [i, p] : scenes)
    for (size_t k = 0; k < p.reference.size(); ++k) {
      const std::string rel =
          "refs/" + b.scenes[i].name + "_" + b.scenes[i].targets[k].object + ".pcd";
      io::write_cloud(dir + "/" + rel, p.reference[k]);
      ref_files.push_back({{"path", rel},
                           {"bytes", fs::file_size(dir + "/" + rel)},
                           {"crc32", hex32(crc32_file(dir + "/" + rel))}});
    }
  std::vector<io::Json> files(trials.size());
  parallel_for(trials.size(), jobs, [&](size_t i) {
    const Trial& t = trials[i];
    const TrialInput in = trial_input(b, scenes.at(t.scene), t);
    const std::string id = std::to_string(t.index);
    PointCloud scan = in.scan;
    scan.metadata["benchmark"] = b.name;
    scan.metadata["trial"] = id;
    io::write_cloud(dir + "/scans/" + id + ".pcd", scan);
    write_file_atomic(dir + "/gt/" + id + ".json",
                      input_json(b, scenes.at(t.scene), t, in).dump(2) + "\n");
    io::Json f = io::Json::array();
    for (const std::string& rel : {"scans/" + id + ".pcd", "gt/" + id + ".json"})
      f.push_back({{"path", rel},
                   {"bytes", fs::file_size(dir + "/" + rel)},
                   {"crc32", hex32(crc32_file(dir + "/" + rel))}});
    files[i] = f;
  });
  DatasetSummary s;
  io::Json list = ref_files;
  for (const auto& e : ref_files) s.bytes += e.at("bytes").get<size_t>();
  for (const auto& f : files)
    for (const auto& e : f) {
      list.push_back(e);
      s.bytes += e.at("bytes").get<size_t>();
    }
  write_file_atomic(
      dir + "/manifest.json",
      io::Json{{"format", "laserfit.dataset/1"},
               {"benchmark", b.name},
               {"file", b.file},
               {"digest", hex32(uint32_t(b.digest))},
               {"seed", b.seed},
               {"trials", trials.size()},
               {"tolerance", {{"translation_mm", b.t_tol_mm}, {"rotation_deg", b.r_tol_deg}}},
               {"files", list}}
              .dump(1) +
          "\n");
  s.trials = trials.size();
  s.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return s;
}

std::string manifest_path(const std::string& manifest, const std::string& path) {
  const fs::path p(path);
  bool up = false;
  for (const auto& part : p) up |= part == "..";
  if (path.empty() || p.is_absolute() || up || path.find('\0') != std::string::npos)
    throw Error(manifest, "file path '" + path + "' leaves the dataset");
  return path;
}

void verify_dataset(const std::string& dir) {
  const io::Json manifest = io::read_json(dir + "/manifest.json");
  try {
    for (const auto& f : manifest.at("files")) {
      const std::string path =
          dir + "/" + manifest_path(dir + "/manifest.json", f.at("path").get<std::string>());
      require_input_file(path, "listed in the manifest", EmptyFile::allowed);
      if (fs::file_size(path) != f.at("bytes").get<size_t>() ||
          hex32(crc32_file(path)) != f.at("crc32"))
        throw Error(path, "differs from the manifest (size or CRC-32)");
    }
  } catch (const io::Json::exception& e) {
    throw Error(dir + "/manifest.json",
                std::string("not a laserfit dataset manifest: ") + e.what());
  }
}

}  // namespace laserfit::bench
