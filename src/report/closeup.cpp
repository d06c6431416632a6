// Close-ups of each defect for report.html: a narrow camera at the sensor position looking at the defect,
// the points splatted through it, and the registered CAD ray cast through it.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "draw.hpp"
#include "ewis/report/pictures.hpp"

namespace ewis {

using namespace report_detail;

namespace {

std::string fmt(const char* f, double a, double b = 0.0) {
  char buf[96];
  std::snprintf(buf, sizeof buf, f, a, b);
  return buf;
}

double cable_diameter(const CableInspection& c) {
  return c.diameter_mm > 0 ? c.diameter_mm : std::max(c.nominal_diameter_mm, 1.0);
}

// Axis lines of every found chain and the defect's own cluster points, on top of a close-up.
void draw_overlays(Image& img, const InspectionResult& r, const DefectView& view, const CloseupCamera& cam,
                   bool points) {
  const Pose cad_to_camera = cam.camera_to_cad.inverse();
  for (std::size_t k = 0; k < r.cables.size(); ++k) {
    const CableInspection& c = r.cables[k];
    if (!c.found) continue;
    for (const SubCable& s : c.trace.segments)
      draw_axis_segment(img, cam.camera, cad_to_camera, s.cylinder.start, s.cylinder.end, Rgb{255, 255, 255}, 2.0,
                        s.bridged);
  }
  if (view.cable < 0 || std::size_t(view.cable) >= r.cables.size()) return;
  const CableInspection& c = r.cables[std::size_t(view.cable)];
  if (view.interference >= 0 && std::size_t(view.interference) < c.interferences.size()) {
    const Interference& f = c.interferences[std::size_t(view.interference)];
    if (points) {
      const Rgb col = f.with ? Rgb{220, 90, 0} : interference_color(true);
      for (std::uint32_t i : f.points) {
        if (i >= r.cloud.size()) continue;
        Eigen::Vector2d uv;
        if (project_cad(cam.camera, cad_to_camera, r.cloud.points[i].cast<double>(), uv)) fill_disc(img, uv, 1.5, col);
      }
    }
    // The measured gap as a short black/yellow segment between its two ends.
    if ((f.closest_on_cable - f.closest_on_other).norm() > 1e-6)
      draw_axis_segment(img, cam.camera, cad_to_camera, f.closest_on_cable, f.closest_on_other, Rgb{255, 230, 0}, 2.0,
                        false);
  } else if (c.min_bend_location) {
    Eigen::Vector2d uv;
    if (project_cad(cam.camera, cad_to_camera, *c.min_bend_location, uv)) {
      const double ring = img.width_px / 14.0;
      draw_ring(img, uv, ring, Rgb{0, 0, 0}, 4.0);
      draw_ring(img, uv, ring, Rgb{255, 0, 255}, 2.0);
    }
    // The fitted circle of the minimum (centre and a few points of it), when it is in front.
    if (c.min_bend_radius_mm && c.bend.circle_normal.norm() > 0.5) {
      const Eigen::Vector3d n = c.bend.circle_normal.normalized();
      Eigen::Vector3d u = n.unitOrthogonal(), v = n.cross(u);
      const double rad = *c.min_bend_radius_mm;
      Eigen::Vector3d prev = c.bend.circle_center + rad * u;
      for (int s = 1; s <= 72; ++s) {
        const double a = 2.0 * M_PI * s / 72.0;
        const Eigen::Vector3d p = c.bend.circle_center + rad * (std::cos(a) * u + std::sin(a) * v);
        if (s % 2) draw_axis_segment(img, cam.camera, cad_to_camera, prev, p, Rgb{255, 0, 255}, 1.0, false);
        prev = p;
      }
    }
  }
}

}  // namespace

std::vector<DefectView> defect_views(const InspectionResult& r, std::size_t max_views) {
  std::vector<DefectView> views;
  for (std::size_t k = 0; k < r.cables.size() && views.size() < max_views; ++k) {
    const CableInspection& c = r.cables[k];
    if (!c.found) continue;
    const double d = cable_diameter(c);
    if (c.bend_ok == false && c.min_bend_location && c.min_bend_radius_mm) {
      DefectView v;
      v.cable = int(k);
      const bool inner = c.bend_reference == BendReference::Inner;
      const double measured = inner && c.min_bend_radius_inner_mm ? *c.min_bend_radius_inner_mm : *c.min_bend_radius_mm;
      v.title = c.name + ": " + (inner ? "inner " : "") + "bend radius " +
                fmt("%.1f mm < allowed %.1f mm", measured, c.allowed_bend_radius_mm);
      v.target = *c.min_bend_location;
      v.half_extent_mm = std::clamp(std::max(1.3 * *c.min_bend_radius_mm, 4.0 * d), 10.0, 300.0);
      views.push_back(v);
    }
    for (std::size_t i = 0; i < c.interferences.size() && views.size() < max_views; ++i) {
      const Interference& f = c.interferences[i];
      DefectView v;
      v.cable = int(k);
      v.interference = int(i);
      v.title = c.name + ": " + (f.with ? "clearance to " + *f.with : std::string("foreign object")) +
                fmt(" %.2f mm < %.2f mm", f.min_distance_mm, c.clearance_mm);
      const bool has_gap = (f.closest_on_cable - f.closest_on_other).norm() > 1e-9 || f.closest_on_cable.norm() > 1e-9;
      v.target = has_gap ? Eigen::Vector3d(0.5 * (f.closest_on_cable + f.closest_on_other)) : f.center;
      v.half_extent_mm = std::clamp(std::max(4.0 * d, 30.0), 10.0, 300.0);
      views.push_back(v);
    }
  }
  return views;
}

CloseupCamera closeup_camera(const InspectionResult& r, const DefectView& view, int width_px, int height_px) {
  CloseupCamera out;
  const Eigen::Vector3d eye = r.sensor_position;
  double dist = (view.target - eye).norm();
  // The sensor's own "up" (-y of the camera frame) stays up in the close-up.
  const Eigen::Vector3d up = -(r.scan_to_cad.linear() * Eigen::Vector3d::UnitY());
  if (!(dist > 1.0)) {
    // Degenerate (target at the sensor): look along the optical axis from 600 mm back.
    out.camera_to_cad = look_at(view.target - 600.0 * r.optical_axis, view.target, up);
    dist = 600.0;
  } else {
    out.camera_to_cad = look_at(eye, view.target, up);
  }
  out.camera.width_px = std::max(16, width_px);
  out.camera.height_px = std::max(16, height_px);
  // The smaller image side covers +-half_extent at the target's distance.
  const double half_small = std::atan(std::max(view.half_extent_mm, 1.0) / dist);
  const double aspect = double(out.camera.width_px) / out.camera.height_px;
  const double half_h = aspect >= 1.0 ? std::atan(std::tan(half_small) * aspect) : half_small;
  out.camera.hfov_deg = std::clamp(2.0 * half_h * 180.0 / M_PI, 0.5, 150.0);
  return out;
}

Image closeup_splat(const InspectionResult& r, const PointLabels& labels, const DefectView& view,
                    const CloseupCamera& cam) {
  // Point spacing on the image: resolution x focal / distance; discs of about that size close the surface.
  const double dist = std::max(1.0, (view.target - cam.camera_to_cad.translation()).norm());
  const double spacing_px = std::max(r.resolution_mm, 0.05) * cam.camera.focal_px() / dist;
  SplatParams p;
  p.point_radius_px = std::clamp(static_cast<int>(std::ceil(0.75 * spacing_px)), 1, 10);
  p.draw_chains = false;
  p.draw_markers = false;
  Image img = splat_scan(r, labels, cam.camera, cam.camera_to_cad, p);
  draw_overlays(img, r, view, cam, false);
  return img;
}

Image closeup_render(const InspectionResult& r, const PointLabels& labels, const Raycaster& caster,
                     const DefectView& view, const CloseupCamera& cam) {
  const Render ren = render(caster, cam.camera, cam.camera_to_cad);
  Image img(ren.width_px, ren.height_px, 255);
  // Element colours: cables in their colour, the element interfered with in orange, the rest light grey.
  const std::size_t n_el = caster.scene().elements.size();
  std::vector<Rgb> color(n_el, Rgb{200, 200, 200});
  for (std::size_t k = 0; k < r.cables.size(); ++k)
    if (r.cables[k].element >= 0 && std::size_t(r.cables[k].element) < n_el)
      color[std::size_t(r.cables[k].element)] = cable_color(k);
  if (view.cable >= 0 && std::size_t(view.cable) < r.cables.size() && view.interference >= 0) {
    const CableInspection& c = r.cables[std::size_t(view.cable)];
    if (std::size_t(view.interference) < c.interferences.size()) {
      const int e = c.interferences[std::size_t(view.interference)].with_element;
      // A light orange, so the measured cluster points (strong orange / red) stand out on it.
      if (e >= 0 && std::size_t(e) < n_el) color[std::size_t(e)] = Rgb{255, 200, 130};
    }
  }
  const Eigen::Matrix3d rot = cam.camera_to_cad.linear();
  for (int y = 0; y < ren.height_px; ++y)
    for (int x = 0; x < ren.width_px; ++x) {
      const std::size_t k = std::size_t(y) * ren.width_px + x;
      const std::uint32_t e = ren.element[k];
      if (e == kNoElement || e >= n_el) continue;
      const Eigen::Vector3d dir = (rot * cam.camera.pixel_ray(x, y)).normalized();
      const double lambert = std::abs(dir.dot(ren.normal[k].cast<double>()));
      put_pixel(img, x, y, scale_rgb(color[e], 0.35 + 0.65 * lambert));
    }
  draw_overlays(img, r, view, cam, true);
  (void)labels;
  return img;
}

}  // namespace ewis
