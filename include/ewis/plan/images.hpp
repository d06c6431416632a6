#pragma once
// Pictures of `ewis plan`: the render of a viewpoint with the inspected element highlighted, and a heat map of
// the score over the candidate sphere (theta across, phi down).
#include <cstdint>
#include <vector>

#include "ewis/core/camera.hpp"
#include "ewis/core/pose.hpp"
#include "ewis/io/image_io.hpp"
#include "ewis/plan/candidates.hpp"
#include "ewis/plan/score.hpp"
#include "ewis/raycast/raycaster.hpp"

namespace ewis {

// Full render: `primary` elements red, `secondary` orange, everything else grey, all shaded by the cosine
// between normal and view ray; background white.
Image render_highlight(const Raycaster& caster, const Camera& camera, const Pose& camera_to_cad,
                       const std::vector<std::uint32_t>& primary,
                       const std::vector<std::uint32_t>& secondary = {});

// One cell_px square per candidate (theta across, phi down), colour from dark blue (0) to yellow (highest
// score); rejected candidates crossed in grey; the best candidates (`marked`, candidate indices) outlined
// in white. A colour bar runs along the bottom.
Image score_heatmap(const CandidateGrid& grid, const std::vector<CandidateScore>& scores,
                    const std::vector<std::size_t>& marked = {}, int cell_px = 16);

}  // namespace ewis
