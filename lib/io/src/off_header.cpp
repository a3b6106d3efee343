// OFF ("Object File Format") headers as assimp's reader reads them: optional prefixes ST, C, N,
// 4 and n before the keyword OFF (itself optional), comment lines starting with '#', then an
// optional dimension (after the n prefix), the vertex count and the face count. assimp
// allocates both arrays from these counts before it reads a line, so a corrupt count (a flipped
// digit, 10^15 faces) is refused here instead.
#include "off_header.hpp"

#include <algorithm>
#include <fstream>
#include <limits>
#include <utility>

#include "laserfit/core/error.hpp"

namespace laserfit::io {
namespace {

struct Cursor {
  const std::string& s;
  size_t at = 0;
  bool done() const { return at >= s.size(); }
  char peek() const { return done() ? '\0' : s[at]; }
  bool blank() const { return peek() == ' ' || peek() == '\t' || peek() == '\n' || peek() == '\r'; }
  // Blanks, line ends and whole comment lines.
  void skip() {
    for (;;) {
      while (!done() && blank()) ++at;
      if (peek() != '#') return;
      while (!done() && peek() != '\n' && peek() != '\r') ++at;
    }
  }
  bool take(const char* word) {
    const size_t n = std::char_traits<char>::length(word);
    if (s.compare(at, n, word) != 0) return false;
    at += n;
    return true;
  }
  // The leading digits as a count, saturating instead of wrapping; none is 0.
  size_t count() {
    size_t v = 0;
    constexpr size_t kMax = std::numeric_limits<size_t>::max() / 10 - 10;
    for (; !done() && peek() >= '0' && peek() <= '9'; ++at)
      v = v > kMax ? kMax : v * 10 + static_cast<size_t>(peek() - '0');
    return v;
  }
};

}  // namespace

void check_off_header(const std::string& path, size_t file_size, size_t max_elements) {
  std::ifstream in(path, std::ios::binary);
  std::string head(65536, '\0');  // a header longer than this is not OFF's counts
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<size_t>(in.gcount()));
  Cursor c{head};
  c.skip();
  c.take("ST");
  c.take("C");
  c.take("N");
  c.take("4");
  const bool dimension = c.take("n");
  c.take("OFF");
  c.skip();
  if (dimension) c.count(), c.skip();
  const size_t vertices = c.count();
  c.skip();
  const size_t faces = c.count();
  for (const auto& [n, what] : {std::pair{vertices, "vertices"}, std::pair{faces, "faces"}})
    if (n > max_elements)
      throw Error(path, "header claims " + std::to_string(n) + " " + what +
                            ", more than the limit of " + std::to_string(max_elements));
  // Every vertex and every face is a line of its own: at least one byte each.
  if (vertices + faces > file_size - std::min(c.at, file_size))
    throw Error(path, "truncated: the OFF header announces " + std::to_string(vertices) +
                          " vertices and " + std::to_string(faces) + " faces, one line each, " +
                          "in a file of " + std::to_string(file_size) + " bytes");
}

}  // namespace laserfit::io
