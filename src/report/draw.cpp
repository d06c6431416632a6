// Raster helpers of the report's pictures: depth-tested splats, eye-dome shading, clipped lines and rings.
#include "draw.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>

#include "ewis/core/parallel.hpp"

namespace ewis::report_detail {

SplatBuffer splat_points(const std::vector<Eigen::Vector3f>& points_cad, const std::vector<std::uint8_t>& keep,
                         const Camera& camera, const Pose& camera_to_cad, int radius_px) {
  SplatBuffer buf;
  buf.width_px = camera.width_px;
  buf.height_px = camera.height_px;
  const std::size_t w = std::size_t(std::max(0, buf.width_px)), h = std::size_t(std::max(0, buf.height_px));
  if (w * h == 0) return buf;
  const Eigen::Matrix3d rot = camera_to_cad.linear().transpose();
  const Eigen::Vector3d tr = -(rot * camera_to_cad.translation());
  const int r = std::clamp(radius_px, 0, 16);
  const int r2 = r * r + r;  // rounder small discs
  const Camera::Projection projection = camera.projection();
  // A pixel holds the smallest word of the points whose disc covers it, i.e. the smallest over the disc around it
  // of the smallest word centred on each pixel: first each point into its centre's pixel (one atomic minimum a
  // point instead of one per disc pixel; a plain load first, since most land behind what a pixel already holds), in
  // a frame r pixels wider on each side (discs centred outside the image reach into it), then that minimum over
  // the disc, pixel by pixel. The same words as splatting every disc.
  const std::size_t ew = w + 2 * std::size_t(r), eh = h + 2 * std::size_t(r);
  std::vector<std::uint64_t>& centre = buf.key;  // becomes the image, in place, below
  centre.assign(ew * eh, SplatBuffer::kEmpty);
  parallel_blocks(points_cad.size(), 1 << 15, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      if (!keep.empty() && !keep[i]) continue;
      const Eigen::Vector3d pc = rot * points_cad[i].cast<double>() + tr;
      double u, v;
      if (pc.z() <= 1e-3 || !projection.project(pc, u, v)) continue;
      const int cx = static_cast<int>(std::floor(u)), cy = static_cast<int>(std::floor(v));
      if (cx < -r || cy < -r || cx >= buf.width_px + r || cy >= buf.height_px + r) continue;
      const std::uint64_t word = SplatBuffer::pack(static_cast<float>(pc.z()), static_cast<std::uint32_t>(i));
      std::atomic_ref<std::uint64_t> pixel(centre[std::size_t(cy + r) * ew + std::size_t(cx + r)]);
      std::uint64_t held = pixel.load(std::memory_order_relaxed);
      while (word < held && !pixel.compare_exchange_weak(held, word, std::memory_order_relaxed)) {
      }
    }
  });
  // Image row y takes the frame's rows y .. y + 2r; once done, frame row y is needed by no later image row, so
  // the image row is written over it (rows in order), then moved to its place in the w-wide image.
  std::vector<int> half(2 * std::size_t(r) + 1);  // the disc's half-width at each row offset
  for (int dy = -r; dy <= r; ++dy) {
    int hw = 0;
    while ((hw + 1) * (hw + 1) + dy * dy <= r2) ++hw;
    half[std::size_t(dy + r)] = hw;
  }
  std::vector<std::uint64_t> row(w);
  for (std::size_t y = 0; y < h; ++y) {
    std::fill(row.begin(), row.end(), SplatBuffer::kEmpty);
    for (int dy = -r; dy <= r; ++dy) {
      const std::uint64_t* src = centre.data() + (y + std::size_t(dy + r)) * ew + std::size_t(r);
      const int hw = half[std::size_t(dy + r)];
      for (int dx = -hw; dx <= hw; ++dx) {
        const std::uint64_t* s = src + dx;
        for (std::size_t x = 0; x < w; ++x) row[x] = std::min(row[x], s[x]);
      }
    }
    std::copy(row.begin(), row.end(), centre.begin() + std::ptrdiff_t(y * w));
  }
  centre.resize(w * h);
  return buf;
}

