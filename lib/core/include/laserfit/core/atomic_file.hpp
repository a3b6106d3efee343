#pragma once
// Outputs are written to a temporary name next to the target and renamed on success, so a failed
// or interrupted run never leaves a partial file behind (the brief's bad-input rule).
#include <fstream>
#include <string>

namespace laserfit {

class AtomicFile {
 public:
  explicit AtomicFile(std::string path, bool binary = true);
  ~AtomicFile();  // removes the temporary if commit() was not reached
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  std::ofstream& stream() { return out_; }
  void commit();  // flush, check, rename over the target; throws laserfit::Error on failure
  const std::string& path() const { return path_; }

 private:
  std::string path_, tmp_;
  std::ofstream out_;
  bool committed_ = false;
};

// Writes a whole string atomically.
void write_file_atomic(const std::string& path, const std::string& content);

}  // namespace laserfit
