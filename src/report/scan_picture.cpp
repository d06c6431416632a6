// The scan as the sensor saw it (report.html's main picture): points splatted from the registered sensor
// pose, coloured by label, the rest grey by depth, eye-dome shading, chains and defect markers on top.
#include <algorithm>
#include <cmath>

#include "draw.hpp"
#include "ewis/core/parallel.hpp"
#include "ewis/report/pictures.hpp"

namespace ewis {

using namespace report_detail;

namespace {

Image shade_splat(const InspectionResult& r, const PointLabels& labels, const SplatBuffer& buf, bool edl) {
  Image img(buf.width_px, buf.height_px, 255);
  double near_mm = 0, far_mm = 1;
  if (!depth_range(buf, near_mm, far_mm)) return img;
  std::vector<float> shade;
  if (edl) shade = eye_dome_factor(buf);
  parallel_for_each_index(std::size_t(std::max(buf.height_px, 0)), [&](std::size_t row) {  // each pixel its own
    const int y = static_cast<int>(row);
    for (int x = 0; x < buf.width_px; ++x) {
      const std::size_t k = std::size_t(y) * buf.width_px + x;
      const std::int32_t i = buf.point(k);
      if (i < 0) continue;
      Rgb c;
      const double t = std::clamp((buf.depth_mm(k) - near_mm) / (far_mm - near_mm), 0.0, 1.0);
      switch (labels.kind[i]) {
        case PointKind::Cable: c = cable_color(std::size_t(labels.cable[i])); break;
        case PointKind::Interference: c = interference_color(labels.foreign[i] != 0); break;
        default: {
          // Near is light, far is dark (a person reads depth from the grey level).
          const auto g = static_cast<std::uint8_t>(std::lround(215.0 - 120.0 * t));
          c = {g, g, g};
        }
      }
      // Coloured points keep most of their colour: only a mild depth cue.
      if (labels.kind[i] != PointKind::Rest) c = scale_rgb(c, 1.0 - 0.25 * t);
      if (edl) c = scale_rgb(c, 0.45 + 0.55 * shade[k]);  // subtle: outlines, not black rings
      put_pixel(img, x, y, c);
    }
  }, 16);
  return img;
}

}  // namespace

Camera report_camera(const InspectionPlan& plan, int width_px) {
  const Camera sensor = plan.sensor.camera();
  Camera c = sensor;
  c.width_px = std::max(16, width_px);
  c.height_px = std::max(16, static_cast<int>(std::lround(double(sensor.height_px) * c.width_px / sensor.width_px)));
  return c;  // same hfov: the same field of view as the sensor, fewer pixels
}

Image splat_scan(const InspectionResult& r, const PointLabels& labels, const Camera& camera,
                 const Pose& camera_to_cad, const SplatParams& params) {
  const SplatBuffer buf = splat_points(r.cloud.points, {}, camera, camera_to_cad, params.point_radius_px);
  Image img = shade_splat(r, labels, buf, params.eye_dome_shading);
  const Pose cad_to_camera = camera_to_cad.inverse();
  if (params.draw_chains) {
    for (std::size_t k = 0; k < r.cables.size(); ++k) {
      const CableInspection& c = r.cables[k];
      if (!c.found) continue;
      const Rgb core = scale_rgb(cable_color(k), 1.0);
      for (const SubCable& s : c.trace.segments)
        draw_axis_segment(img, camera, cad_to_camera, s.cylinder.start, s.cylinder.end, Rgb{255, 255, 255}, 1.5,
                          s.bridged);
      // Joints between sub-cables (paper Fig. 9: the chain of cylinders) as small dots in the cable colour.
      for (const SubCable& s : c.trace.segments) {
        Eigen::Vector2d uv;
        if (project_cad(camera, cad_to_camera, s.cylinder.start, uv)) {
          fill_disc(img, uv, 2.5, Rgb{0, 0, 0});
          fill_disc(img, uv, 1.5, core);
        }
      }
    }
  }
  if (params.draw_markers) {
    const double ring = std::max(8.0, camera.width_px / 60.0);
    for (std::size_t k = 0; k < r.cables.size(); ++k) {
      const CableInspection& c = r.cables[k];
      for (const Interference& f : c.interferences) {
        Eigen::Vector2d uv;
        if (!project_cad(camera, cad_to_camera, f.center, uv)) continue;
        draw_ring(img, uv, ring, Rgb{0, 0, 0}, 4.0);
        draw_ring(img, uv, ring, interference_color(!f.with), 2.0);
      }
      if (c.bend_ok == false && c.min_bend_location) {
        Eigen::Vector2d uv;
        if (!project_cad(camera, cad_to_camera, *c.min_bend_location, uv)) continue;
        draw_ring(img, uv, ring * 1.3, Rgb{0, 0, 0}, 4.0);
        draw_ring(img, uv, ring * 1.3, Rgb{255, 0, 255}, 2.0);
      }
    }
  }
  return img;
}

}  // namespace ewis