bool depth_range(const SplatBuffer& buf, double& near_mm, double& far_mm) {
  // The 2nd and 98th percentiles of the covered pixels' depths, exactly (the values nth_element would pick): the
  // depths are positive floats, whose bit patterns order as they do, so a histogram of their top 16 bits finds the
  // bucket holding each rank, and only that bucket's values are sorted.
  constexpr std::size_t kBuckets = std::size_t(1) << 16;
  std::vector<std::uint32_t> count(kBuckets, 0);
  std::size_t n = 0;
  for (std::size_t k = 0; k < buf.size(); ++k)
    if (buf.key[k] != SplatBuffer::kEmpty) {
      ++count[buf.key[k] >> 48];
      ++n;
    }
  if (n == 0) return false;
  // The bucket holding each rank and the ranks below it; then one pass gathers those buckets' depths.
  const auto bucket_of = [&](std::size_t rank, std::size_t& below) {
    std::size_t bucket = 0;
    below = 0;
    while (below + count[bucket] <= rank) below += count[bucket++];
    return static_cast<std::uint64_t>(bucket);
  };
  const std::size_t rank_lo = n / 50, rank_hi = n - 1 - n / 50;
  std::size_t below_lo = 0, below_hi = 0;
  const std::uint64_t bucket_lo = bucket_of(rank_lo, below_lo), bucket_hi = bucket_of(rank_hi, below_hi);
  std::vector<float> in_lo, in_hi;
  for (std::size_t k = 0; k < buf.size(); ++k) {
    if (buf.key[k] == SplatBuffer::kEmpty) continue;
    const std::uint64_t bucket = buf.key[k] >> 48;
    if (bucket == bucket_lo) in_lo.push_back(buf.depth_mm(k));
    if (bucket == bucket_hi) in_hi.push_back(buf.depth_mm(k));
  }
  const auto select = [](std::vector<float>& in, std::size_t at) {
    std::nth_element(in.begin(), in.begin() + static_cast<std::ptrdiff_t>(at), in.end());
    return in[at];
  };
  near_mm = select(in_lo, rank_lo - below_lo);
  far_mm = select(in_hi, rank_hi - below_hi);
  if (far_mm <= near_mm) far_mm = near_mm + 1.0;
  return true;
}

