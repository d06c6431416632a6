#pragma once
// Small raster helpers for the report's pictures (internal to the report stage): a depth-tested point splat
// and 2D lines and rings. No fonts: captions live in the HTML.
#include <Eigen/Core>
#include <bit>
#include <cstdint>
#include <limits>
#include <vector>

#include "ewis/core/camera.hpp"
#include "ewis/core/cloud.hpp"
#include "ewis/core/pose.hpp"
#include "ewis/io/image_io.hpp"

namespace ewis::report_detail {

// Per pixel: the depth (camera z, mm) and the index of the nearest point splatted there, in one word: the
// depth's float bits (positive, so ordered as the depths) above the index. The smallest word is the nearest
// point, the lowest index among equally near ones, whatever order the points come in: threads splat at once
// with an atomic minimum and the picture stays the same.
struct SplatBuffer {
  static constexpr std::uint64_t kEmpty = (std::uint64_t{0x7f800000} << 32) | 0xffffffffu;  // depth +inf, point -1
  int width_px = 0, height_px = 0;
  std::vector<std::uint64_t> key;

  static std::uint64_t pack(float depth_mm, std::uint32_t point) {
    return (std::uint64_t{std::bit_cast<std::uint32_t>(depth_mm)} << 32) | point;
  }
  std::size_t size() const { return key.size(); }
  float depth_mm(std::size_t k) const { return std::bit_cast<float>(static_cast<std::uint32_t>(key[k] >> 32)); }
  std::int32_t point(std::size_t k) const { return static_cast<std::int32_t>(static_cast<std::uint32_t>(key[k])); }
};

// Splats points[i] for every i with keep(i) (all when keep is empty) as discs of radius_px pixels.
SplatBuffer splat_points(const std::vector<Eigen::Vector3f>& points_cad, const std::vector<std::uint8_t>& keep,
                         const Camera& camera, const Pose& camera_to_cad, int radius_px);

// Depth range (low and high percentiles) of the covered pixels; false when nothing is covered.
bool depth_range(const SplatBuffer& buf, double& near_mm, double& far_mm);

// Eye-dome lighting factor per pixel in (0, 1]: 1 on smooth surfaces, darker where neighbours are nearer.
std::vector<float> eye_dome_factor(const SplatBuffer& buf, double strength = 60.0);

void put_pixel(Image& img, int x, int y, const Rgb& c);
void blend_pixel(Image& img, int x, int y, const Rgb& c, double alpha);
// A line of the given thickness (pixels) between image points; clipped to the image.
void draw_line(Image& img, const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Rgb& c, double thickness_px);
// A ring (circle outline) of radius r and thickness t.
void draw_ring(Image& img, const Eigen::Vector2d& centre, double radius_px, const Rgb& c, double thickness_px);
void fill_disc(Image& img, const Eigen::Vector2d& centre, double radius_px, const Rgb& c);

// Projects a CAD point into the image; false when behind the camera.
bool project_cad(const Camera& camera, const Pose& cad_to_camera, const Eigen::Vector3d& p_cad, Eigen::Vector2d& uv);

// A segment in CAD coordinates drawn with a dark outline and a coloured core (visible on any background).
void draw_axis_segment(Image& img, const Camera& camera, const Pose& cad_to_camera, const Eigen::Vector3d& a,
                       const Eigen::Vector3d& b, const Rgb& core, double thickness_px, bool dashed);

Rgb scale_rgb(const Rgb& c, double f);

}  // namespace ewis::report_detail
