// Wavefront OBJ reader, streamed: gives the Scene the Assimp 5.2 path gave (aiProcess_Triangulate |
// aiProcess_JoinIdenticalVertices, then one element per node name), measured against Assimp case by case
// (tests/scene/test_read_obj_mesh.cpp). What Assimp does, and so what we do:
// - `o NAME` (first word) and `g NAME` (the rest of the line, blanks after the name kept) start an object, i.e.
//   a node with its own mesh; `g` with the active group's name does nothing, `o` without a name does nothing,
//   `g` without a name starts an object named "" once another group was active. Faces before any o/g belong to
//   an object "defaultobject". `usemtl` with another material starts a new mesh of the same object (named
//   after the material) once the current mesh has faces.
// - Element name: the object name; for "" or a name Assimp reserves ("<...>", "$$$...", "ROOT") the mesh name,
//   else the file stem. Meshes of one name form one element, in order of first appearance.
// - Per mesh, vertices are numbered in order of first use by a face/line/point corner, and corners at equal
//   positions share one vertex (JoinIdenticalVertices; texture coordinates and normals are not read here, so
//   corners Assimp kept apart only for a different normal or uv share a vertex).
// - Polygons: triangles as they are; quads fanned from their concave corner (Assimp's float test), else from
//   the first corner; larger polygons fanned from the last corner, every second triangle rotated (Assimp's
//   ear cutting and NGON encoding give exactly that for convex polygons).
// - `v x y z w` is divided by w; `v x y z r g b` keeps x y z; a decimal comma is read as a point.
// Where Assimp 5.2 misreads a file we read it as written: `o NAME` again after another object adds to NAME
// (Assimp added to the other object's mesh), lines may start with blanks (Assimp skipped them), ".5" is a number
// (Assimp dropped the vertex), a UTF-8 BOM is skipped. Faces may use vertices defined later (as in Assimp):
// the file is then read twice.
#include "read_obj_mesh.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <optional>
#include <string_view>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "ewis/core/error.hpp"
#include "ewis/core/scratch.hpp"
#include "obj_line_reader.hpp"

namespace ewis::detail {
namespace {

bool blank(char c) { return c == ' ' || c == '\t' || c == '\v'; }

struct Words {
  std::string_view s;
  std::size_t i = 0;
  void skip_blanks() {
    while (i < s.size() && blank(s[i])) ++i;
  }
  std::string_view next() {  // "" at the end of the line
    skip_blanks();
    const std::size_t b = i;
    while (i < s.size() && !blank(s[i])) ++i;
    return s.substr(b, i - b);
  }
  std::string_view rest() {
    skip_blanks();
    return s.substr(i);
  }
};

// A number as Assimp's fast_atof accepts it when well formed ("+1", ".5", "1e-5", "nan", "inf", "1,5" for 1.5),
// correctly rounded (std::from_chars). Trailing characters make it malformed.
bool parse_float(std::string_view t, float& out) {
  if (!t.empty() && t[0] == '+') {
    t.remove_prefix(1);
    if (!t.empty() && (t[0] == '+' || t[0] == '-')) return false;
  }
  if (t.empty()) return false;
  std::string copy;
  if (t.find(',') != std::string_view::npos) {
    copy.assign(t);
    std::replace(copy.begin(), copy.end(), ',', '.');
    t = copy;
  }
  const char* end = t.data() + t.size();
  const auto r = std::from_chars(t.data(), end, out);
  if (r.ptr != end) return false;
  if (r.ec == std::errc::result_out_of_range) {  // beyond float: +-inf or 0, as a float conversion gives
    copy.assign(t);
    out = static_cast<float>(std::strtod(copy.c_str(), nullptr));
    return true;
  }
  return r.ec == std::errc();
}

// Assimp's reserved node names (the Assimp path does not take them as element names).
bool synthetic_name(const std::string& name) {
  return name.empty() || name.front() == '<' || name.rfind("$$$", 0) == 0 || name == "ROOT";
}

// TriangulateProcess's quad test, in its float arithmetic: the corner whose two angles to the opposite diagonal
// sum to more than pi is concave and the fan starts there.
int quad_fan_start(const Eigen::Vector3f* q[4]) {
  const auto normalized = [](Eigen::Vector3f v) {
    const float l = std::sqrt(v.x() * v.x() + v.y() * v.y() + v.z() * v.z());
    if (l == 0.0f) return v;
    const float inv = 1.0f / l;
    return Eigen::Vector3f(v.x() * inv, v.y() * inv, v.z() * inv);
  };
  const auto dot = [](const Eigen::Vector3f& a, const Eigen::Vector3f& b) {
    return a.x() * b.x() + a.y() * b.y() + a.z() * b.z();
  };
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector3f& v = *q[i];
    const Eigen::Vector3f left = normalized(*q[(i + 3) % 4] - v);
    const Eigen::Vector3f diag = normalized(*q[(i + 2) % 4] - v);
    const Eigen::Vector3f right = normalized(*q[(i + 1) % 4] - v);
    const float angle = std::acos(dot(left, diag)) + std::acos(dot(right, diag));
    if (angle > 3.1415926538f) return i;  // AI_MATH_PI_F
  }
  return 0;
}

// Thrown when a face uses a vertex not defined yet: the file is then read again with all vertices known.
struct ForwardReference {};

class ObjParser {
 public:
  // `all_vertices`: the positions of every `v` of the file, from a first pass (prefilled), or none.
  ObjParser(const std::string& path, std::optional<std::vector<Eigen::Vector3f>> all_vertices)
      : path_(path), stem_(std::filesystem::path(path).stem().string()), prefilled_(all_vertices.has_value()) {
    if (all_vertices) positions_ = std::move(*all_vertices);
  }

