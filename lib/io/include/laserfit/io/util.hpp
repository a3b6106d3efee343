#pragma once
// Small helpers shared by the readers and writers.
#include <algorithm>
#include <filesystem>
#include <ostream>
#include <string>

namespace laserfit::io {

inline std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return ext;
}

// Header comments are line based: newlines inside a value would corrupt the header.
inline std::string one_line(std::string s) {
  std::replace(s.begin(), s.end(), '\n', ' ');
  std::replace(s.begin(), s.end(), '\r', ' ');
  return s;
}

template <typename T>
void write_pod(std::ostream& out, const T* data, size_t n) {
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(sizeof(T) * n));
}

}  // namespace laserfit::io
