#pragma once
// Pictures for the report (issue 6, item 3): the scan as the sensor saw it (points splatted into the camera
// image from the registered pose, coloured by what the inspection made of them) and close-ups of each defect
// (a zoomed splat of the points and a ray-cast render of the registered CAD around it).
#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "ewis/core/camera.hpp"
#include "ewis/core/pose.hpp"
#include "ewis/inspect/pipeline.hpp"
#include "ewis/io/image_io.hpp"
#include "ewis/raycast/raycaster.hpp"
#include "ewis/scene/scene.hpp"

namespace ewis {

// What the inspection made of each point of result.cloud.
enum class PointKind : std::uint8_t { Rest = 0, Cable = 1, Interference = 2 };
struct PointLabels {
  std::vector<PointKind> kind;          // per point of result.cloud
  std::vector<std::int16_t> cable;      // Cable: index in result.cables (32767 at most); Interference: the cable it is near
  std::vector<std::uint8_t> foreign;    // Interference: 1 when the cluster is a foreign object (with null)
};
// Cable points from each found cable's trace, interference clusters on top of the rest (a cluster point that
// is also a cable point stays a cable point, as result_clouds does).
PointLabels label_points(const InspectionResult& result);

// Colours of the pictures (the PLY files of result_clouds use the same cable palette).
Rgb interference_color(bool foreign);   // orange for a CAD element, red for a foreign object

struct SplatParams {
  int point_radius_px = 1;              // each point fills a disc of this radius (0: one pixel)
  bool eye_dome_shading = true;         // darken depth edges so shapes read (eye-dome lighting)
  bool draw_chains = true;              // each found cable's chain of cylinders as axis lines
  bool draw_markers = true;             // rings at interference centres and the minimum bend radius
};

// The scan as seen by `camera` at `camera_to_cad` (usually the sensor at result.scan_to_cad): cables in
// their colour, interference clusters in a strong colour, the rest grey shaded by depth; background white.
Image splat_scan(const InspectionResult& result, const PointLabels& labels, const Camera& camera,
                 const Pose& camera_to_cad, const SplatParams& params = {});

// A camera of the sensor's aspect, `width_px` wide, at the sensor pose of the result (scan_to_cad).
Camera report_camera(const InspectionPlan& plan, int width_px);

// One defect to show close up.
struct DefectView {
  std::string title;                    // e.g. "cable_A: bend radius 38.2 mm < 56.0 mm"
  int cable = -1;                       // index in result.cables
  int interference = -1;                // index in that cable's interferences, -1 for a bend defect
  Eigen::Vector3d target = Eigen::Vector3d::Zero();  // CAD coordinates, centre of the view
  double half_extent_mm = 50.0;         // the view covers at least +-this around the target
};
// Every failed check that has a place: each bend_ok == false at its minimum, each interference at the gap.
// At most max_views, in cable order.
std::vector<DefectView> defect_views(const InspectionResult& result, std::size_t max_views = 12);

// A camera looking from the sensor position at view.target, narrow enough to show +-half_extent_mm.
struct CloseupCamera {
  Camera camera;
  Pose camera_to_cad = Pose::Identity();
};
CloseupCamera closeup_camera(const InspectionResult& result, const DefectView& view, int width_px, int height_px);

// Zoomed splat: points grow so the zoomed surface stays closed.
Image closeup_splat(const InspectionResult& result, const PointLabels& labels, const DefectView& view,
                    const CloseupCamera& cam);
// The registered CAD around the defect, ray cast with `caster` (over the whole scene), shaded by the normal:
// the inspected cable in its colour, the element it interferes with in orange, other elements grey; the
// measured chain and the interference points drawn on top.
Image closeup_render(const InspectionResult& result, const PointLabels& labels, const Raycaster& caster,
                     const DefectView& view, const CloseupCamera& cam);

}  // namespace ewis