  // Pass `vertices_only`: collect the positions of every `v` line (for files with forward references).
  void run(bool vertices_only) {
    ObjLineReader lines(path_);
    std::string_view line;
    bool first = true;
    while (lines.next(line)) {
      line_ = lines.line_number();
      if (first && line.size() >= 3 && line.substr(0, 3) == "\xEF\xBB\xBF") line.remove_prefix(3);  // UTF-8 BOM
      first = false;
      Words w{line};
      const std::string_view key = w.next();
      if (key.empty() || key[0] == '#') continue;
      if (key == "v") {
        if (vertices_only || !prefilled_) read_vertex(w);
        else ++vertices_seen_;
      } else if (vertices_only) {
        continue;
      } else if (key == "f" || key == "l" || key == "p") {
        read_face(w, key[0]);
      } else if (key == "o") {
        const std::string_view name = w.next();
        if (!name.empty()) use_object(std::string(name));
      } else if (key == "g") {
        const std::string name(w.rest());
        if (name != active_group_) {
          create_object(name);
          active_group_ = name;
        }
      } else if (key == "usemtl") {
        use_material(w.rest());
      }
      // vt, vn, vp, s, mtllib, free-form geometry, ...: nothing that changes the triangles.
    }
  }

  std::vector<Eigen::Vector3f> take_positions() { return std::move(positions_); }
  Scene finish(std::size_t* dropped_degenerate);

 private:
  struct Mesh {
    std::string object, name;
    std::optional<std::string> material;
    bool has_faces = false;
    int segment = -1;
  };
  struct Segment {  // a mesh with faces: its vertices and triangles are contiguous in vertices_/triangles_
    std::uint32_t element = 0;
    std::size_t first_vertex = 0, first_triangle = 0;
  };

  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(path_, "line " + std::to_string(line_) + ": " + what);
  }

  void read_vertex(Words& w) {
    float x[7];
    int n = 0;
    for (std::string_view t = w.next(); !t.empty() && t[0] != '#'; t = w.next()) {
      if (n == 7 || !parse_float(t, x[n])) {
        if (n == 7) fail("a vertex needs 3, 4 (x y z w) or 6 (x y z r g b) numbers, found more than 6");
        fail("malformed number '" + std::string(t.substr(0, 40)) + "'");
      }
      ++n;
    }
    if (n == 4) {
      if (x[3] == 0.0f) fail("vertex with w = 0");
      positions_.emplace_back(x[0] / x[3], x[1] / x[3], x[2] / x[3]);
    } else if (n == 3 || n == 6) {
      positions_.emplace_back(x[0], x[1], x[2]);
    } else {
      fail("a vertex needs 3, 4 (x y z w) or 6 (x y z r g b) numbers, found " + std::to_string(n));
    }
    if (positions_.size() > std::size_t(std::numeric_limits<std::int32_t>::max())) fail("too many vertices");
  }

