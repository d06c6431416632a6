// Paper 3.3: f_score = pixels of the element in a render of the whole CAD scene from the candidate.
#include "ewis/plan/score.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

#include "ewis/core/parallel.hpp"

namespace ewis {

PixelWindow projected_window(const Camera& camera, const Pose& camera_to_cad, const Element& element) {
  const Pose cad_to_camera = camera_to_cad.inverse();
  PixelWindow full{0, 0, camera.width_px, camera.height_px};
  double u0 = std::numeric_limits<double>::infinity(), v0 = u0, u1 = -u0, v1 = -u0;
  int behind = 0;
  for (int corner = 0; corner < 8; ++corner) {
    const Eigen::Vector3d q((corner & 1) ? element.bounds_max.x() : element.bounds_min.x(),
                            (corner & 2) ? element.bounds_max.y() : element.bounds_min.y(),
                            (corner & 4) ? element.bounds_max.z() : element.bounds_min.z());
    behind += (cad_to_camera * q).z() <= 0 ? 1 : 0;
  }
  if (behind == 8) return PixelWindow{0, 0, 0, 0};  // the whole box is behind the camera
  for (int corner = 0; corner < 8; ++corner) {
    const Eigen::Vector3d p((corner & 1) ? element.bounds_max.x() : element.bounds_min.x(),
                            (corner & 2) ? element.bounds_max.y() : element.bounds_min.y(),
                            (corner & 4) ? element.bounds_max.z() : element.bounds_min.z());
    double u = 0, v = 0;
    // A corner behind (or at) the camera: the box may cover any part of the image.
    if (!camera.project(cad_to_camera * p, u, v) || !std::isfinite(u) || !std::isfinite(v)) return full;
    u0 = std::min(u0, u), u1 = std::max(u1, u), v0 = std::min(v0, v), v1 = std::max(v1, v);
  }
  // Pixel centres at col + 0.5: a pixel can show the box when its centre lies within [u0, u1].
  PixelWindow w;
  w.col0 = static_cast<int>(std::clamp(std::floor(u0 - 0.5), 0.0, double(camera.width_px)));
  w.col1 = static_cast<int>(std::clamp(std::ceil(u1 + 0.5), 0.0, double(camera.width_px)));
  w.row0 = static_cast<int>(std::clamp(std::floor(v0 - 0.5), 0.0, double(camera.height_px)));
  w.row1 = static_cast<int>(std::clamp(std::ceil(v1 + 0.5), 0.0, double(camera.height_px)));
  return w;
}

namespace {

std::uint64_t count_pixels(const Raycaster& caster, const Camera& camera, const Pose& pose, std::uint32_t element,
                           const ScoreParams& params) {
  return params.measurable ? count_measurable_pixels(caster, camera, pose, element, params.sensor)
                           : count_visible_pixels(caster, camera, pose, element);
}

}  // namespace

std::vector<CandidateScore> score_candidates(const Raycaster& scene_caster, const Camera& camera,
                                             std::uint32_t element, const std::vector<Candidate>& candidates,
                                             double radius_mm, const ScoreParams& params,
                                             const ProgressFn& progress) {
  std::vector<CandidateScore> scores(candidates.size());
  const double min_distance = params.min_distance_mm < 0 ? 0.5 * radius_mm : params.min_distance_mm;
  std::atomic<std::size_t> done{0};
  // All candidates in parallel; each count is exact and integer, so the order of work does not matter.
  parallel_for_each_index(
      candidates.size(),
      [&](std::size_t i) {
        CandidateScore& s = scores[i];
        const Candidate& c = candidates[i];
        s.reject_reason = sensor_position_problem(scene_caster.scene(), scene_caster, c.position, min_distance);
        s.rejected = !s.reject_reason.empty();
        if (!s.rejected) s.score_px = count_pixels(scene_caster, camera, c.camera_to_cad, element, params);
        const std::size_t k = ++done;
        if (progress) progress("plan: score", double(k) / double(candidates.size()));
      },
      1);
  return scores;
}

void add_visible_fractions(const Raycaster& element_caster, const Camera& camera, std::uint32_t element,
                           const std::vector<Candidate>& candidates, const ScoreParams& params,
                           std::vector<CandidateScore>& scores, const std::vector<std::size_t>& which) {
  std::vector<std::size_t> todo = which;
  if (todo.empty())
    for (std::size_t i = 0; i < scores.size(); ++i) todo.push_back(i);
  parallel_for_each_index(
      todo.size(),
      [&](std::size_t k) {
        const std::size_t i = todo[k];
        if (i >= scores.size() || i >= candidates.size()) return;
        CandidateScore& s = scores[i];
        s.isolated_px = s.score_px > 0 ? count_pixels(element_caster, camera, candidates[i].camera_to_cad, element, params) : 0;
        // An element never shows more pixels with others present; guard the ratio against ray-caster
        // edge cases all the same.
        s.visible_fraction = s.isolated_px > 0 ? std::min(1.0, double(s.score_px) / double(s.isolated_px)) : 0.0;
      },
      1);
}

}  // namespace ewis
