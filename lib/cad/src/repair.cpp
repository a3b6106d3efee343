// Mesh checks and repair with CGAL Polygon Mesh Processing — the only TU that includes CGAL.
#include "laserfit/cad/repair.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#include <CGAL/Surface_mesh.h>

#include <cmath>
#include <map>

#include "laserfit/core/error.hpp"

namespace laserfit::cad {
namespace {

namespace PMP = CGAL::Polygon_mesh_processing;
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = K::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
using Polygon = std::vector<std::size_t>;

size_t count_non_manifold_edges(const std::vector<Polygon>& polys) {
  std::map<std::pair<size_t, size_t>, int> uses;
  for (const auto& p : polys)
    for (size_t k = 0; k < p.size(); ++k) {
      size_t a = p[k], b = p[(k + 1) % p.size()];
      if (a > b) std::swap(a, b);
      ++uses[{a, b}];
    }
  size_t n = 0;
  for (const auto& [e, c] : uses) n += c > 2;
  return n;
}

// True when polygon `after` is `before` with reversed winding (compared by coordinates, since
// orienting may have duplicated points).
bool flipped(const std::vector<Point>& pb, const Polygon& before, const std::vector<Point>& pa,
             const Polygon& after) {
  for (size_t s = 0; s < 3; ++s) {
    bool same = true;
    for (size_t k = 0; k < 3 && same; ++k) same = pb[before[k]] == pa[after[(k + s) % 3]];
    if (same) return false;
  }
  return true;
}

}  // namespace

RepairReport check_and_repair(TriMesh& mesh, const RepairSettings& s, const std::string& source) {
  RepairReport r;
  r.input_vertices = mesh.vertices.size();
  r.input_triangles = mesh.faces.size();
  if (mesh.faces.empty()) throw Error(source, "mesh has no triangles");
  for (const auto& v : mesh.vertices)
    if (!v.allFinite()) throw Error(source, "mesh has NaN or infinite vertex coordinates");
  for (const auto& f : mesh.faces)
    for (int k = 0; k < 3; ++k)
      if (f[k] < 0 || f[k] >= static_cast<int>(mesh.vertices.size()))
        throw Error(source, "face refers to a vertex index out of range");

  std::vector<Point> pts;
  pts.reserve(mesh.vertices.size());
  for (const auto& v : mesh.vertices) pts.emplace_back(v.x(), v.y(), v.z());
  std::vector<Polygon> polys;
  polys.reserve(mesh.faces.size());
  for (const auto& f : mesh.faces) polys.push_back({size_t(f[0]), size_t(f[1]), size_t(f[2])});

  // 1. Soup-level repair, step by step so that every fix is counted.
  r.duplicate_vertices_merged = PMP::merge_duplicate_points_in_polygon_soup(pts, polys);
  // Degenerate: a repeated vertex (after merging) or three collinear points (exact predicate).
  const size_t before_degenerate = polys.size();
  polys.erase(std::remove_if(polys.begin(), polys.end(),
                             [&](const Polygon& p) {
                               return p[0] == p[1] || p[1] == p[2] || p[0] == p[2] ||
                                      CGAL::collinear(pts[p[0]], pts[p[1]], pts[p[2]]);
                             }),
              polys.end());
  r.degenerate_faces_removed = before_degenerate - polys.size();
  r.duplicate_faces_removed = PMP::merge_duplicate_polygons_in_polygon_soup(pts, polys);
  PMP::remove_isolated_points_in_polygon_soup(pts, polys);
  if (polys.empty()) throw Error(source, "mesh has zero area (every triangle is degenerate)");
  r.non_manifold_edges = count_non_manifold_edges(polys);

  // 2. Consistent orientation; non-manifold vertices get duplicated so a manifold mesh exists.
  const std::vector<Point> pts_in = pts;
  const std::vector<Polygon> polys_in = polys;
  const size_t n_points = pts.size();
  PMP::orient_polygon_soup(pts, polys);
  r.non_manifold_vertices_split = pts.size() - n_points;
  Mesh sm;
  PMP::polygon_soup_to_polygon_mesh(pts, polys, sm);

  // 3. Open boundaries, optional hole filling.
  std::vector<Mesh::Halfedge_index> cycles;
  PMP::extract_boundary_cycles(sm, std::back_inserter(cycles));
  if (s.repair && s.fill_holes) {
    for (auto h : cycles) {
      std::vector<Mesh::Face_index> added;
      PMP::triangulate_hole(sm, h, std::back_inserter(added));
      r.holes_filled += !added.empty();
    }
    cycles.clear();
    PMP::extract_boundary_cycles(sm, std::back_inserter(cycles));
  }
  r.holes = cycles.size();
  for (auto h : halfedges(sm)) r.boundary_edges += sm.is_border(h);
  r.watertight = CGAL::is_closed(sm) && r.non_manifold_edges == 0;

  // 4. Self-intersections, then outward orientation (only meaningful for a clean closed mesh).
  if (s.check_self_intersections) {
    std::vector<std::pair<Mesh::Face_index, Mesh::Face_index>> pairs;
    PMP::self_intersections(sm, std::back_inserter(pairs));
    r.self_intersecting_pairs = pairs.size();
    r.self_intersections_checked = true;
  }
  if (CGAL::is_closed(sm) && r.self_intersecting_pairs == 0) {
    PMP::orient_to_bound_a_volume(sm);
    r.outward = true;
    r.volume_mm3 = CGAL::to_double(PMP::volume(sm));
  }

  std::vector<Polygon> out_polys;
  for (auto f : faces(sm)) {
    Polygon p;
    for (auto v : CGAL::vertices_around_face(sm.halfedge(f), sm)) p.push_back(v);
    out_polys.push_back(p);
  }
  std::vector<Point> final_pts;
  final_pts.reserve(sm.number_of_vertices());
  for (auto v : vertices(sm)) final_pts.push_back(sm.point(v));
  // Faces keep their order through orienting and conversion (filled holes come last).
  for (size_t i = 0; i < polys_in.size() && i < out_polys.size(); ++i)
    r.faces_reoriented += flipped(pts_in, polys_in[i], final_pts, out_polys[i]);
  if (!s.repair) return r;  // check only: leave the caller's mesh as it was

  TriMesh out;
  out.vertices.reserve(sm.number_of_vertices());
  for (const Point& p : final_pts)
    out.vertices.emplace_back(float(p.x()), float(p.y()), float(p.z()));
  for (const auto& p : out_polys) out.faces.emplace_back(int(p[0]), int(p[1]), int(p[2]));
  mesh = std::move(out);
  return r;
}

}  // namespace laserfit::cad