  // A face/line/point corner "v", "v/vt", "v//vn" or "v/vt/vn": the vertex index, 0-based.
  std::uint32_t corner_index(std::string_view t) {
    long long v = 0;
    const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
    if (r.ec != std::errc() || (r.ptr != t.data() + t.size() && *r.ptr != '/'))
      fail("malformed face index '" + std::string(t.substr(0, 40)) + "'");
    const long long defined = static_cast<long long>(prefilled_ ? vertices_seen_ : positions_.size());
    if (v == 0) fail("face index 0 (OBJ counts vertices from 1)");
    const long long i = v > 0 ? v - 1 : defined + v;
    if (i < 0) fail("relative face index " + std::to_string(v) + " before the first vertex");
    if (i >= static_cast<long long>(positions_.size())) {
      if (!prefilled_) throw ForwardReference{};
      fail("face index " + std::to_string(v) + " but the file has " + std::to_string(positions_.size()) +
           " vertices");
    }
    return static_cast<std::uint32_t>(i);
  }

  void create_object(const std::string& name) {
    objects_.insert(name);
    mesh_ = Mesh{name, name, material_};
  }

  void use_object(const std::string& name) {
    if (objects_.count(name) == 0) return create_object(name);
    // Assimp keeps adding to the current mesh even when it belongs to another object; we add to NAME.
    if (!mesh_ || mesh_->object != name) mesh_ = Mesh{name, name, material_};
  }

  void use_material(std::string_view name) {
    while (!name.empty() && blank(name.back())) name.remove_suffix(1);
    if (name.empty() || material_ == name) return;
    material_ = std::string(name);
    if (!mesh_) {
      mesh_ = Mesh{"", material_.value(), material_};  // Assimp's mesh outside any object: gets no faces
      mesh_->segment = -2;
      return;
    }
    if (mesh_->material && *mesh_->material != name && mesh_->has_faces) {
      const std::string object = mesh_->object;
      mesh_ = Mesh{object, material_.value(), std::nullopt};
    }
    mesh_->material = material_;
  }

  std::uint32_t element_of(const Mesh& m) {
    const std::string& name = !synthetic_name(m.object) ? m.object : !synthetic_name(m.name) ? m.name : stem_;
    const auto [it, added] = element_ids_.emplace(name, static_cast<std::uint32_t>(element_names_.size()));
    if (added) element_names_.push_back(name);
    return it->second;
  }

  void start_segment() {
    mesh_->segment = static_cast<int>(segments_.size());
    segments_.push_back(Segment{element_of(*mesh_), vertices_.size(), triangles_.size()});
    stamp_.resize(positions_.size(), 0);
    local_.resize(positions_.size(), 0);
    table_.assign(64, 0);
    table_count_ = 0;
  }

  static std::uint32_t key_bits(float x) {
    if (x == 0.0f) x = 0.0f;  // -0 and +0 are one position
    std::uint32_t b;
    std::memcpy(&b, &x, 4);
    return b;
  }
  static std::size_t hash(const Eigen::Vector3f& p) {
    std::uint64_t h = key_bits(p.x()) * 0x9E3779B97F4A7C15ull;
    h = (h ^ key_bits(p.y())) * 0xC2B2AE3D27D4EB4Full;
    h = (h ^ key_bits(p.z())) * 0x165667B19E3779F9ull;
    return static_cast<std::size_t>(h ^ (h >> 29));
  }
  static bool same(const Eigen::Vector3f& a, const Eigen::Vector3f& b) {
    return key_bits(a.x()) == key_bits(b.x()) && key_bits(a.y()) == key_bits(b.y()) &&
           key_bits(a.z()) == key_bits(b.z());
  }

