#pragma once
// CRC-32 (boost::crc, the IEEE 802.3 polynomial zlib and `cksum -a crc32b` use) of bytes and
// files: dataset manifests and the benchmark digest a resumed run must match.
#include <cstdint>
#include <string>

namespace laserfit::bench {

uint32_t crc32(const std::string& bytes);
uint32_t crc32_file(const std::string& path);  // throws laserfit::Error naming it if unreadable
std::string hex32(uint32_t v);                 // 8 lowercase hex digits

}  // namespace laserfit::bench
