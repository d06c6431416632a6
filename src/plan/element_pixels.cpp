// Paper 3.3, made fast: a pixel can show the element only if its centre lies inside the projection of one of
// the element's triangles. Rasterising those triangles (cheap: a few thousand small triangles) finds these
// pixels, and only their rays are cast: for a cable that is ~10x fewer rays than its projected bounding box.
// The ray of each pixel is the same as the ray caster's render (same centre, same float direction), so the
// count is the exact element-id count of the render.
#include <algorithm>
#include <cmath>

#include "ewis/plan/score.hpp"

namespace ewis {
namespace {

constexpr double kMarginPx = 0.01;   // conservative: pixel centres this close outside a triangle count too
constexpr double kNearMm = 1e-3;     // vertices closer to the camera plane than this: no safe projection

Ray pixel_ray(const Camera& camera, const Eigen::Matrix3d& rot, const Eigen::Vector3f& origin, int col, int row) {
  const double f = camera.focal_px();
  const Eigen::Vector3d d_cam((col + 0.5 - camera.cx()) / f, (row + 0.5 - camera.cy()) / f, 1.0);
  Ray ray;
  ray.origin = origin;
  ray.direction = (rot * d_cam.normalized()).cast<float>();
  return ray;
}

// Casts the ray of each listed pixel (index row * width + col) from the camera pose.
void cast_pixels(const Raycaster& caster, const Camera& camera, const Pose& camera_to_cad,
                 const std::vector<std::uint32_t>& pixels, std::vector<Ray>& rays, std::vector<Hit>& hits) {
  const Eigen::Matrix3d rot = camera_to_cad.linear();
  const Eigen::Vector3f origin = camera_to_cad.translation().cast<float>();
  rays.resize(pixels.size());
  for (std::size_t i = 0; i < pixels.size(); ++i)
    rays[i] = pixel_ray(camera, rot, origin, int(pixels[i] % camera.width_px), int(pixels[i] / camera.width_px));
  caster.cast(rays, hits);
}


}  // namespace

bool element_footprint(const Scene& scene, const Camera& camera, const Pose& camera_to_cad, std::uint32_t element,
                       std::vector<std::uint32_t>& pixels) {
  pixels.clear();
  if (element >= scene.elements.size()) return true;
  const Element& e = scene.elements[element];
  const Pose cad_to_camera = camera_to_cad.inverse();
  const std::size_t first = e.first_triangle;
  const std::size_t end = std::min<std::size_t>(first + e.triangle_count, scene.triangles.size());
  const int W = camera.width_px, H = camera.height_px;
  if (W <= 0 || H <= 0) return true;
  const double f = camera.focal_px(), cx = camera.cx(), cy = camera.cy();
  // Pass 1: project; bail out when the element reaches the camera plane.
  std::vector<Eigen::Vector2d> uv((end - first) * 3);
  int c0 = W, c1 = -1, r0 = H, r1 = -1;
  for (std::size_t t = first; t < end; ++t) {
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d p = cad_to_camera * scene.vertices[scene.triangles[t][k]].cast<double>();
      if (!(p.z() > kNearMm)) return false;
      uv[(t - first) * 3 + k] = {cx + f * p.x() / p.z(), cy + f * p.y() / p.z()};
    }
  }
  for (const auto& q : uv) {  // pixel-centre window of all projected vertices
    c0 = std::min(c0, static_cast<int>(std::clamp(std::ceil(q.x() - 0.5 - kMarginPx), -1.0, double(W))));
    c1 = std::max(c1, static_cast<int>(std::clamp(std::floor(q.x() - 0.5 + kMarginPx), -1.0, double(W))));
    r0 = std::min(r0, static_cast<int>(std::clamp(std::ceil(q.y() - 0.5 - kMarginPx), -1.0, double(H))));
    r1 = std::max(r1, static_cast<int>(std::clamp(std::floor(q.y() - 0.5 + kMarginPx), -1.0, double(H))));
  }
  c0 = std::max(c0, 0), r0 = std::max(r0, 0), c1 = std::min(c1, W - 1), r1 = std::min(r1, H - 1);
  if (c0 > c1 || r0 > r1) return true;
  const int mw = c1 - c0 + 1, mh = r1 - r0 + 1;
  std::vector<std::uint8_t> mask(std::size_t(mw) * mh, 0);
  std::vector<int> row_lo(mh, c1 + 1), row_hi(mh, c0 - 1);  // marked columns of each row, to gather fast
  // Pass 2: mark pixel centres inside (or within kMarginPx of) each triangle.
  for (std::size_t i = 0; i + 2 < uv.size(); i += 3) {
    const Eigen::Vector2d a = uv[i], b = uv[i + 1], c = uv[i + 2];
    const int tc0 = std::max(c0, static_cast<int>(std::ceil(std::min({a.x(), b.x(), c.x()}) - 0.5 - kMarginPx)));
    const int tc1 = std::min(c1, static_cast<int>(std::floor(std::max({a.x(), b.x(), c.x()}) - 0.5 + kMarginPx)));
    const int tr0 = std::max(r0, static_cast<int>(std::ceil(std::min({a.y(), b.y(), c.y()}) - 0.5 - kMarginPx)));
    const int tr1 = std::min(r1, static_cast<int>(std::floor(std::max({a.y(), b.y(), c.y()}) - 0.5 + kMarginPx)));
    if (tc0 > tc1 || tr0 > tr1) continue;
    // Orientation-free edge tests: signed distance (px) of a pixel centre to each edge line, positive
    // inside. Each is linear in the column, so every row's inside span is an interval: O(rows) per triangle.
    const double area = (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
    const double sign = area >= 0 ? 1.0 : -1.0;
    const Eigen::Vector2d v[3] = {a, b, c};
    double nx[3], ny[3], off[3];  // inside: nx * u + ny * v + off >= -margin
    bool sliver = !(std::abs(area) > 1e-12);
    for (int k = 0; k < 3 && !sliver; ++k) {
      const Eigen::Vector2d d = v[(k + 1) % 3] - v[k];
      const double len = d.norm();
      if (!(len > 1e-12)) { sliver = true; break; }
      nx[k] = -d.y() * sign / len;
      ny[k] = d.x() * sign / len;
      off[k] = -(nx[k] * v[k].x() + ny[k] * v[k].y());
    }
    for (int row = tr0; row <= tr1; ++row) {
      double lo = tc0, hi = tc1;  // column interval, as reals
      if (!sliver) {              // a sliver (edge-on triangle): keep its whole small box, to be safe
        const double vc = row + 0.5;
        for (int k = 0; k < 3; ++k) {
          // nx * (col + 0.5) + (ny * vc + off + margin) >= 0
          const double rest = ny[k] * vc + off[k] + kMarginPx;
          if (nx[k] > 1e-15) lo = std::max(lo, -rest / nx[k] - 0.5);
          else if (nx[k] < -1e-15) hi = std::min(hi, -rest / nx[k] - 0.5);
          else if (rest < 0) hi = lo - 1;  // edge parallel to the rows, the whole row outside
        }
      }
      const int from = std::max(tc0, static_cast<int>(std::ceil(lo - 1e-9)));
      const int to = std::min(tc1, static_cast<int>(std::floor(hi + 1e-9)));
      if (from <= to) {
        std::fill_n(mask.begin() + std::ptrdiff_t(row - r0) * mw + (from - c0), to - from + 1, 1);
        row_lo[row - r0] = std::min(row_lo[row - r0], from);
        row_hi[row - r0] = std::max(row_hi[row - r0], to);
      }
    }
  }
  for (int row = r0; row <= r1; ++row)
    for (int col = row_lo[row - r0]; col <= row_hi[row - r0]; ++col)
      if (mask[std::size_t(row - r0) * mw + (col - c0)]) pixels.push_back(std::uint32_t(row) * W + col);
  return true;
}

std::uint64_t count_visible_pixels(const Raycaster& caster, const Camera& camera, const Pose& camera_to_cad,
                                   std::uint32_t element) {
  std::vector<std::uint32_t> pixels;
  if (!element_footprint(caster.scene(), camera, camera_to_cad, element, pixels))
    return count_element_pixels(caster, camera, camera_to_cad, element);  // element crosses the camera plane
  if (pixels.empty()) return 0;
  std::vector<Ray> rays;
  std::vector<Hit> hits;
  cast_pixels(caster, camera, camera_to_cad, pixels, rays, hits);
  std::uint64_t n = 0;
  for (const Hit& h : hits) n += h.element == element ? 1 : 0;
  return n;
}

std::uint64_t count_measurable_pixels(const Raycaster& caster, const Camera& camera, const Pose& camera_to_cad,
                                      std::uint32_t element, const MeasurableModel& model) {
  const Scene& scene = caster.scene();
  if (element >= scene.elements.size()) return 0;
  std::vector<std::uint32_t> pixels;
  if (!element_footprint(scene, camera, camera_to_cad, element, pixels)) {
    // The element crosses the camera plane: every pixel of the image may show it.
    pixels.resize(std::size_t(camera.width_px) * camera.height_px);
    for (std::size_t i = 0; i < pixels.size(); ++i) pixels[i] = static_cast<std::uint32_t>(i);
  }
  if (pixels.empty()) return 0;
  const Eigen::Matrix3d rot = camera_to_cad.linear();
  std::vector<Ray> rays;
  std::vector<Hit> hits;
  cast_pixels(caster, camera, camera_to_cad, pixels, rays, hits);
  // Shadow rays towards the projector for the element's pixels that pass the incidence tests.
  const double cos_max = std::cos(model.max_incidence_deg * M_PI / 180.0);
  const Eigen::Vector3d eye = camera_to_cad.translation();
  const Eigen::Vector3d projector = eye + model.baseline_mm * rot.col(0);
  std::vector<Ray> shadows;
  for (std::size_t i = 0; i < hits.size(); ++i) {
    const Hit& h = hits[i];
    if (h.element != element || !std::isfinite(h.distance_mm)) continue;
    const Eigen::Vector3d dir = rays[i].direction.cast<double>().normalized();
    const Eigen::Vector3d n = h.normal.cast<double>();  // faces the camera ray
    if (-dir.dot(n) < cos_max) continue;                // camera incidence too grazing
    const Eigen::Vector3d p = eye + dir * double(h.distance_mm);
    Eigen::Vector3d to_projector = projector - p;
    const double dist = to_projector.norm();
    if (!(dist > 0)) continue;
    to_projector /= dist;
    if (to_projector.dot(n) < cos_max) continue;  // not lit, or lit too grazing to decode the pattern
    const double eps = 0.05 + 1e-4 * dist;
    Ray shadow;
    shadow.origin = (p + n * eps).cast<float>();
    shadow.direction = to_projector.cast<float>();
    shadow.tmax_mm = static_cast<float>(dist - 2 * eps);
    shadows.push_back(shadow);
  }
  std::vector<Hit> blocked;
  caster.cast(shadows, blocked);
  std::uint64_t n = 0;
  for (const Hit& b : blocked) n += b.hit() ? 0 : 1;  // lit: nothing between the point and the projector
  return n;
}

}  // namespace ewis
