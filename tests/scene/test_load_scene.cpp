// load_scene / write_obj against files with known element names, triangle counts and areas.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "ewis/core/error.hpp"
#include "ewis/scene/primitives.hpp"
#include "ewis/scene/scene.hpp"
#include "test_tmp.hpp"

namespace {

namespace fs = std::filesystem;

std::string tmp_path(const std::string& name) {
  const fs::path dir = ewis::test::own_tmp_dir("scene");
  return (dir / name).string();
}

std::string write_text(const std::string& name, const std::string& text) {
  const std::string p = tmp_path(name);
  std::ofstream(p, std::ios::binary) << text;
  return p;
}

const ewis::Element& element(const ewis::Scene& s, const std::string& name) {
  const int i = s.find(name);
  EXPECT_GE(i, 0) << "no element " << name;
  static ewis::Element none;
  return i >= 0 ? s.elements[i] : none;
}

void expect_contiguous(const ewis::Scene& s) {
  ASSERT_EQ(s.triangle_element.size(), s.triangles.size());
  std::uint32_t next = 0;
  for (std::size_t e = 0; e < s.elements.size(); ++e) {
    EXPECT_EQ(s.elements[e].first_triangle, next);
    for (std::uint32_t t = 0; t < s.elements[e].triangle_count; ++t)
      EXPECT_EQ(s.triangle_element[s.elements[e].first_triangle + t], e);
    next += s.elements[e].triangle_count;
  }
  EXPECT_EQ(next, s.triangles.size());
}

// Two unit squares side by side (4 triangles) in object A split by usemtl; object B a 2x3 rectangle;
// a group `g C` with a single right triangle. (A repeated `o NAME` after another object is not tested:
// Assimp 5.2 then keeps adding faces to the previous object's mesh.)
const char* kObj = R"(# test
mtllib none.mtl
o cable_A
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 2 0 0
v 2 1 0
usemtl red
f 1 2 3
f 1 3 4
usemtl blue
f 2 5 6 3
o bracket_B
v 0 0 5
v 2 0 5
v 2 3 5
v 0 3 5
f 7 8 9 10
g clamp_C
v 0 0 9
v 4 0 9
v 0 4 9
f 11 12 13
)";

TEST(LoadScene, ObjObjectsGroupsAndMaterials) {
  const std::string p = write_text("objects.obj", kObj);
  std::size_t dropped = 99;
  const ewis::Scene s = ewis::load_scene(p, &dropped);
  EXPECT_EQ(dropped, 0u);
  ASSERT_EQ(s.elements.size(), 3u);
  expect_contiguous(s);
  EXPECT_EQ(s.elements[0].name, "cable_A");
  EXPECT_EQ(element(s, "cable_A").triangle_count, 4u);
  EXPECT_NEAR(element(s, "cable_A").area_mm2, 2.0, 1e-6);
  EXPECT_EQ(element(s, "bracket_B").triangle_count, 2u);
  EXPECT_NEAR(element(s, "bracket_B").area_mm2, 6.0, 1e-6);
  EXPECT_EQ(element(s, "clamp_C").triangle_count, 1u);
  EXPECT_NEAR(element(s, "clamp_C").area_mm2, 8.0, 1e-6);
  const auto& b = element(s, "bracket_B");
  EXPECT_NEAR((b.center_of_mass - Eigen::Vector3d(1, 1.5, 5)).norm(), 0, 1e-6);
  EXPECT_NEAR((b.bounds_min - Eigen::Vector3d(0, 0, 5)).norm(), 0, 1e-6);
  EXPECT_NEAR((b.bounds_max - Eigen::Vector3d(2, 3, 5)).norm(), 0, 1e-6);
}