  // The index in vertices_ of global vertex g in the current segment (JoinIdenticalVertices: one vertex per
  // position and mesh, numbered in order of first use).
  std::uint32_t segment_vertex(std::uint32_t g) {
    const std::uint32_t seg = static_cast<std::uint32_t>(mesh_->segment) + 1;
    if (g >= stamp_.size()) {
      stamp_.resize(positions_.size(), 0);
      local_.resize(positions_.size(), 0);
    }
    if (stamp_[g] == seg) return local_[g];
    const Eigen::Vector3f& p = positions_[g];
    const std::size_t first = segments_.back().first_vertex;
    std::size_t mask = table_.size() - 1, slot = hash(p) & mask;
    std::uint32_t found = 0;
    for (; table_[slot] != 0; slot = (slot + 1) & mask) {
      if (same(vertices_[first + table_[slot] - 1], p)) {
        found = static_cast<std::uint32_t>(first + table_[slot] - 1);
        break;
      }
    }
    if (table_[slot] == 0) {
      found = static_cast<std::uint32_t>(vertices_.size());
      vertices_.push_back(p);
      table_[slot] = static_cast<std::uint32_t>(vertices_.size() - first);
      if (2 * ++table_count_ > table_.size()) grow_table(first);
    }
    stamp_[g] = seg;
    local_[g] = found;
    return found;
  }

  void grow_table(std::size_t first) {
    std::vector<std::uint32_t> bigger(table_.size() * 2, 0);
    const std::size_t mask = bigger.size() - 1;
    for (std::uint32_t e : table_) {
      if (e == 0) continue;
      std::size_t slot = hash(vertices_[first + e - 1]) & mask;
      while (bigger[slot] != 0) slot = (slot + 1) & mask;
      bigger[slot] = e;
    }
    table_.swap(bigger);
  }

  void add_triangle(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    const Eigen::Vector3d pa = vertices_[a].cast<double>();
    const double area2 = (vertices_[b].cast<double>() - pa).cross(vertices_[c].cast<double>() - pa).norm();
    if (!(area2 > 0.0) || !std::isfinite(area2)) {  // zero area or NaN/inf coordinates
      ++degenerate_;
      return;
    }
    triangles_.emplace_back(int(a), int(b), int(c));
  }

  void read_face(Words& w, char kind) {
    corners_.clear();
    for (std::string_view t = w.next(); !t.empty() && t[0] != '#'; t = w.next()) corners_.push_back(corner_index(t));
    if (corners_.empty()) return;  // Assimp ignores an empty face
    if (!mesh_ || mesh_->segment == -2) create_object("defaultobject");
    if (mesh_->segment < 0) start_segment();
    mesh_->has_faces = true;
    local_corners_.resize(corners_.size());
    for (std::size_t k = 0; k < corners_.size(); ++k) local_corners_[k] = segment_vertex(corners_[k]);
    const std::size_t n = corners_.size();
    if (kind != 'f' || n < 3) return;  // lines and points: their vertices count, they are not surfaces
    const std::uint32_t* c = local_corners_.data();
    if (n == 3) {
      add_triangle(c[0], c[1], c[2]);
    } else if (n == 4) {
      const Eigen::Vector3f* q[4] = {&positions_[corners_[0]], &positions_[corners_[1]], &positions_[corners_[2]],
                                     &positions_[corners_[3]]};
      const int s = quad_fan_start(q);
      add_triangle(c[s], c[(s + 1) % 4], c[(s + 2) % 4]);
      add_triangle(c[s], c[(s + 2) % 4], c[(s + 3) % 4]);
    } else {
      // Fan from the last corner: (n-1, i, i+1), the last one (n-3, n-2, n-1); a triangle whose first corner is
      // the previous triangle's first corner is rotated to (c, a, b) (Assimp's NGON encoding).
      std::size_t last_first = n;
      const auto emit = [&](std::size_t a, std::size_t b, std::size_t d) {
        if (a == last_first) {
          const std::size_t t = d;
          d = b;
          b = a;
          a = t;
        }
        last_first = a;
        add_triangle(c[a], c[b], c[d]);
      };
      for (std::size_t i = 0; i + 3 < n; ++i) emit(n - 1, i, i + 1);
      emit(n - 3, n - 2, n - 1);
    }
    if (triangles_.size() > std::size_t(std::numeric_limits<std::int32_t>::max())) fail("too many triangles");
  }

  std::string path_, stem_;
  std::size_t line_ = 0;
  std::vector<Eigen::Vector3f> positions_;  // every `v` of the file, in order
  bool prefilled_ = false;                  // positions_ came from a first pass
  std::size_t vertices_seen_ = 0;           // `v` lines so far, when prefilled (relative indices)

