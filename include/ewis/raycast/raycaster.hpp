#pragma once
// Ray casting over the CAD scene with Embree 3 (hidden behind this interface).
#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include "ewis/core/camera.hpp"
#include "ewis/core/pose.hpp"
#include "ewis/scene/scene.hpp"

namespace ewis {

namespace detail {
struct RaycasterAccess;  // the camera-block fast path of render() (src/raycast/)
}

inline constexpr std::uint32_t kNoElement = std::numeric_limits<std::uint32_t>::max();

struct Ray {
  Eigen::Vector3f origin;
  Eigen::Vector3f direction;  // need not be unit length; distances are along the unit direction
  float tmax_mm = std::numeric_limits<float>::infinity();
};

struct Hit {
  float distance_mm = std::numeric_limits<float>::infinity();  // along the unit direction
  std::uint32_t element = kNoElement;                          // kNoElement: no hit
  std::uint32_t triangle = kNoElement;
  Eigen::Vector3f normal = Eigen::Vector3f::Zero();            // unit geometric normal, facing the ray
  bool hit() const { return element != kNoElement; }
};

class Raycaster {
 public:
  // `include`: per element, whether it takes part (empty: all elements). The scene must outlive this.
  explicit Raycaster(const Scene& scene, const std::vector<bool>& include = {});
  // `packet_width`: rays per Embree packet in batch casts and renders: 1 (single rays), 4, 8 or 16;
  // 0 picks the widest packet the CPU supports natively. Every width gives the same hits (up to rounding
  // for rays grazing a triangle edge).
  Raycaster(const Scene& scene, const std::vector<bool>& include, int packet_width);
  ~Raycaster();
  Raycaster(Raycaster&&) noexcept;
  Raycaster& operator=(Raycaster&&) noexcept;

  const Scene& scene() const;
  Hit cast(const Ray& ray) const;
  bool occluded(const Ray& ray) const;  // any hit before tmax
  // Many rays, in parallel and in coherent packets where possible.
  void cast(const std::vector<Ray>& rays, std::vector<Hit>& hits) const;
  // One packet of up to kMaxPacket coherent rays (e.g. a small pixel tile), cast together on this thread.
  static constexpr int kMaxPacket = 16;
  void cast_packet(const Ray* rays, int count, Hit* hits) const;
  int packet_width() const;  // the width in use (1, 4, 8 or 16)
  // Whether element e takes part (the `include` mask).
  bool included(std::uint32_t element) const;

 private:
  friend struct detail::RaycasterAccess;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// An image rendered from a camera pose: per pixel depth along the ray (mm), element id, normal.
struct Render {
  int width_px = 0, height_px = 0;
  std::vector<float> distance_mm;         // infinity where nothing was hit
  std::vector<std::uint32_t> element;     // kNoElement where nothing was hit
  std::vector<Eigen::Vector3f> normal;    // world frame
};

struct PixelWindow {
  int col0 = 0, row0 = 0, col1 = 0, row1 = 0;  // [col0, col1) x [row0, row1); pixels outside stay empty
};

// Renders every pixel (or only `window`) with 1 ray per pixel centre, in parallel, packets of rays.
Render render(const Raycaster& caster, const Camera& camera, const Pose& camera_to_world,
              const PixelWindow* window = nullptr);

// Counts the pixels showing `element` (fast path for viewpoint scoring: only rays inside the element's
// projected bounding box are cast).
std::size_t count_element_pixels(const Raycaster& caster, const Camera& camera, const Pose& camera_to_world,
                                 std::uint32_t element);

}  // namespace ewis