TEST(LoadScene, ObjFacesBeforeAnyObjectAreOneElement) {
  const std::string p = write_text("noname.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  const ewis::Scene s = ewis::load_scene(p);
  ASSERT_EQ(s.elements.size(), 1u);
  EXPECT_EQ(s.elements[0].triangle_count, 1u);
  EXPECT_FALSE(s.elements[0].name.empty());
}

TEST(LoadScene, DegenerateTrianglesAreDroppedAndCounted) {
  const std::string p = write_text("degenerate.obj",
                                   "o thing\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\n"
                                   "f 1 2 3\nf 1 2 4\nf 1 1 3\n");
  std::size_t dropped = 0;
  const ewis::Scene s = ewis::load_scene(p, &dropped);
  EXPECT_EQ(s.triangle_count(), 1u);
  EXPECT_EQ(dropped, 2u);
}

TEST(LoadScene, AsciiStlWithTwoSolids) {
  const std::string p = write_text("two.stl",
                                   "solid first_part\n"
                                   " facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 2 0 0\n"
                                   "   vertex 0 2 0\n  endloop\n endfacet\n"
                                   "endsolid first_part\n"
                                   "solid second_part\n"
                                   " facet normal 0 0 1\n  outer loop\n   vertex 0 0 1\n   vertex 3 0 1\n"
                                   "   vertex 0 3 1\n  endloop\n endfacet\n"
                                   " facet normal 0 0 1\n  outer loop\n   vertex 3 0 1\n   vertex 3 3 1\n"
                                   "   vertex 0 3 1\n  endloop\n endfacet\n"
                                   "endsolid second_part\n");
  const ewis::Scene s = ewis::load_scene(p);
  ASSERT_EQ(s.elements.size(), 2u);
  expect_contiguous(s);
  EXPECT_EQ(element(s, "first_part").triangle_count, 1u);
  EXPECT_NEAR(element(s, "first_part").area_mm2, 2.0, 1e-6);
  EXPECT_EQ(element(s, "second_part").triangle_count, 2u);
  EXPECT_NEAR(element(s, "second_part").area_mm2, 9.0, 1e-6);
}

std::string binary_stl(const ewis::Mesh& m) {
  std::string out(80, ' ');
  const std::uint32_t n = static_cast<std::uint32_t>(m.triangles.size());
  out.append(reinterpret_cast<const char*>(&n), 4);
  for (const auto& t : m.triangles) {
    const float normal[3] = {0, 0, 0};
    out.append(reinterpret_cast<const char*>(normal), 12);
    for (int k = 0; k < 3; ++k) out.append(reinterpret_cast<const char*>(m.vertices[t[k]].data()), 12);
    out.append(2, '\0');
  }
  return out;
}

TEST(LoadScene, BinaryStlIsOneElementNamedAfterTheFile) {
  const ewis::Mesh box = ewis::make_box(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(10, 20, 30));
  const std::string p = write_text("bracket.stl", binary_stl(box));
  const ewis::Scene s = ewis::load_scene(p);
  ASSERT_EQ(s.elements.size(), 1u);
  EXPECT_EQ(s.elements[0].name, "bracket");
  EXPECT_EQ(s.elements[0].triangle_count, 12u);
  EXPECT_NEAR(s.elements[0].area_mm2, 2 * (200 + 600 + 300), 1e-3);
}

TEST(LoadScene, PlyIsOneElementNamedAfterTheFile) {
  const std::string p = write_text("plate.ply",
                                   "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                                   "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                   "end_header\n0 0 0\n4 0 0\n4 5 0\n0 5 0\n4 0 1 2 3\n");
  const ewis::Scene s = ewis::load_scene(p);
  ASSERT_EQ(s.elements.size(), 1u);
  EXPECT_EQ(s.elements[0].name, "plate");
  EXPECT_EQ(s.elements[0].triangle_count, 2u);
  EXPECT_NEAR(s.elements[0].area_mm2, 20.0, 1e-6);
}

std::string ply_header(const std::string& format, int vertices, int faces) {
  return "ply\nformat " + format + " 1.0\ncomment made by a test\nelement vertex " + std::to_string(vertices) +
         "\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\nelement face " +
         std::to_string(faces) + "\nproperty list uchar int vertex_indices\nelement edge 1\n"
         "property int vertex1\nproperty int vertex2\nend_header\n";
}

template <class T>
void put(std::string& out, T v, bool big) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  if (big) std::reverse(b, b + sizeof(T));
  out.append(b, sizeof(T));
}

std::string binary_ply(bool big) {
  std::string s = ply_header(big ? "binary_big_endian" : "binary_little_endian", 4, 1);
  const float v[4][3] = {{0, 0, 0}, {4, 0, 0}, {4, 5, 0}, {0, 5, 0}};
  for (const auto& p : v) {
    for (float x : p) put(s, x, big);
    s += char(200);
  }
  s += char(4);
  for (int i : {0, 1, 2, 3}) put(s, std::int32_t(i), big);
  put(s, std::int32_t(0), big);
  put(s, std::int32_t(1), big);
  return s;
}

