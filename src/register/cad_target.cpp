// The registration target from the CAD: rigid elements anchor the pose, cables only mark where scan points
// must be ignored (paper 4.2: cables are flexible and move). See the rule in cad_target.hpp.
#include "ewis/register/cad_target.hpp"

#include <algorithm>
#include <limits>

#include "ewis/core/error.hpp"
#include "ewis/core/parallel.hpp"
#include "ewis/sample/mesh_sampling.hpp"

namespace ewis {

CadTarget build_cad_target(const Scene& scene, const InspectionPlan& plan, const CadTargetParams& params) {
  std::vector<int> rigid, cables;
  for (int e = 0; e < static_cast<int>(scene.elements.size()); ++e) {
    if (scene.elements[e].triangle_count == 0) continue;
    const PlanElement* pe = plan.find(scene.elements[e].name);
    // CONTRACT: CAD objects the plan does not list are rigid.
    (pe && pe->kind == ElementKind::Cable ? cables : rigid).push_back(e);
  }
  if (rigid.empty()) throw InputError("", "registration: the CAD has no rigid element to register to");

  CadTarget t;
  t.spacing_mm = params.spacing_mm;
  t.cable_margin_mm = params.cable_margin_mm;
  t.rigid_elements = rigid;
  t.max_points = params.max_points;
  t.seed = params.seed;
  MeshSamplingParams sp;
  sp.spacing_mm = params.spacing_mm;
  sp.max_points = params.max_points;
  sp.seed = params.seed;
  sp.elements = rigid;
  if (params.sample_up_front) {
    MeshSamples rs = sample_mesh(scene, sp);
    t.rigid = std::move(rs.cloud);
    t.rigid_element = std::move(rs.element);
    if (t.rigid.empty()) throw InputError("", "registration: sampling the rigid CAD elements gave no points");
  } else {
    t.scene = &scene;
  }
  if (params.exact_surface) t.surface = std::make_shared<const SurfaceIndex>(scene, rigid);
  if (!cables.empty()) {
    sp.elements = cables;
    sp.seed = params.seed + 1;
    t.cables = std::move(sample_mesh(scene, sp).cloud);
    if (!t.cables.empty()) t.cable_tree = std::make_unique<KdTree>(t.cables.points);
  }
  return t;
}

bool has_rigid(const CadTarget& target) { return !target.rigid.empty() || target.scene; }

namespace {

bool facing(const Eigen::Vector3f& q, const Eigen::Vector3f& normal, const Eigen::Vector3d& eye) {
  const Eigen::Vector3d to_eye = eye - q.cast<double>();
  return normal.cast<double>().dot(to_eye) > -0.2 * to_eye.norm();
}

bool inside(const Eigen::Vector3f& q, const Eigen::Vector3f& lo, const Eigen::Vector3f& hi) {
  return !((q.array() < lo.array()).any() || (q.array() > hi.array()).any());
}

// The rigid samples (those `keep` accepts, when given), drawn from the scene now.
Cloud draw(const CadTarget& target, const MeshSamplingParams::KeepFn& keep) {
  MeshSamplingParams sp;
  sp.spacing_mm = target.spacing_mm;
  sp.max_points = target.max_points;
  sp.seed = target.seed;
  sp.elements = target.rigid_elements;
  sp.keep = keep;
  return std::move(sample_mesh(*target.scene, sp).cloud);
}

}  // namespace

Cloud sample_rigid_view(const CadTarget& target, const Eigen::Vector3f& lo, const Eigen::Vector3f& hi,
                        const Eigen::Vector3d* eye) {
  auto in_view = [&](const Eigen::Vector3f& q, const Eigen::Vector3f& n) {
    return inside(q, lo, hi) && (!eye || facing(q, n, *eye));
  };
  // Drawn now: the same samples as the up-front ones, of which only the view is ever held.
  if (target.rigid.empty() && target.scene) return draw(target, in_view);
  const Cloud& t = target.rigid;
  const std::vector<std::uint32_t> keep =
      parallel_select(t.size(), [&](std::size_t i) { return in_view(t.points[i], t.normals[i]); });
  return select(t, keep);
}

Cloud sample_cable_view(const CadTarget& target, const Eigen::Vector3f& lo, const Eigen::Vector3f& hi,
                        const Eigen::Vector3d* eye) {
  const Cloud& c = target.cables;
  if (!c.has_normals()) return {};
  const std::vector<std::uint32_t> keep = parallel_select(
      c.size(), [&](std::size_t i) { return inside(c.points[i], lo, hi) && (!eye || facing(c.points[i], c.normals[i], *eye)); });
  return select(c, keep);
}

Cloud sample_rigid_all(const CadTarget& target) {
  if (!target.rigid.empty() || !target.scene) return target.rigid;
  return draw(target, {});
}

std::vector<std::uint32_t> points_away_from_cables(const std::vector<Eigen::Vector3f>& source,
                                                   const Pose& source_to_cad, const CadTarget& target,
                                                   double extra_margin_mm) {
  if (!target.cable_tree) return parallel_select(source.size(), [](std::size_t) { return true; });
  const double zone = target.cable_margin_mm + extra_margin_mm + target.spacing_mm;
  const float zone_sq = static_cast<float>(zone * zone);
  const KdTree& tree = *target.cable_tree;
  // Only whether the nearest cable sample lies within the zone matters: the search stops a hair beyond it.
  const float reach = search_bound_mm(zone);
  return parallel_select(source.size(), [&](std::size_t i) {
    const Eigen::Vector3f p = (source_to_cad * source[i].cast<double>()).cast<float>();
    return tree.nearest(p, reach, std::numeric_limits<std::uint32_t>::max()).distance_sq > zone_sq;
  });
}

}  // namespace ewis
