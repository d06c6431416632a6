#include "cloud_builder.hpp"

#include "ewis/core/scratch.hpp"

#include <algorithm>
#include <cmath>

namespace ewis::io_detail {

namespace {

Role role_of(const std::string& n) {
  if (n == "x") return Role::X;
  if (n == "y") return Role::Y;
  if (n == "z") return Role::Z;
  if (n == "nx" || n == "normal_x") return Role::NX;
  if (n == "ny" || n == "normal_y") return Role::NY;
  if (n == "nz" || n == "normal_z") return Role::NZ;
  if (n == "red" || n == "r" || n == "diffuse_red") return Role::Red;
  if (n == "green" || n == "g" || n == "diffuse_green") return Role::Green;
  if (n == "blue" || n == "b" || n == "diffuse_blue") return Role::Blue;
  if (n == "rgb" || n == "rgba") return Role::PackedRgb;
  if (n == "intensity" || n == "scalar_intensity") return Role::Intensity;
  if (n == "_") return Role::Skip;
  return Role::Scalar;
}

// Colour channels in PLY/PCD are uchar 0..255 by convention; ushort channels are 0..65535, float ones 0..1.
float channel_scale(ScalarType t) {
  switch (t) {
    case ScalarType::Int16: case ScalarType::UInt16: return 1.0f / 257.0f;
    case ScalarType::Float32: case ScalarType::Float64: return 255.0f;
    default: return 1.0f;
  }
}

std::uint8_t to_byte(float v) {
  if (!(v > 0.0f)) return 0;  // also NaN
  if (v >= 255.0f) return 255;
  return static_cast<std::uint8_t>(std::lround(v));
}

}  // namespace

std::vector<Role> assign_roles(const std::vector<FieldSpec>& fields) {
  std::vector<Role> roles(fields.size(), Role::Skip);
  int first[13];
  std::fill(std::begin(first), std::end(first), -1);
  for (std::size_t i = 0; i < fields.size(); ++i) {
    Role r = role_of(fields[i].name);
    if (fields[i].count != 1) r = Role::Skip;  // e.g. PCD fpfh[33]: listed in `fields`, not decoded
    if (r == Role::PackedRgb && scalar_size(fields[i].type) != 4) r = Role::Scalar;
    if (r != Role::Skip && r != Role::Scalar) {
      int& slot = first[static_cast<int>(r)];
      if (slot >= 0) r = Role::Scalar;  // a repeated name: keep the first as the attribute
      else slot = static_cast<int>(i);
    }
    roles[i] = r;
  }
  auto have = [&](Role r) { return first[static_cast<int>(r)] >= 0; };
  auto demote = [&](Role r) {
    if (have(r)) roles[first[static_cast<int>(r)]] = Role::Scalar;
    first[static_cast<int>(r)] = -1;
  };
  // Normals and colour channels only as complete triples; a lone "nx" or "r" stays a named scalar.
  if (!(have(Role::NX) && have(Role::NY) && have(Role::NZ))) {
    demote(Role::NX), demote(Role::NY), demote(Role::NZ);
  }
  if (!(have(Role::Red) && have(Role::Green) && have(Role::Blue))) {
    demote(Role::Red), demote(Role::Green), demote(Role::Blue);
  }
  if (have(Role::Red) && have(Role::PackedRgb)) demote(Role::PackedRgb);
  return roles;
}

CloudBuilder::CloudBuilder(const std::vector<FieldSpec>& fields, std::size_t n)
    : fields_(fields), roles_(assign_roles(fields)), scalar_index_(fields.size(), 0), n_(n) {
  bool x = false, y = false, z = false, normals = false, colors = false, packed = false, intensity = false;
  for (std::size_t i = 0; i < fields_.size(); ++i) {
    switch (roles_[i]) {
      case Role::X: x = true; break;
      case Role::Y: y = true; break;
      case Role::Z: z = true; break;
      case Role::NX: normals = true; break;
      case Role::Red: case Role::Green: case Role::Blue: {
        colors = true;
        const int c = roles_[i] == Role::Red ? 0 : roles_[i] == Role::Green ? 1 : 2;
        channel_scale_[c] = channel_scale(fields_[i].type);
        break;
      }
      case Role::PackedRgb: packed = true; break;
      case Role::Intensity: intensity = true; break;
      case Role::Scalar:
        scalar_index_[i] = cloud_.scalars.size();
        cloud_.scalars.push_back({fields_[i].name, {}});
        break;
      default: break;
    }
  }
  has_xyz_ = x && y && z;
  if (!has_xyz_) return;
  cloud_.points.resize(n);  // not initialised (Eigen): the decoder touches it first
  prefer_huge_pages(cloud_.points.data(), n * sizeof(Eigen::Vector3f));
  if (normals) {
    cloud_.normals.resize(n);
    prefer_huge_pages(cloud_.normals.data(), n * sizeof(Eigen::Vector3f));
  }
  if (colors)
    for (auto& c : channel_) c.resize(n);
  if (packed) packed_.resize(n);
  if (intensity) cloud_.intensities.resize(n);
  for (auto& s : cloud_.scalars) s.values.resize(n);
}

float* CloudBuilder::float_dest(std::size_t f, std::size_t& dst_stride) {
  dst_stride = 1;
  float* pts = cloud_.points.empty() ? nullptr : cloud_.points[0].data();
  float* nrm = cloud_.normals.empty() ? nullptr : cloud_.normals[0].data();
  switch (roles_[f]) {
    case Role::X: dst_stride = 3; return pts;
    case Role::Y: dst_stride = 3; return pts ? pts + 1 : nullptr;
    case Role::Z: dst_stride = 3; return pts ? pts + 2 : nullptr;
    case Role::NX: dst_stride = 3; return nrm;
    case Role::NY: dst_stride = 3; return nrm ? nrm + 1 : nullptr;
    case Role::NZ: dst_stride = 3; return nrm ? nrm + 2 : nullptr;
    case Role::Red: return channel_[0].data();
    case Role::Green: return channel_[1].data();
    case Role::Blue: return channel_[2].data();
    case Role::Intensity: return cloud_.intensities.data();
    case Role::Scalar: return cloud_.scalars[scalar_index_[f]].values.data();
    default: return nullptr;
  }
}

CloudFile CloudBuilder::finish(std::vector<std::string> file_fields, std::size_t width, std::size_t height,
                               float to_mm) {
  CloudFile out;
  out.fields = std::move(file_fields);
  out.width = width;
  out.height = height;
  Cloud& c = cloud_;
  if (!channel_[0].empty()) {
    c.colors.resize(n_);
    for (std::size_t i = 0; i < n_; ++i)
      c.colors[i] = {to_byte(channel_[0][i] * channel_scale_[0]), to_byte(channel_[1][i] * channel_scale_[1]),
                     to_byte(channel_[2][i] * channel_scale_[2])};
  } else if (!packed_.empty()) {
    // PCL packs colour as 0xAARRGGBB (read as float or uint32: the bits are the same).
    c.colors.resize(n_);
    for (std::size_t i = 0; i < n_; ++i) {
      const std::uint32_t v = packed_[i];
      c.colors[i] = {std::uint8_t((v >> 16) & 0xff), std::uint8_t((v >> 8) & 0xff), std::uint8_t(v & 0xff)};
    }
  }
  for (auto& c : channel_) release_memory(c);
  release_memory(packed_);

  // Scale, then keep finite points in order (compaction in place, attributes alongside). The common case,
  // all finite, only reads the points.
  if (to_mm != 1.0f)
    for (auto& p : c.points) p *= to_mm;
  const auto finite = [](const Eigen::Vector3f& p) {
    return std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z());
  };
  std::size_t kept = 0;
  while (kept < n_ && finite(c.points[kept])) ++kept;
  for (std::size_t i = kept + 1; i < n_; ++i) {
    if (!finite(c.points[i])) continue;
    if (!c.normals.empty()) c.normals[kept] = c.normals[i];
    if (!c.colors.empty()) c.colors[kept] = c.colors[i];
    if (!c.intensities.empty()) c.intensities[kept] = c.intensities[i];
    for (auto& s : c.scalars) s.values[kept] = s.values[i];
    c.points[kept++] = c.points[i];
  }
  out.dropped_nonfinite = n_ - kept;
  if (kept != n_) {
    c.points.resize(kept);
    if (!c.normals.empty()) c.normals.resize(kept);
    if (!c.colors.empty()) c.colors.resize(kept);
    if (!c.intensities.empty()) c.intensities.resize(kept);
    for (auto& s : c.scalars) s.values.resize(kept);
  }
  out.cloud = std::move(c);
  return out;
}

}  // namespace ewis::io_detail
