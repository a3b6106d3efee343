// Twins: poses other than the one found that the scan may not tell apart from it. A part that is
// nearly symmetric (a bearing housing square but for one boss, a pulley the same both ways up,
// a gear motor round but for its flats) looks the same turned by its near-symmetry wherever the
// scan misses what breaks it; RANSAC then finds either pose, and two attempts agreeing on the
// wrong one confirm it. So each near-symmetry S of the reference (found once, when the reference
// is first needed) is tried from the pose found, T * S: refined, a twin that fits the scan as
// well and does not agree with T makes the pose ambiguous.
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "driver.hpp"
#include "reference_cache.hpp"

namespace laserfit::registration {

namespace {

constexpr size_t kSamples = 2000;      // reference and scan points a twin is screened on
constexpr double kToleranceVox = 2;    // a point maps onto the surface within this (voxels)
constexpr double kDistinctDeg = 5;     // near-symmetries closer than this are one
constexpr size_t kAlignSamples = 500;  // reference points a near-symmetry is aligned on
constexpr double kNearFraction = 0.3;  // of them within 2 tolerances before aligning

// Every `step`-th point, about n of them.
std::vector<Eigen::Vector3f> subsample(const PclCloud& c, size_t n) {
  const size_t step = std::max<size_t>(1, c.size() / n);
  std::vector<Eigen::Vector3f> out;
  for (size_t i = 0; i < c.size(); i += step)
    if (c[i].getVector3fMap().allFinite()) out.push_back(c[i].getVector3fMap());
  return out;
}

// Fraction of `pts`, moved by T, within `tol` of a point of the tree's cloud.
double fraction_on(const Tree& tree, const std::vector<Eigen::Vector3f>& pts, const Pose& T,
                   double tol) {
  if (pts.empty()) return 0;
  const Eigen::Matrix4f M = T.matrix().cast<float>();
  std::vector<Eigen::Vector3f> q(pts.size());
  for (size_t i = 0; i < pts.size(); ++i)
    q[i] = M.topLeftCorner<3, 3>() * pts[i] + M.topRightCorner<3, 1>();
  std::vector<int> idx;
  std::vector<float> d2;
  tree.nearest_batch(q, idx, d2, float(tol * tol));
  return double(std::count_if(idx.begin(), idx.end(), [](int i) { return i >= 0; })) /
         double(pts.size());
}

// The rotations tried about each principal axis: multiples of 360/N for 2-, 3-, 4-, 5-, 6-, 8-,
// 10- and 12-fold symmetry, each angle once.
std::vector<double> twin_angles_deg() {
  std::vector<double> a;
  for (int n : {2, 3, 4, 5, 6, 8, 10, 12})
    for (int k = 1; k < n; ++k) a.push_back(360.0 * k / n);
  std::sort(a.begin(), a.end());
  a.erase(
      std::unique(a.begin(), a.end(), [](double x, double y) { return std::abs(x - y) < 1e-6; }),
      a.end());
  return a;
}

// S refined so that the reference turned by it lies on itself: point-to-plane Gauss-Newton on
// the subsample, the reference's own normals. The principal axis of a part that is symmetric but
// for a boss is a few degrees off its axis of symmetry: turned 90 deg about it, points 27 mm out
// land 2 mm off, too far for the twin's screen or its refinement against a scan.
Pose self_aligned(const PclCloud& ref, const Tree& tree, const std::vector<Eigen::Vector3f>& pts,
                  Pose S, double gate) {
  std::vector<int> idx;
  std::vector<float> d2;
  for (int it = 0; it < 20; ++it) {
    std::vector<Eigen::Vector3f> q(pts.size());
    for (size_t i = 0; i < pts.size(); ++i) q[i] = (S * pts[i].cast<double>()).cast<float>();
    tree.nearest_batch(q, idx, d2, float(gate * gate));
    Eigen::Matrix<double, 6, 6> H = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> g = Eigen::Matrix<double, 6, 1>::Zero();
    for (size_t i = 0; i < q.size(); ++i) {
      if (idx[i] < 0) continue;
      const auto& m = ref[size_t(idx[i])];
      const Eigen::Vector3d y = q[i].cast<double>(), n = m.getNormalVector3fMap().cast<double>();
      if (!n.allFinite()) continue;
      Eigen::Matrix<double, 6, 1> J;
      J << y.cross(n), n;
      H += J * J.transpose(), g += J * n.dot(y - m.getVector3fMap().cast<double>());
    }
    const Eigen::Matrix<double, 6, 1> d =
        -(H + 1e-6 * Eigen::Matrix<double, 6, 6>::Identity()).ldlt().solve(g);
    Pose D = Pose::Identity();
    if (d.head<3>().norm() > 0)
      D.linear() =
          Eigen::AngleAxisd(d.head<3>().norm(), d.head<3>().normalized()).toRotationMatrix();
    D.translation() = d.tail<3>();
    S = D * S;
    if (d.norm() < 1e-6) break;
  }
  return S;
}

bool known(const std::vector<Twin>& twins, const Pose& S) {  // within kDistinctDeg of one
  for (const auto& t : twins)
    if (Eigen::AngleAxisd(t.S.linear().transpose() * S.linear()).angle() <
        kDistinctDeg * M_PI / 180)
      return true;
  return false;
}

// Adds S, aligned, when it lays enough of the part near itself (a box turned 30 deg does not:
// not worth aligning) and is neither the identity nor a symmetry already known.
void add_if_twin(const PclCloud& ref, const Tree& tree, const std::vector<Eigen::Vector3f>& few,
                 const std::vector<Eigen::Vector3f>& pts, double voxel, Pose S,
                 std::vector<Twin>& twins) {
  if (Eigen::AngleAxisd(S.linear()).angle() < kDistinctDeg * M_PI / 180 || known(twins, S) ||
      fraction_on(tree, few, S, 2 * kToleranceVox * voxel) < kNearFraction)
    return;
  S = self_aligned(ref, tree, few, S, 2 * kToleranceVox * voxel);
  const Eigen::AngleAxisd turn(S.linear());
  if (turn.angle() < kDistinctDeg * M_PI / 180 || known(twins, S)) return;  // slid back, or met
  twins.push_back({S, fraction_on(tree, pts, S, voxel), turn.angle() * 180 / M_PI, turn.axis()});
}

}  // namespace

// Turns about the principal axes, then their products: a disc with n-fold symmetry has n flips
// end over end, and the principal axes in its plane (any two, the plane being isotropic) give
// two of them; the others are a flip times a turn about the disc's axis.
std::vector<Twin> reference_twins(const PclCloud& ref, const Tree& tree, double voxel,
                                  double max_turn_deg) {
  const auto pts = subsample(ref, kSamples), few = subsample(ref, kAlignSamples);
  if (pts.size() < 10) return {};
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const auto& x : pts) c += x.cast<double>();
  c /= double(pts.size());
  Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
  for (const auto& x : pts) C += (x.cast<double>() - c) * (x.cast<double>() - c).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(C);
  std::vector<Twin> twins;
  for (int k = 0; k < 3; ++k)
    for (const double deg : twin_angles_deg()) {
      if (std::min(deg, 360 - deg) > max_turn_deg) continue;
      Pose S = Pose::Identity();  // about the line through the centroid along the axis
      S.linear() = Eigen::AngleAxisd(deg * M_PI / 180, es.eigenvectors().col(k)).toRotationMatrix();
      S.translation() = c - S.linear() * c;
      add_if_twin(ref, tree, few, pts, voxel, S, twins);
    }
  const size_t found = twins.size();
  for (size_t i = 0; i < found; ++i)
    for (size_t j = 0; j < found; ++j) {
      // A half turn times a turn about another axis (turns about one axis compose to turns about
      // it, which the angles above cover).
      if (std::abs(twins[i].angle_deg - 180) > kDistinctDeg ||
          std::abs(twins[i].axis.dot(twins[j].axis)) > std::cos(kDistinctDeg * M_PI / 180))
        continue;
      const Pose S = twins[i].S * twins[j].S;
      if (Eigen::AngleAxisd(S.linear()).angle() <= max_turn_deg * M_PI / 180)
        add_if_twin(ref, tree, few, pts, voxel, S, twins);
    }
  return twins;
}