  std::unordered_set<std::string> objects_;
  std::optional<Mesh> mesh_;
  std::optional<std::string> material_;
  std::string active_group_;

  std::vector<std::string> element_names_;
  std::unordered_map<std::string, std::uint32_t> element_ids_;
  std::vector<Segment> segments_;
  std::vector<Eigen::Vector3f> vertices_;   // per segment, its vertices
  std::vector<Eigen::Vector3i> triangles_;  // indices into vertices_
  std::size_t degenerate_ = 0;

  std::vector<std::uint32_t> stamp_, local_;  // per global vertex: segment + 1 and index in vertices_
  std::vector<std::uint32_t> table_;          // the current segment's positions (index + 1 from its first)
  std::size_t table_count_ = 0;
  std::vector<std::uint32_t> corners_, local_corners_;
};

Scene ObjParser::finish(std::size_t* dropped_degenerate) {
  release_memory(positions_);
  release_memory(stamp_);
  release_memory(local_);
  if (dropped_degenerate) *dropped_degenerate = degenerate_;
  if (triangles_.empty())
    throw InputError(path_, degenerate_ > 0 ? "mesh has only degenerate (zero-area) triangles" : "mesh has no triangles");

  const std::size_t elements = element_names_.size();
  std::vector<std::size_t> count(elements, 0);
  bool in_order = true;
  for (std::size_t s = 0; s < segments_.size(); ++s) {
    const std::size_t end = s + 1 < segments_.size() ? segments_[s + 1].first_triangle : triangles_.size();
    count[segments_[s].element] += end - segments_[s].first_triangle;
    if (s > 0 && segments_[s].element < segments_[s - 1].element) in_order = false;
  }
  for (std::size_t e = 0; e < elements; ++e)
    if (count[e] == 0) in_order = false;  // its vertices go, as the Assimp path added no such element

  Scene scene;
  if (in_order) {  // every name once, in file order: the arrays are the Scene's already
    scene.vertices = std::move(vertices_);
    scene.triangles = std::move(triangles_);
  } else {  // gather each element's segments, in order of first appearance
    std::vector<std::size_t> order(segments_.size());
    for (std::size_t s = 0; s < order.size(); ++s) order[s] = s;
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return segments_[a].element < segments_[b].element; });
    scene.triangles.reserve(triangles_.size());
    for (std::size_t s : order) {
      if (count[segments_[s].element] == 0) continue;
      const Segment& g = segments_[s];
      const std::size_t vend = s + 1 < segments_.size() ? segments_[s + 1].first_vertex : vertices_.size();
      const std::size_t tend = s + 1 < segments_.size() ? segments_[s + 1].first_triangle : triangles_.size();
      const int shift = static_cast<int>(scene.vertices.size()) - static_cast<int>(g.first_vertex);
      scene.vertices.insert(scene.vertices.end(), vertices_.begin() + g.first_vertex, vertices_.begin() + vend);
      for (std::size_t t = g.first_triangle; t < tend; ++t) scene.triangles.push_back(triangles_[t].array() + shift);
    }
    release_memory(vertices_);
    release_memory(triangles_);
  }
  scene.triangle_element.reserve(scene.triangles.size());
  for (std::size_t e = 0; e < elements; ++e) {
    if (count[e] == 0) continue;
    Element el;
    el.name = element_names_[e];
    el.first_triangle = static_cast<std::uint32_t>(scene.triangle_element.size());
    el.triangle_count = static_cast<std::uint32_t>(count[e]);
    scene.triangle_element.insert(scene.triangle_element.end(), count[e],
                                  static_cast<std::uint32_t>(scene.elements.size()));
    scene.elements.push_back(std::move(el));
  }
  update_element_stats(scene);
  return scene;
}

}  // namespace

Scene read_obj_mesh(const std::string& path, std::size_t* dropped_degenerate) {
  try {
    ObjParser parser(path, std::nullopt);
    parser.run(false);
    return parser.finish(dropped_degenerate);
  } catch (const ForwardReference&) {
  }
  // A face used a vertex defined further down (Assimp allows it): all positions first, then the faces.
  ObjParser vertices(path, std::nullopt);
  vertices.run(true);
  ObjParser parser(path, vertices.take_positions());
  parser.run(false);
  return parser.finish(dropped_degenerate);
}

}  // namespace ewis::detail