TEST(LoadScene, BinaryPlyBothEndians) {
  for (bool big : {false, true}) {
    const ewis::Scene s = ewis::load_scene(write_text(big ? "big.ply" : "little.ply", binary_ply(big)));
    ASSERT_EQ(s.elements.size(), 1u);
    EXPECT_EQ(s.elements[0].name, big ? "big" : "little");
    EXPECT_EQ(s.elements[0].triangle_count, 2u);
    EXPECT_NEAR(s.elements[0].area_mm2, 20.0, 1e-6);
  }
}

TEST(LoadScene, TruncatedOrBrokenPlyThrowsWithoutHanging) {
  const std::string good = binary_ply(false);
  for (std::size_t cut : {std::size_t(3), std::size_t(20), std::size_t(60), good.size() - 30, good.size() - 1}) {
    EXPECT_THROW(ewis::load_scene(write_text("cut.ply", good.substr(0, cut))), ewis::InputError) << cut;
  }
  EXPECT_THROW(ewis::load_scene(write_text("t1.ply", "ply\nformat ascii 1.0\nelement vertex 4\n")),
               ewis::InputError);
  EXPECT_THROW(ewis::load_scene(write_text("t2.ply", ply_header("ascii", 4, 1) + "0 0 0 1\n4 0 0 1\n")),
               ewis::InputError);
  EXPECT_THROW(ewis::load_scene(write_text("t3.ply", ply_header("ascii", 3, 1) + "0 0 0 1\n4 0 0 1\n4 5 0 1\n"
                                                                                   "3 0 1 7\n2 0 1\n")),
               ewis::InputError);  // face index out of range
  EXPECT_THROW(ewis::load_scene(write_text("t4.ply", ply_header("ascii", 1000000000, 1) + "0 0 0 1\n")),
               ewis::InputError);  // count larger than the file
  EXPECT_THROW(ewis::load_scene(write_text("t5.ply", ply_header("ascii", 3, 0) + "0 0 0 1\n4 0 0 1\n4 5 0 1\n")),
               ewis::InputError);  // no faces: a point cloud, not a mesh
}

TEST(LoadScene, RealRangeScanPlyIsRejectedQuickly) {
  const std::string p = std::string(EWIS_REALDATA_DIR) + "/stanford_bunny/bun000.ply";
  if (!fs::exists(p)) GTEST_SKIP() << "real data absent: " << p;
  // A range scan (vertex + range_grid elements, no faces): a clear error, not a hang or a crash.
  EXPECT_THROW(ewis::load_scene(p), ewis::InputError);
}

std::string base64(const std::string& in) {
  static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  std::size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const std::uint32_t v = (std::uint8_t(in[i]) << 16) | (std::uint8_t(in[i + 1]) << 8) | std::uint8_t(in[i + 2]);
    out += t[v >> 18];
    out += t[(v >> 12) & 63];
    out += t[(v >> 6) & 63];
    out += t[v & 63];
  }
  if (i + 1 == in.size()) {
    const std::uint32_t v = std::uint8_t(in[i]) << 16;
    out += t[v >> 18];
    out += t[(v >> 12) & 63];
    out += "==";
  } else if (i + 2 == in.size()) {
    const std::uint32_t v = (std::uint8_t(in[i]) << 16) | (std::uint8_t(in[i + 1]) << 8);
    out += t[v >> 18];
    out += t[(v >> 12) & 63];
    out += t[(v >> 6) & 63];
    out += '=';
  }
  return out;
}

