// Camera renders (depth, element id, normal per pixel) and the element pixel count for viewpoint scoring.
#include <algorithm>
#include <cmath>

#include "camera_block.hpp"
#include "ewis/core/parallel.hpp"
#include "ewis/raycast/raycaster.hpp"

namespace ewis {
namespace {

// Rays are cast in 4x4 pixel blocks aligned to the image grid (one 16-ray packet, or two 8-ray packets).
// The blocks never depend on the window, so a pixel gets the same ray packet - and so bit-identical
// results - in a full render, a windowed render and count_element_pixels.
constexpr int kBlock = 4;
constexpr int kTile = 32;  // parallel work item: 32x32 pixels

PixelWindow clamp_window(const Camera& camera, const PixelWindow* window) {
  PixelWindow w{0, 0, camera.width_px, camera.height_px};
  if (window) {
    w.col0 = std::max(window->col0, 0);
    w.row0 = std::max(window->row0, 0);
    w.col1 = std::min(window->col1, camera.width_px);
    w.row1 = std::min(window->row1, camera.height_px);
  }
  return w;
}

// Calls visit(tile_index, col, row, distance, element, normal) for every image pixel of the 4x4 blocks that
// overlap `w` (pixels outside `w` included: callers filter). Tiles run in parallel; `visit` may only write
// state of its own tile or pixel.
template <class Visit>
void cast_window(const Raycaster& caster, const Camera& camera, const Pose& camera_to_world, const PixelWindow& w,
                 bool want_normals, const Visit& visit) {
  if (w.col0 >= w.col1 || w.row0 >= w.row1) return;
  const int tc0 = w.col0 / kTile, tc1 = (w.col1 + kTile - 1) / kTile;
  const int tr0 = w.row0 / kTile, tr1 = (w.row1 + kTile - 1) / kTile;
  const int tiles_x = tc1 - tc0, tiles = tiles_x * (tr1 - tr0);
  // World direction of pixel (col, row): normalise(x * R.col(0) + y * R.col(1) + R.col(2)), in float.
  const Eigen::Matrix3f rot = camera_to_world.linear().cast<float>();
  const Eigen::Vector3f origin = camera_to_world.translation().cast<float>();
  const float inv_f = static_cast<float>(1.0 / camera.focal_px());
  const float cx = static_cast<float>(camera.cx()), cy = static_cast<float>(camera.cy());
  parallel_blocks(static_cast<std::size_t>(tiles), 1, [&](std::size_t t0, std::size_t t1) {
    detail::CameraBlock block;
    detail::CameraHits hits;
    block.origin = origin;
    int cols[16], rows[16];
    for (std::size_t t = t0; t < t1; ++t) {
      const int tx = tc0 + static_cast<int>(t) % tiles_x, ty = tr0 + static_cast<int>(t) / tiles_x;
      // Blocks of this tile that overlap the window.
      const int c0 = std::max(tx * kTile, w.col0 / kBlock * kBlock), c1 = std::min((tx + 1) * kTile, w.col1);
      const int r0 = std::max(ty * kTile, w.row0 / kBlock * kBlock), r1 = std::min((ty + 1) * kTile, w.row1);
      for (int br = r0; br < r1; br += kBlock)
        for (int bc = c0; bc < c1; bc += kBlock) {
          int n = 0;
          for (int dr = 0; dr < kBlock; ++dr) {
            const int row = br + dr;
            if (row >= camera.height_px) break;
            const float y = (row + 0.5f - cy) * inv_f;
            for (int dc = 0; dc < kBlock; ++dc) {
              const int col = bc + dc;
              if (col >= camera.width_px) break;
              const float x = (col + 0.5f - cx) * inv_f;
              const Eigen::Vector3f d = x * rot.col(0) + y * rot.col(1) + rot.col(2);
              const float inv = 1.0f / std::sqrt(d.squaredNorm());
              block.dx[n] = d.x() * inv;
              block.dy[n] = d.y() * inv;
              block.dz[n] = d.z() * inv;
              cols[n] = col;
              rows[n] = row;
              ++n;
            }
          }
          block.count = n;
          detail::RaycasterAccess::cast_camera_block(caster, block, hits, want_normals);
          for (int i = 0; i < n; ++i) visit(t, cols[i], rows[i], hits, i);
        }
    }
  });
}

bool inside(const PixelWindow& w, int col, int row) {
  return col >= w.col0 && col < w.col1 && row >= w.row0 && row < w.row1;
}

}  // namespace

Render render(const Raycaster& caster, const Camera& camera, const Pose& camera_to_world, const PixelWindow* window) {
  Render r;
  r.width_px = std::max(camera.width_px, 0);
  r.height_px = std::max(camera.height_px, 0);
  const std::size_t n = std::size_t(r.width_px) * r.height_px;
  r.distance_mm.assign(n, std::numeric_limits<float>::infinity());
  r.element.assign(n, kNoElement);
  r.normal.assign(n, Eigen::Vector3f::Zero());
  const PixelWindow w = clamp_window(camera, window);
  cast_window(caster, camera, camera_to_world, w, true,
              [&](std::size_t, int col, int row, const detail::CameraHits& h, int lane) {
                if (h.element[lane] == kNoElement || !inside(w, col, row)) return;
                const std::size_t i = std::size_t(row) * r.width_px + col;  // each pixel written by one tile only
                r.distance_mm[i] = h.distance_mm[lane];
                r.element[i] = h.element[lane];
                r.normal[i] = h.normal[lane];
              });
  return r;
}

std::size_t count_element_pixels(const Raycaster& caster, const Camera& camera, const Pose& camera_to_world,
                                 std::uint32_t element) {
  const Scene& scene = caster.scene();
  if (element >= scene.elements.size() || !caster.included(element) || scene.elements[element].triangle_count == 0)
    return 0;
  const Element& e = scene.elements[element];
  // paper 3.3 (scoring: pixels of the element in a render): only pixels inside the projection of the
  // element's bounding box can show it, so only those rays are cast.
  PixelWindow w{0, 0, camera.width_px, camera.height_px};
  const Pose world_to_camera = camera_to_world.inverse();
  double umin = 1e300, umax = -1e300, vmin = 1e300, vmax = -1e300;
  bool behind = false;
  for (int c = 0; c < 8 && !behind; ++c) {
    const Eigen::Vector3d corner(c & 1 ? e.bounds_max.x() : e.bounds_min.x(), c & 2 ? e.bounds_max.y() : e.bounds_min.y(),
                                 c & 4 ? e.bounds_max.z() : e.bounds_min.z());
    double u, v;
    // A corner at or behind the camera plane: the box's image is unbounded, use the whole image.
    if (!camera.project(world_to_camera * corner, u, v) || !std::isfinite(u) || !std::isfinite(v)) {
      behind = true;
      break;
    }
    umin = std::min(umin, u);
    umax = std::max(umax, u);
    vmin = std::min(vmin, v);
    vmax = std::max(vmax, v);
  }
  if (!behind) {
    // One pixel of margin for rounding of hit points on the box's silhouette.
    w.col0 = static_cast<int>(std::max(std::floor(umin) - 1.0, 0.0));
    w.row0 = static_cast<int>(std::max(std::floor(vmin) - 1.0, 0.0));
    w.col1 = static_cast<int>(std::min(std::ceil(umax) + 1.0, double(camera.width_px)));
    w.row1 = static_cast<int>(std::min(std::ceil(vmax) + 1.0, double(camera.height_px)));
    if (w.col0 >= w.col1 || w.row0 >= w.row1) return 0;
  }
  const int tiles_x = (w.col1 + kTile - 1) / kTile - w.col0 / kTile;
  const int tiles = tiles_x * ((w.row1 + kTile - 1) / kTile - w.row0 / kTile);
  std::vector<std::size_t> per_tile(std::max(tiles, 0), 0);
  cast_window(caster, camera, camera_to_world, w, false,
              [&](std::size_t t, int col, int row, const detail::CameraHits& h, int lane) {
                if (h.element[lane] == element && inside(w, col, row)) ++per_tile[t];
              });
  std::size_t sum = 0;
  for (std::size_t c : per_tile) sum += c;
  return sum;
}

}  // namespace ewis
