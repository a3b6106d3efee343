#include "laserfit/bench/checksum.hpp"

#include <boost/crc.hpp>
#include <cstdio>
#include <fstream>
#include <vector>

#include "laserfit/core/error.hpp"

namespace laserfit::bench {

uint32_t crc32(const std::string& bytes) {
  boost::crc_32_type c;
  c.process_bytes(bytes.data(), bytes.size());
  return c.checksum();
}

uint32_t crc32_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path, "cannot read the file");
  boost::crc_32_type c;
  std::vector<char> buf(1 << 20);
  while (in) {
    in.read(buf.data(), std::streamsize(buf.size()));
    c.process_bytes(buf.data(), size_t(in.gcount()));
  }
  return c.checksum();
}

std::string hex32(uint32_t v) {
  char s[9];
  std::snprintf(s, sizeof s, "%08x", v);
  return s;
}

}  // namespace laserfit::bench
