// Mesh formats through assimp. Units: only COLLADA (<unit meter=...>) and glTF (metres by
// specification) declare one; for the rest the caller decides (user or guess).
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <assimp/Importer.hpp>
#include <fstream>
#include <functional>
#include <regex>
#include <set>

#include "laserfit/cad/import.hpp"
#include "laserfit/core/error.hpp"
#include "laserfit/io/util.hpp"

namespace laserfit::cad {
namespace {

Eigen::Matrix4f to_eigen(const aiMatrix4x4& m) {
  Eigen::Matrix4f e;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) e(r, c) = m[r][c];
  return e;
}

void append_mesh(const aiMesh& am, const Eigen::Matrix4f& T, TriMesh& out) {
  const int offset = static_cast<int>(out.vertices.size());
  for (unsigned i = 0; i < am.mNumVertices; ++i) {
    const Eigen::Vector4f v(am.mVertices[i].x, am.mVertices[i].y, am.mVertices[i].z, 1.f);
    out.vertices.emplace_back((T * v).head<3>());
  }
  for (unsigned f = 0; f < am.mNumFaces; ++f) {
    const aiFace& face = am.mFaces[f];
    if (face.mNumIndices != 3) continue;  // points and lines carry no surface
    out.faces.emplace_back(offset + static_cast<int>(face.mIndices[0]),
                           offset + static_cast<int>(face.mIndices[1]),
                           offset + static_cast<int>(face.mIndices[2]));
  }
  if (T.topLeftCorner<3, 3>().determinant() < 0)
    for (int f = static_cast<int>(out.faces.size()) - 1; f >= 0 && out.faces[f][0] >= offset; --f)
      std::swap(out.faces[f][1], out.faces[f][2]);
}

// COLLADA's <asset><unit meter="0.001"/>. assimp applies it itself (its output is then in
// metres), so a declared unit means "metres now". Absent means "1 metre" by the spec, but
// exporters that omit it almost always meant the numbers as they stand: treat it as undeclared.
double collada_unit(const std::string& path, std::string& declared) {
  std::ifstream in(path);
  std::string head(65536, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<size_t>(in.gcount()));
  std::smatch m;
  if (std::regex_search(head, m, std::regex(R"(<unit[^>]*meter\s*=\s*"([0-9.eE+-]+)\")"))) {
    declared = "<unit meter=\"" + m[1].str() + "\">";
    return 1000.0;
  }
  return 0.0;
}

}  // namespace

RawMesh read_with_assimp(const std::string& path, const std::string& part) {
  Assimp::Importer importer;
  // Keep the file's own axes and numbers; units are resolved by the caller.
  importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, true);
  const aiScene* scene = nullptr;
  try {
    scene = importer.ReadFile(
        path, aiProcess_Triangulate | aiProcess_SortByPType | aiProcess_ValidateDataStructure);
  } catch (const std::exception& e) {
    throw Error(path, std::string("cannot parse: ") + e.what());
  }
  if (!scene || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) || !scene->mRootNode) {
    std::string why = importer.GetErrorString();
    if (why.empty()) why = "unreadable or incomplete file";
    throw Error(path, "cannot parse: " + why);
  }

  RawMesh raw;
  std::set<std::string> names;
  bool matched = part.empty();
  std::function<void(const aiNode*, const Eigen::Matrix4f&, bool)> visit =
      [&](const aiNode* node, const Eigen::Matrix4f& parent, bool take) {
        const Eigen::Matrix4f T = parent * to_eigen(node->mTransformation);
        const std::string nname = node->mName.C_Str();
        if (!part.empty() && nname == part) take = matched = true;
        for (unsigned i = 0; i < node->mNumMeshes; ++i) {
          const aiMesh& am = *scene->mMeshes[node->mMeshes[i]];
          const std::string mname = am.mName.C_Str();
          if (!nname.empty() && node->mNumMeshes > 0) names.insert(nname);
          if (!mname.empty()) names.insert(mname);
          const bool take_mesh = take || (!part.empty() && mname == part);
          if (take_mesh) {
            matched = true;
            append_mesh(am, T, raw.mesh);
          }
        }
        for (unsigned c = 0; c < node->mNumChildren; ++c) visit(node->mChildren[c], T, take);
      };
  visit(scene->mRootNode, Eigen::Matrix4f::Identity(), part.empty());
  raw.parts.assign(names.begin(), names.end());
  if (!matched) {
    std::string list;
    for (const auto& n : raw.parts) list += (list.empty() ? "" : ", ") + n;
    throw Error(path,
                "no part named '" + part + "' (parts: " + (list.empty() ? "none" : list) + ")");
  }

  const std::string ext = io::lower_extension(path);
  if (ext == ".dae") {
    raw.declared_to_mm = collada_unit(path, raw.declared_unit);
  } else if (ext == ".gltf" || ext == ".glb") {
    raw.declared_to_mm = 1000.0;  // glTF 2.0: "the units for all linear distances are meters"
    raw.declared_unit = "m (glTF 2.0 specification)";
  }
  return raw;
}

}  // namespace laserfit::cad
