#pragma once
// Beyond the paper (issue 7, 4b): a small set of viewpoints that together cover several elements (e.g. every
// cable of the plan). Each element's surface is sampled uniformly by area; a candidate "sees" a sample when
// the sample projects into its image, faces it within max_incidence_deg and nothing hides it (and, for the
// measurable model, the projector lights it). Greedy set cover then picks candidates until every element has
// at least target_fraction of its area seen.
//
// The greedy objective is f(S) = sum_e min(seen_e(S), need_e), need_e = ceil(target * samples_e): monotone
// and submodular with integer values, so greedy uses at most H(max_c f({c})) <= 1 + ln(max_c f({c})) times
// the optimal number of viewpoints (Wolsey 1982); `lower_bound` is a simple bound on that optimum.
// When no candidate sees enough of an element (hidden underside, clamps), need_e is capped at what all the
// candidates together see, and `complete` is false.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "ewis/core/camera.hpp"
#include "ewis/core/pose.hpp"
#include "ewis/core/progress.hpp"
#include "ewis/plan/score.hpp"
#include "ewis/raycast/raycaster.hpp"

namespace ewis {

struct SurfaceSamples {
  std::vector<Eigen::Vector3d> points;   // grouped by element, in the order the elements were given
  std::vector<Eigen::Vector3d> normals;  // triangle normals (outward winding; used two-sided)
  std::vector<std::size_t> element_begin;  // samples of element k: [element_begin[k], element_begin[k+1])
};

// About `per_element` area-uniform samples of each listed element (fewer for tiny meshes: at least one per
// triangle is not promised). Deterministic: fixed per-element seeds, no thread dependence.
SurfaceSamples sample_elements(const Scene& scene, const std::vector<std::uint32_t>& elements,
                               std::size_t per_element, std::uint64_t seed = 1);

struct CoverageParams {
  double target_fraction = 0.9;     // of each element's area
  std::size_t samples_per_element = 2000;
  std::uint64_t seed = 1;
  double max_incidence_deg = 85.0;  // without the measurable model: grazing surfaces give no useful pixels
  bool measurable = false;          // use MeasurableModel (projector light and its incidence limit)
  MeasurableModel sensor;
  std::size_t max_viewpoints = 1000;  // bound on the greedy loop
  // Stop when the best remaining view adds less than this fraction of an unfinished element's samples: the
  // long tail of views that each find a few more visible samples (around clamps, under cables) is not worth
  // a robot move.
  double min_gain_fraction = 0.005;
};

// Per candidate view, which samples it sees, as a bitset (one bit a sample, 64 to a word; each element's
// samples start on a new word so per-element counts are plain popcounts).
struct VisibilitySets {
  std::size_t words = 0;                        // words per view
  std::vector<std::size_t> element_word_begin;  // element k: words [begin[k], begin[k+1])
  std::vector<std::size_t> element_samples;     // samples of element k
  std::vector<std::vector<std::uint64_t>> seen;  // per view
};

// `views`: camera poses; `usable[i]` false skips view i (a rejected candidate). Parallel over views.
VisibilitySets visible_samples(const Raycaster& scene_caster, const Camera& camera, const std::vector<Pose>& views,
                               const std::vector<bool>& usable, const SurfaceSamples& samples,
                               const CoverageParams& params, const ProgressFn& progress = {});

struct CoverResult {
  std::vector<std::size_t> chosen;             // view indices, in the order greedy picked them
  std::vector<std::vector<double>> gained;     // per chosen view, fraction of each element it newly covers
  std::vector<double> coverage;                // per element: fraction of its samples seen by the chosen set
  std::vector<double> best_single;             // per element: best fraction any one view sees
  std::vector<double> reachable;               // per element: fraction seen by any view at all
  bool complete = false;                       // every element reached the target
  std::size_t lower_bound = 0;                 // the optimum needs at least this many views
  double greedy_factor = 1.0;                  // chosen.size() <= greedy_factor * optimum
};

CoverResult greedy_cover(const VisibilitySets& sets, double target_fraction, std::size_t max_viewpoints = 1000,
                         double min_gain_fraction = 0.005);

}  // namespace ewis