TEST(LoadScene, GltfNodeNamesAndTransforms) {
  // One triangle mesh used by two nodes: "left" translated by -10 in x, "right" scaled 2x and moved +10.
  const float pos[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const std::uint16_t idx[4] = {0, 1, 2, 0};  // padded to 4-byte multiple
  std::string buf(reinterpret_cast<const char*>(pos), sizeof(pos));
  buf.append(reinterpret_cast<const char*>(idx), sizeof(idx));
  const std::string json = R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0,1]}],
 "nodes":[{"name":"left","mesh":0,"translation":[-10,0,0]},
          {"name":"right","mesh":0,"translation":[10,0,0],"scale":[2,2,2]}],
 "meshes":[{"name":"tri","primitives":[{"attributes":{"POSITION":0},"indices":1}]}],
 "buffers":[{"byteLength":44,"uri":"data:application/octet-stream;base64,)" +
                           base64(buf) + R"("}],
 "bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":6}],
 "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},
              {"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"}]})";
  const std::string p = write_text("nodes.gltf", json);
  const ewis::Scene s = ewis::load_scene(p);
  ASSERT_EQ(s.elements.size(), 2u);
  EXPECT_NEAR(element(s, "left").area_mm2, 0.5, 1e-6);
  EXPECT_NEAR(element(s, "right").area_mm2, 2.0, 1e-6);
  EXPECT_NEAR(element(s, "left").bounds_min.x(), -10, 1e-6);
  EXPECT_NEAR(element(s, "right").bounds_max.x(), 12, 1e-6);
}

TEST(LoadScene, BadFilesThrowInputError) {
  EXPECT_THROW(ewis::load_scene(tmp_path("does_not_exist.obj")), ewis::InputError);
  EXPECT_THROW(ewis::load_scene(fs::path(tmp_path("x")).parent_path().string()), ewis::InputError);
  EXPECT_THROW(ewis::load_scene(write_text("empty.obj", "")), ewis::InputError);
  EXPECT_THROW(ewis::load_scene(write_text("garbage.stl", std::string("\x01\x02garbage\xff\xfe", 11))),
               ewis::InputError);
  EXPECT_THROW(ewis::load_scene(write_text("garbage.xyzq", "hello world\n")), ewis::InputError);
  EXPECT_THROW(ewis::load_scene(write_text("points.obj", "v 0 0 0\nv 1 0 0\n")), ewis::InputError);
  try {
    ewis::load_scene(tmp_path("does_not_exist.obj"));
  } catch (const ewis::InputError& e) {
    EXPECT_EQ(e.file(), tmp_path("does_not_exist.obj"));
  }
}

TEST(WriteObj, RoundTripKeepsNamesCountsAndAreas) {
  ewis::Scene s;
  const ewis::Mesh sphere = ewis::make_sphere(Eigen::Vector3d(1, 2, 3), 7.5, 24, 12);
  const ewis::Mesh tube = ewis::make_tube({Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0, 0, 50),
                                           Eigen::Vector3d(10, 0, 80)}, 2.5, 12);
  const ewis::Mesh box = ewis::make_box(Eigen::Vector3d(-5, -5, -5), Eigen::Vector3d(5, 0, 1));
  ewis::add_element(s, "sphere 1", sphere.vertices, sphere.triangles);
  ewis::add_element(s, "cable_W12", tube.vertices, tube.triangles);
  ewis::add_element(s, "bracket", box.vertices, box.triangles);
  ewis::add_element(s, "sphere 1", box.vertices, box.triangles);  // extends the first element
  expect_contiguous(s);
  EXPECT_EQ(s.elements[0].triangle_count, sphere.triangles.size() + 12);

  const std::string p = tmp_path("roundtrip.obj");
  ewis::write_obj(s, p);
  const ewis::Scene r = ewis::load_scene(p);
  ASSERT_EQ(r.elements.size(), s.elements.size());
  expect_contiguous(r);
  for (std::size_t i = 0; i < s.elements.size(); ++i) {
    // Blanks become '_' (Assimp's OBJ reader ends names at a blank).
    EXPECT_EQ(r.elements[i].name, i == 0 ? std::string("sphere_1") : s.elements[i].name);
    EXPECT_EQ(r.elements[i].triangle_count, s.elements[i].triangle_count);
    EXPECT_NEAR(r.elements[i].area_mm2, s.elements[i].area_mm2, 1e-9 * s.elements[i].area_mm2);
  }
  // No temporary left behind.
  int files = 0;
  for (const auto& f : fs::directory_iterator(fs::path(p).parent_path()))
    if (f.path().filename().string().rfind("roundtrip.obj", 0) == 0) ++files;
  EXPECT_EQ(files, 1);
}

}  // namespace