namespace {

// Signed point-to-plane residual of every scan point at T (mm); NaN where no reference point
// lies within the gate.
std::vector<double> residuals(const Problem& p, const Pose& T) {
  const Pose Ti = T.inverse();
  std::vector<Eigen::Vector3f> q(p.scan->size());
  for (size_t i = 0; i < q.size(); ++i)
    q[i] = (Ti * (*p.scan)[i].getVector3fMap().cast<double>()).cast<float>();
  std::vector<int> idx;
  std::vector<float> d2;
  p.ref_tree->nearest_batch(q, idx, d2, float(p.matcher.gate * p.matcher.gate));
  std::vector<double> r(q.size(), std::nan(""));
  for (size_t i = 0; i < q.size(); ++i)
    if (idx[i] >= 0) {
      const auto& m = (*p.ref)[size_t(idx[i])];
      r[i] = m.getNormalVector3fMap().dot(q[i] - m.getVector3fMap());
    }
  return r;
}

double finite_sigma(const std::vector<double>& r) {  // robust_sigma of the matched points (mm)
  std::vector<double> a;
  for (const double x : r)
    if (std::isfinite(x)) a.push_back(std::abs(x));
  return a.empty() ? 0 : robust_sigma_of(a);
}

// The fraction of the scan on the reference at pose a (within on_mm) and off it at pose b
// (beyond off_mm, or unmatched).
double on_a_off_b(const std::vector<double>& a, const std::vector<double>& b, double on_mm,
                  double off_mm) {
  size_t n = 0;
  for (size_t i = 0; i < a.size(); ++i) n += std::abs(a[i]) <= on_mm && !(std::abs(b[i]) <= off_mm);
  return a.empty() ? 0 : double(n) / double(a.size());
}

// How much of the scan tells the pose found apart from its twin: the points that fit it and not
// the twin (first), and those that fit the twin and not it (second). Sampling alone gives both:
// where the scan crosses a fillet or an edge, a point's nearest reference sample may lie 0.3 mm
// away along a curved face and miss it by 0.1 mm at one pose and not the other (a bearing
// housing turned by its near-symmetry: 1.8 % one way, 1.6 % the other). A feature that breaks
// the symmetry in view counts one way only; the difference is the evidence.
std::pair<double, double> evidence(const std::vector<double>& at_best,
                                   const std::vector<double>& at_twin, double floor_mm,
                                   double off_mm) {
  const double on = std::max(3 * std::max(finite_sigma(at_best), finite_sigma(at_twin)), floor_mm);
  return {on_a_off_b(at_best, at_twin, on, off_mm), on_a_off_b(at_twin, at_best, on, off_mm)};
}

// The twins worth refining: near-symmetries of the part (twin_self_overlap), inside the rho_rot
// cone of a prior orientation as RANSAC's poses must be, explaining nearly as much of a scan
// subsample as the pose found (twin_screen); the max_twins that explain most of it. Ranked by
// their own symmetry instead, a toothed pulley's dozen turns about its axis crowd out its flip
// end over end, which a top-down scan seeing only the teeth fits as well as the true pose.
std::vector<const Twin*> screened(const Problem& p, const Pose& T_best, std::vector<Twin>& gated) {
  const TrustSettings& ts = p.s.trust;
  const auto seen = subsample(*p.scan, kSamples);
  const double tol = kToleranceVox * p.voxel;
  const double own = fraction_on(*p.ref_tree, seen, T_best.inverse(), tol);
  // With a prior orientation only turns that can land inside its cone (10 deg of slack for the
  // alignment) are found, afresh: a view reference is new in every registration.
  if (p.s.q0) {
    const double off = rotation_angle(Eigen::Quaterniond(T_best.rotation()), *p.s.q0) * 180 / M_PI;
    gated = reference_twins(*p.ref, *p.ref_tree, p.voxel, p.s.rho_rot_deg + off + 10);
  }
  std::vector<std::pair<double, const Twin*>> fit;  // fraction of the subsample it explains
  for (const auto& tw : p.s.q0 ? gated : p.prepared->twins()) {
    const Pose T = T_best * tw.S;
    const double d_phi = p.s.q0 ? rotation_angle(Eigen::Quaterniond(T.rotation()), *p.s.q0) : 0;
    if (tw.self_overlap < ts.twin_self_overlap || d_phi * 180 / M_PI > p.s.rho_rot_deg) continue;
    const double f = fraction_on(*p.ref_tree, seen, T.inverse(), tol);
    if (f >= ts.twin_screen * own) fit.emplace_back(f, &tw);
  }
  std::stable_sort(fit.begin(), fit.end(),
                   [](const auto& x, const auto& y) { return x.first > y.first; });
  std::vector<const Twin*> out;
  for (const auto& [f, tw] : fit)
    if (out.size() < size_t(std::max(ts.max_twins, 0))) out.push_back(tw);
  return out;
}

// One pass over the screened twins of `best`: the twin the scan prefers most clearly (told apart
// the other way), if any; else r is set ambiguous when a twin is not told apart. All are refined
// before deciding: from the wrong one of four quarter turns, the opposite quarter is as wrong and
// fits as well, and only the true one is preferred.
std::optional<Candidate> probe_round(const Problem& p, const Candidate& best,
                                     RegistrationResult& r) {
  const TrustSettings& ts = p.s.trust;
  std::vector<Twin> gated;
  const auto candidates = screened(p, best.T_scan_ref, gated);
  const auto at_best = candidates.empty() ? std::vector<double>{} : residuals(p, best.T_scan_ref);
  std::optional<Pose> preferred;
  double most = 0, least = std::numeric_limits<double>::infinity();
  const Twin* equal = nullptr;
  for (const Twin* tw : candidates) {
    const RefineOutput out = p.refine(p.refine_input(best.T_scan_ref * tw->S));
    r.iterations += out.iterations;
    if (!out.T.matrix().allFinite() || agree(out.T, best.T_scan_ref, *p.ref, ts)) continue;
    const auto [for_best, for_twin] =
        evidence(at_best, residuals(p, out.T), ts.rmse_floor_mm, ts.twin_off_mm);
    const double e = for_best - for_twin;
    r.log.push_back("twin " + fmt(tw->angle_deg) + " deg about [" + fmt(tw->axis.x()) + ", " +
                    fmt(tw->axis.y()) + ", " + fmt(tw->axis.z()) + "] (reference frame; maps " +
                    fmt(tw->self_overlap) + " of it onto itself), refined to " + fmt_t(out.T) +
                    ": " + fmt(100 * for_best) + " % of the scan fits only the pose found, " +
                    fmt(100 * for_twin) + " % only the twin");
    // Told apart when the points only one pose explains exceed the floor and the other pose's
    // own such points, a measure of what sampling alone gives.
    const auto excess = [&](double x, double y) { return x - y > std::max(ts.twin_evidence, y); };
    if (excess(for_twin, for_best) && -e > most) most = -e, preferred = out.T;
    if (!excess(for_best, for_twin) && !excess(for_twin, for_best) && std::abs(e) < least)
      least = std::abs(e), equal = tw;
  }
  if (preferred)
    return Candidate{*preferred, evaluate(*p.scan, *p.ref_tree, *preferred, p.matcher)};
  if (equal) {
    r.status = Status::Ambiguous;
    r.reason = "the part turned " + fmt(equal->angle_deg) +
               " deg by a near-symmetry fits as well: the scan tells the two apart by " +
               fmt(100 * least) + " % of its points (symmetric within the view?)";
  }
  return std::nullopt;
}

}  // namespace

// Policies::twins: an ok pose against each screened near-symmetry of its reference, refined from
// the pose turned by it. A twin that moves the surface (does not agree) yet is not told apart
// (TrustSettings::twin_evidence) is a pose the scan cannot exclude: ambiguous. A twin the scan
// prefers (two RANSAC attempts agreed on the wrong one of a near-symmetric pair) replaces the
// pose, and its own twins are probed in turn; a third pose preferred again is no stable answer.
void probe_twins(const Problem& p, Candidate& best, RegistrationResult& r) {
  if (r.status != Status::Ok) return;
  const auto t = Clock::now();
  for (int round = 0; r.status == Status::Ok; ++round) {
    const auto better = probe_round(p, best, r);
    if (!better) break;
    if (round == 1) {
      r.status = Status::Ambiguous;
      r.reason = "the scan prefers another near-symmetric twin at every turn";
      break;
    }
    r.log.push_back("twins: the scan prefers the twin at " + fmt_t(better->T_scan_ref));
    best = *better;
    r.T_scan_ref = best.T_scan_ref;
    assess(*p.scan, *p.ref_tree, p.matcher, p.s.trust, p.voxel, r);
  }
  r.timings_s["twins"] = since(t);
}

}  // namespace laserfit::registration
