#pragma once
// Internal to io/: maps a file's fields (PLY properties, PCD FIELDS) onto Cloud attributes, holds the
// destination arrays while a reader decodes into them, then drops non-finite points (CONTRACT.md "Scan").
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "ewis/io/cloud_io.hpp"
#include "scalar_type.hpp"

namespace ewis::io_detail {

struct FieldSpec {
  std::string name;
  ScalarType type = ScalarType::Float32;
  std::size_t count = 1;  // PCD COUNT; PLY scalar properties have 1
};

enum class Role : std::uint8_t { Skip, X, Y, Z, NX, NY, NZ, Red, Green, Blue, PackedRgb, Intensity, Scalar };

// Roles by name: x y z; nx ny nz / normal_x..; red green blue / r g b / diffuse_*; rgb / rgba (packed, 4 bytes);
// intensity / scalar_intensity; "_" (PCD padding) and multi-count fields are skipped; everything else a scalar.
std::vector<Role> assign_roles(const std::vector<FieldSpec>& fields);

class CloudBuilder {
 public:
  // Allocates n points and the attributes the fields carry; n must already be checked against the file size.
  CloudBuilder(const std::vector<FieldSpec>& fields, std::size_t n);

  bool has_xyz() const { return has_xyz_; }
  Role role(std::size_t field) const { return roles_[field]; }
  std::size_t size() const { return n_; }
  // Where field `f` goes as float (dst[i * dst_stride]); nullptr for skipped and packed fields.
  float* float_dest(std::size_t f, std::size_t& dst_stride);
  // Where a packed rgb/rgba field goes; nullptr for other fields.
  std::uint32_t* packed_dest(std::size_t f) { return roles_[f] == Role::PackedRgb ? packed_.data() : nullptr; }

  // Scales positions by `to_mm`, converts colours, drops points with a non-finite coordinate (counted).
  CloudFile finish(std::vector<std::string> file_fields, std::size_t width, std::size_t height, float to_mm);

 private:
  std::vector<FieldSpec> fields_;
  std::vector<Role> roles_;
  std::vector<std::size_t> scalar_index_;  // per field, index into cloud_.scalars for Role::Scalar
  std::size_t n_ = 0;
  bool has_xyz_ = false;
  Cloud cloud_;
  std::vector<float> channel_[3];  // red, green, blue as decoded
  float channel_scale_[3] = {1, 1, 1};
  std::vector<std::uint32_t> packed_;
};

}  // namespace ewis::io_detail
