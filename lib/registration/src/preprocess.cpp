#include "laserfit/registration/preprocess.hpp"

#include <pcl/features/normal_3d_omp.h>
#include <pcl/filters/statistical_outlier_removal.h>
#include <pcl/filters/voxel_grid.h>

#include "laserfit/core/error.hpp"
#include "pcl_types.hpp"

namespace laserfit::registration {

PclCloud::Ptr to_pcl(const PointCloud& c) {
  PclCloud::Ptr out(new PclCloud);
  out->reserve(c.size());
  for (size_t i = 0; i < c.size(); ++i) {
    if (!c.points[i].allFinite()) continue;
    PointT p;
    p.getVector3fMap() = c.points[i];
    p.getNormalVector3fMap() = c.has_normals() ? c.normals[i] : Eigen::Vector3f::Zero();
    p.curvature = 0;
    out->push_back(p);
  }
  out->width = static_cast<uint32_t>(out->size());
  out->height = 1;
  out->is_dense = true;
  return out;
}

double auto_voxel_mm(const PointCloud& ref) {
  Eigen::AlignedBox3f box;
  for (const auto& p : ref.points)
    if (p.allFinite()) box.extend(p);
  if (box.isEmpty()) throw Error("reference cloud has no finite points");
  return box.diagonal().norm() / 150.0;
}

PointCloud preprocess(const PointCloud& in, const PreprocessSettings& s, double voxel) {
  PclCloud::Ptr c = to_pcl(in);
  if (c->empty()) throw Error("cloud has no finite points");
  if (s.outlier_std > 0 && c->size() > size_t(s.outlier_neighbours)) {
    pcl::StatisticalOutlierRemoval<PointT> sor;
    sor.setInputCloud(c);
    sor.setMeanK(s.outlier_neighbours);
    sor.setStddevMulThresh(s.outlier_std);
    PclCloud::Ptr f(new PclCloud);
    sor.filter(*f);
    c = f;
  }
  pcl::VoxelGrid<PointT> vg;
  vg.setInputCloud(c);
  vg.setLeafSize(float(voxel), float(voxel), float(voxel));
  PclCloud::Ptr d(new PclCloud);
  vg.filter(*d);
  if (d->size() < 10) throw Error("fewer than 10 points left after filtering and downsampling");
  // Normals from the points themselves (scan) — reference normals from CAD are kept but
  // re-estimated too so both clouds see the same smoothing.
  pcl::NormalEstimationOMP<PointT, PointT> ne(2);
  ne.setInputCloud(d);
  Tree::Ptr tree(new Tree);
  ne.setSearchMethod(tree);
  ne.setRadiusSearch(s.normal_radius_vox * voxel);
  PclCloud::Ptr withn(new PclCloud(*d));
  ne.compute(*withn);
  PointCloud out;
  for (size_t i = 0; i < withn->size(); ++i) {
    const auto& p = (*withn)[i];
    Eigen::Vector3f n = p.getNormalVector3fMap();
    if (!n.allFinite()) continue;  // isolated point: no normal
    if (s.use_viewpoint) {
      if (n.dot(s.viewpoint.cast<float>() - p.getVector3fMap()) < 0) n = -n;
    } else if (in.has_normals() && d->at(i).getNormalVector3fMap().dot(n) < 0) {
      n = -n;  // keep the CAD's outward side (voxel-averaged normal)
    }
    out.points.push_back(p.getVector3fMap());
    out.normals.push_back(n);
  }
  out.width = static_cast<int>(out.points.size());
  out.height = 1;
  if (out.points.size() < 10) throw Error("fewer than 10 points with normals after preprocessing");
  return out;
}

}  // namespace laserfit::registration
