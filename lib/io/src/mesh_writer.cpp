#include "laserfit/io/mesh_writer.hpp"

#include <cstdint>
#include <cstring>
#include <filesystem>

#include "laserfit/core/atomic_file.hpp"
#include "laserfit/core/error.hpp"
#include "laserfit/io/util.hpp"

namespace laserfit::io {
namespace {

void write_ply(AtomicFile& f, const TriMesh& m, const std::map<std::string, std::string>& c) {
  auto& out = f.stream();
  out << "ply\nformat binary_little_endian 1.0\n";
  for (const auto& [k, v] : c) out << "comment laserfit." << k << " " << one_line(v) << "\n";
  out << "element vertex " << m.vertices.size() << "\n"
      << "property float x\nproperty float y\nproperty float z\n"
      << "element face " << m.faces.size() << "\n"
      << "property list uchar int vertex_indices\nend_header\n";
  for (const auto& v : m.vertices) write_pod(out, v.data(), 3);
  for (const auto& t : m.faces) {
    const uint8_t n = 3;
    write_pod(out, &n, 1);
    write_pod(out, t.data(), 3);
  }
}

void write_stl(AtomicFile& f, const TriMesh& m, const std::map<std::string, std::string>& c) {
  auto& out = f.stream();
  char header[80] = {};
  // Never start with "solid": readers would take the file for ASCII STL.
  std::string title = "laserfit binary STL, mm";
  if (auto it = c.find("source"); it != c.end()) title += ", from " + it->second;
  std::strncpy(header, title.c_str(), sizeof(header) - 1);
  out.write(header, sizeof(header));
  const uint32_t n = static_cast<uint32_t>(m.faces.size());
  write_pod(out, &n, 1);
  for (int i = 0; i < static_cast<int>(m.faces.size()); ++i) {
    const Eigen::Vector3f nrm = m.face_normal(i);
    write_pod(out, nrm.data(), 3);
    for (int k = 0; k < 3; ++k) write_pod(out, m.vertices[m.faces[i][k]].data(), 3);
    const uint16_t attr = 0;
    write_pod(out, &attr, 1);
  }
}

}  // namespace

void write_mesh(const std::string& path, const TriMesh& mesh,
                const std::map<std::string, std::string>& comments) {
  const std::string ext = lower_extension(path);
  if (ext != ".ply" && ext != ".stl")
    throw Error(path, "unsupported mesh output format '" + ext + "' (use .ply or .stl)");
  if (mesh.empty()) throw Error(path, "refusing to write an empty mesh");
  AtomicFile f(path);
  if (ext == ".ply")
    write_ply(f, mesh, comments);
  else
    write_stl(f, mesh, comments);
  f.commit();
}

}  // namespace laserfit::io