std::vector<float> eye_dome_factor(const SplatBuffer& buf, double strength) {
  // Eye-dome lighting (Boucheny 2009): each pixel compares its log-depth with neighbours two pixels away;
  // being behind them (a depth edge) darkens it. Only covered neighbours count, so sparse splats stay light.
  const int w = buf.width_px, h = buf.height_px;
  std::vector<float> f(buf.size(), 1.0f);
  static const int off[8][2] = {{2, 0}, {-2, 0}, {0, 2}, {0, -2}, {1, 1}, {-1, -1}, {1, -1}, {-1, 1}};
  constexpr int kRows = 16;  // rows per task; each task takes the log-depths of its rows and two more each side once
  const int tasks = (std::max(h, 0) + kRows - 1) / kRows;
  parallel_for_each_index(std::size_t(tasks), [&](std::size_t task) {  // each pixel its own
    const int y0 = static_cast<int>(task) * kRows, y1 = std::min(h, y0 + kRows);
    const int l0 = std::max(0, y0 - 2), l1 = std::min(h, y1 + 2);
    std::vector<double> log_depth(std::size_t(l1 - l0) * w);  // NaN: no point there
    for (int y = l0; y < l1; ++y)
      for (int x = 0; x < w; ++x) {
        const float z = buf.depth_mm(std::size_t(y) * w + x);
        log_depth[std::size_t(y - l0) * w + x] = std::isfinite(z) ? std::log2(double(z)) : std::nan("");
      }
    for (int y = y0; y < y1; ++y)
      for (int x = 0; x < w; ++x) {
        const double lz = log_depth[std::size_t(y - l0) * w + x];
        if (std::isnan(lz)) continue;
        double sum = 0.0;
        for (const auto& o : off) {
          const int xx = x + o[0], yy = y + o[1];
          if (xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
          const double ln = log_depth[std::size_t(yy - l0) * w + xx];
          if (std::isnan(ln)) continue;
          sum += std::max(0.0, lz - ln);
        }
        f[std::size_t(y) * w + x] = static_cast<float>(std::exp(-strength * sum / 8.0));
      }
  }, 1);
  return f;
}

void put_pixel(Image& img, int x, int y, const Rgb& c) {
  if (x < 0 || y < 0 || x >= img.width_px || y >= img.height_px) return;
  std::uint8_t* p = img.at(x, y);
  p[0] = c[0], p[1] = c[1], p[2] = c[2];
}

void blend_pixel(Image& img, int x, int y, const Rgb& c, double alpha) {
  if (x < 0 || y < 0 || x >= img.width_px || y >= img.height_px) return;
  std::uint8_t* p = img.at(x, y);
  for (int k = 0; k < 3; ++k) p[k] = static_cast<std::uint8_t>(std::lround(p[k] * (1.0 - alpha) + c[k] * alpha));
}

void fill_disc(Image& img, const Eigen::Vector2d& centre, double radius_px, const Rgb& c) {
  const int x0 = int(std::floor(centre.x() - radius_px)), x1 = int(std::ceil(centre.x() + radius_px));
  const int y0 = int(std::floor(centre.y() - radius_px)), y1 = int(std::ceil(centre.y() + radius_px));
  const double r2 = radius_px * radius_px;
  for (int y = std::max(0, y0); y <= std::min(img.height_px - 1, y1); ++y)
    for (int x = std::max(0, x0); x <= std::min(img.width_px - 1, x1); ++x) {
      const double dx = x + 0.5 - centre.x(), dy = y + 0.5 - centre.y();
      if (dx * dx + dy * dy <= r2) put_pixel(img, x, y, c);
    }
}

namespace {
// Liang-Barsky clipping of segment a-b to [lo, hi]^2; false when nothing is left.
bool clip(Eigen::Vector2d& a, Eigen::Vector2d& b, const Eigen::Vector2d& lo, const Eigen::Vector2d& hi) {
  double t0 = 0.0, t1 = 1.0;
  const Eigen::Vector2d d = b - a;
  for (int k = 0; k < 2; ++k) {
    const double p[2] = {-d[k], d[k]};
    const double q[2] = {a[k] - lo[k], hi[k] - a[k]};
    for (int s = 0; s < 2; ++s) {
      if (p[s] == 0.0) {
        if (q[s] < 0) return false;
        continue;
      }
      const double t = q[s] / p[s];
      if (p[s] < 0) t0 = std::max(t0, t);
      else t1 = std::min(t1, t);
    }
  }
  if (t0 > t1) return false;
  const Eigen::Vector2d a0 = a;
  a = a0 + t0 * d;
  b = a0 + t1 * d;
  return true;
}
}  // namespace

void draw_line(Image& img, const Eigen::Vector2d& a_in, const Eigen::Vector2d& b_in, const Rgb& c,
               double thickness_px) {
  Eigen::Vector2d a = a_in, b = b_in;
  if (!a.allFinite() || !b.allFinite()) return;
  const double m = thickness_px + 2.0;
  if (!clip(a, b, Eigen::Vector2d(-m, -m), Eigen::Vector2d(img.width_px + m, img.height_px + m))) return;
  const double len = (b - a).norm();
  const int steps = std::max(1, static_cast<int>(std::ceil(len / 0.5)));  // bounded: clipped to the image
  const double r = std::max(0.5, thickness_px / 2.0);
  for (int s = 0; s <= steps; ++s) fill_disc(img, a + (b - a) * (double(s) / steps), r, c);
}

void draw_ring(Image& img, const Eigen::Vector2d& centre, double radius_px, const Rgb& c, double thickness_px) {
  if (!centre.allFinite()) return;
  const double ro = radius_px + thickness_px / 2.0, ri = std::max(0.0, radius_px - thickness_px / 2.0);
  const int x0 = int(std::floor(centre.x() - ro)), x1 = int(std::ceil(centre.x() + ro));
  const int y0 = int(std::floor(centre.y() - ro)), y1 = int(std::ceil(centre.y() + ro));
  for (int y = std::max(0, y0); y <= std::min(img.height_px - 1, y1); ++y)
    for (int x = std::max(0, x0); x <= std::min(img.width_px - 1, x1); ++x) {
      const double dx = x + 0.5 - centre.x(), dy = y + 0.5 - centre.y();
      const double d2 = dx * dx + dy * dy;
      if (d2 <= ro * ro && d2 >= ri * ri) put_pixel(img, x, y, c);
    }
}

bool project_cad(const Camera& camera, const Pose& cad_to_camera, const Eigen::Vector3d& p_cad, Eigen::Vector2d& uv) {
  const Eigen::Vector3d pc = cad_to_camera * p_cad;
  double u, v;
  if (!camera.project(pc, u, v)) return false;
  uv = {u, v};
  return true;
}

void draw_axis_segment(Image& img, const Camera& camera, const Pose& cad_to_camera, const Eigen::Vector3d& a,
                       const Eigen::Vector3d& b, const Rgb& core, double thickness_px, bool dashed) {
  Eigen::Vector3d pa = cad_to_camera * a, pb = cad_to_camera * b;
  const double near = 1.0;  // mm: clip to the front of the camera
  if (pa.z() < near && pb.z() < near) return;
  if (pa.z() < near) pa = pa + (pb - pa) * ((near - pa.z()) / (pb.z() - pa.z()));
  if (pb.z() < near) pb = pb + (pa - pb) * ((near - pb.z()) / (pa.z() - pb.z()));
  double ua, va, ub, vb;
  if (!camera.project(pa, ua, va) || !camera.project(pb, ub, vb)) return;
  const Eigen::Vector2d A(ua, va), B(ub, vb);
  if (!dashed) {
    draw_line(img, A, B, Rgb{0, 0, 0}, thickness_px + 2.0);
    draw_line(img, A, B, core, thickness_px);
    return;
  }
  // Dashes of ~6 px (a stretch bridged without data).
  const double len = (B - A).norm();
  const int n = std::clamp(static_cast<int>(len / 6.0), 1, 2000);
  for (int k = 0; k < n; k += 2) {
    const Eigen::Vector2d s = A + (B - A) * (double(k) / n), e = A + (B - A) * (double(k + 1) / n);
    draw_line(img, s, e, Rgb{0, 0, 0}, thickness_px + 2.0);
    draw_line(img, s, e, core, thickness_px);
  }
}

Rgb scale_rgb(const Rgb& c, double f) {
  Rgb out;
  for (int k = 0; k < 3; ++k) out[k] = static_cast<std::uint8_t>(std::clamp(std::lround(c[k] * f), 0L, 255L));
  return out;
}

}  // namespace ewis::report_detail
