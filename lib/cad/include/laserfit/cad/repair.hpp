#pragma once
// Mesh checks and repair (CGAL Polygon Mesh Processing). CAD exports are triangle soups with
// duplicated vertices, slivers and flipped faces; registration and ray casting want a clean,
// consistently oriented surface, and a user wants to know what was wrong with the file.
#include <string>

#include "laserfit/core/mesh.hpp"

namespace laserfit::cad {

struct RepairSettings {
  bool repair = true;                    // false: only check and report, return the input mesh
  bool fill_holes = false;               // triangulate open boundaries (CGAL triangulate_hole)
  bool check_self_intersections = true;  // O(n log n) box intersection; off for huge meshes
};

struct RepairReport {
  size_t input_vertices = 0, input_triangles = 0;
  size_t duplicate_vertices_merged = 0;  // exact duplicates (STL stores 3 per triangle)
  size_t degenerate_faces_removed = 0;   // repeated vertex or collinear (zero area)
  size_t duplicate_faces_removed = 0;
  size_t non_manifold_edges = 0;           // edges shared by more than two faces (input)
  size_t non_manifold_vertices_split = 0;  // vertices duplicated to make the surface manifold
  size_t faces_reoriented = 0;             // winding flipped for consistency / outward normals
  size_t boundary_edges = 0;               // after repair
  size_t holes = 0;                        // open boundary cycles after repair
  size_t holes_filled = 0;
  size_t self_intersecting_pairs = 0;  // pairs of faces that intersect (after repair)
  bool self_intersections_checked = false;
  bool watertight = false;  // closed 2-manifold (no boundary, no non-manifold edge)
  bool outward = false;     // closed and oriented to bound a volume
  double volume_mm3 = 0.0;  // signed volume when watertight, else 0
};

// Validates (finite coordinates, indices in range, non-zero area) and repairs. Throws
// laserfit::Error naming `source` when nothing usable is left (empty or zero-area mesh).
RepairReport check_and_repair(TriMesh& mesh, const RepairSettings& settings,
                              const std::string& source);

}  // namespace laserfit::cad
