#pragma once
#include <cstddef>
#include <string>

namespace laserfit::io {

// Throws laserfit::Error naming `path` when the OFF header's vertex or face count exceeds
// `max_elements` or cannot fit in the file's `file_size` bytes.
void check_off_header(const std::string& path, size_t file_size, size_t max_elements);

}  // namespace laserfit::io
