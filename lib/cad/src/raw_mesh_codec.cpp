// The reader child's answer, as bytes: a magic, then the mesh, part names, declared unit and
// warnings, every count followed by what it counts. The parent decodes it as untrusted input:
// a count is checked against the bytes left before anything is allocated from it.
#include <cmath>
#include <cstdint>
#include <cstring>

#include "laserfit/cad/isolate.hpp"
#include "laserfit/core/error.hpp"

namespace laserfit::cad {
namespace {

constexpr char kMagic[8] = {'L', 'F', 'R', 'M', 'E', 'S', 'H', '1'};

struct Writer {
  std::string out;
  void bytes(const void* p, size_t n) {
    if (n > 0) out.append(static_cast<const char*>(p), n);
  }
  void u64(uint64_t v) { bytes(&v, sizeof v); }
  void f64(double v) { bytes(&v, sizeof v); }
  void str(const std::string& s) { u64(s.size()), bytes(s.data(), s.size()); }
  void strings(const std::vector<std::string>& v) {
    u64(v.size());
    for (const auto& s : v) str(s);
  }
};

struct Reader {
  const std::string& in;
  const std::string& path;
  size_t at = 0;
  void fail(const std::string& what) const {
    throw Error(path, "the reader process answered garbage (" + what + ")");
  }
  void bytes(void* p, size_t n) {
    if (n == 0) return;  // an empty string's or vector's data() may be null
    if (n > in.size() - at) fail("truncated");
    std::memcpy(p, in.data() + at, n);
    at += n;
  }
  uint64_t u64() {
    uint64_t v;
    bytes(&v, sizeof v);
    return v;
  }
  double f64() {
    double v;
    bytes(&v, sizeof v);
    return v;
  }
  // A count of items of `size` bytes each, refused when the rest of the message cannot hold it.
  size_t count(size_t size) {
    const uint64_t n = u64();
    if (n > (in.size() - at) / size) fail("a count exceeds the message");
    return static_cast<size_t>(n);
  }
  std::string str() {
    std::string s(count(1), '\0');
    bytes(s.data(), s.size());
    return s;
  }
  std::vector<std::string> strings() {
    std::vector<std::string> v(count(sizeof(uint64_t)));
    for (auto& s : v) s = str();
    return v;
  }
};

}  // namespace

std::string encode_raw_mesh(const RawMesh& raw) {
  Writer w;
  w.bytes(kMagic, sizeof kMagic);
  w.u64(raw.mesh.vertices.size());
  for (const auto& v : raw.mesh.vertices) w.bytes(v.data(), 3 * sizeof(float));
  w.u64(raw.mesh.faces.size());
  for (const auto& f : raw.mesh.faces) w.bytes(f.data(), 3 * sizeof(int));
  w.strings(raw.parts);
  w.f64(raw.declared_to_mm);
  w.str(raw.declared_unit);
  w.strings(raw.warnings);
  return std::move(w.out);
}

RawMesh decode_raw_mesh(const std::string& bytes, const std::string& path) {
  Reader r{bytes, path};
  char magic[sizeof kMagic];
  r.bytes(magic, sizeof magic);
  if (std::memcmp(magic, kMagic, sizeof kMagic) != 0) r.fail("no magic");
  RawMesh raw;
  raw.mesh.vertices.resize(r.count(3 * sizeof(float)));
  for (auto& v : raw.mesh.vertices) r.bytes(v.data(), 3 * sizeof(float));
  raw.mesh.faces.resize(r.count(3 * sizeof(int)));
  const auto nv = static_cast<long long>(raw.mesh.vertices.size());
  for (auto& f : raw.mesh.faces) {
    r.bytes(f.data(), 3 * sizeof(int));
    for (int k = 0; k < 3; ++k)
      if (f[k] < 0 || f[k] >= nv) r.fail("a face index out of range");
  }
  raw.parts = r.strings();
  raw.declared_to_mm = r.f64();
  if (!(raw.declared_to_mm >= 0) || !std::isfinite(raw.declared_to_mm)) r.fail("bad unit");
  raw.declared_unit = r.str();
  raw.warnings = r.strings();
  if (r.at != bytes.size()) r.fail("trailing bytes");
  return raw;
}

RawMesh read_isolated(const std::string& path, const std::string& reader,
                      const IsolationLimits& limits, const std::function<RawMesh()>& read) {
  if (!limits.isolate) return read();
  return decode_raw_mesh(
      run_isolated(path, reader, limits, [&] { return encode_raw_mesh(read()); }), path);
}

}  // namespace laserfit::cad
