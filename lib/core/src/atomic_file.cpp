#include "laserfit/core/atomic_file.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "laserfit/core/error.hpp"
#include "laserfit/core/input_file.hpp"

namespace laserfit {

AtomicFile::AtomicFile(std::string path, bool binary) : path_(std::move(path)) {
  if (path_.empty()) throw Error("output path is empty");
  if (is_existing_directory(path_)) throw Error(shown_path(path_), "is a directory, not a file");
  tmp_ = path_ + ".tmp." + std::to_string(::getpid());
  out_.open(tmp_, binary ? std::ios::binary | std::ios::out : std::ios::out);
  if (!out_) throw Error(shown_path(path_), std::string("cannot write: ") + std::strerror(errno));
}

AtomicFile::~AtomicFile() {
  if (!committed_) {
    out_.close();
    std::remove(tmp_.c_str());
  }
}

void AtomicFile::commit() {
  out_.flush();
  const bool ok = static_cast<bool>(out_);
  out_.close();
  if (!ok || out_.fail()) {
    std::remove(tmp_.c_str());
    committed_ = true;
    throw Error(path_, "write failed (disk full?)");
  }
  if (std::rename(tmp_.c_str(), path_.c_str()) != 0) {
    const std::string why = std::strerror(errno);
    std::remove(tmp_.c_str());
    committed_ = true;
    throw Error(path_, "cannot rename temporary file into place: " + why);
  }
  committed_ = true;
}

void write_file_atomic(const std::string& path, const std::string& content) {
  AtomicFile f(path);
  f.stream().write(content.data(), static_cast<std::streamsize>(content.size()));
  f.commit();
}

}  // namespace laserfit
