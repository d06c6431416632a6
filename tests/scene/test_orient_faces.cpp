// Face winding made consistent and outward (orient_faces.hpp): closed shapes wound inside out or at random, split at
// hard edges, open sheets, and the simulator's mirrored frames.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <fstream>
#include <random>
#include <string>

#include "ewis/scene/orient_faces.hpp"
#include "ewis/scene/primitives.hpp"
#include "ewis/scene/scene.hpp"
#include "test_tmp.hpp"

namespace {

using Eigen::Vector3d;

// Divergence theorem over one element's triangles: positive for a closed, outward mesh.
double volume(const ewis::Scene& s, int element) {
  const ewis::Element& e = s.elements[std::size_t(element)];
  double v = 0;
  for (std::size_t t = e.first_triangle; t < e.first_triangle + e.triangle_count; ++t) {
    const Eigen::Vector3i& tri = s.triangles[t];
    v += s.vertices[std::size_t(tri[0])].cast<double>().dot(
             s.vertices[std::size_t(tri[1])].cast<double>().cross(s.vertices[std::size_t(tri[2])].cast<double>())) /
         6.0;
  }
  return v;
}

Vector3d normal(const ewis::Scene& s, std::size_t t) {
  const Eigen::Vector3i& tri = s.triangles[t];
  const Vector3d a = s.vertices[std::size_t(tri[0])].cast<double>();
  return (s.vertices[std::size_t(tri[1])].cast<double>() - a).cross(s.vertices[std::size_t(tri[2])].cast<double>() - a);
}

Vector3d centroid(const ewis::Scene& s, std::size_t t) {
  const Eigen::Vector3i& tri = s.triangles[t];
  return (s.vertices[std::size_t(tri[0])] + s.vertices[std::size_t(tri[1])] + s.vertices[std::size_t(tri[2])])
             .cast<double>() /
         3.0;
}

ewis::Scene scene_of(const std::string& name, const ewis::Mesh& m) {
  ewis::Scene s;
  ewis::add_element(s, name, m.vertices, m.triangles);
  return s;
}

void reverse(ewis::Mesh& m) {
  for (Eigen::Vector3i& t : m.triangles) std::swap(t[1], t[2]);
}

// Every triangle of a box around `centre` faces away from it.
void expect_box_outward(const ewis::Scene& s, const Vector3d& centre) {
  for (std::size_t t = 0; t < s.triangles.size(); ++t)
    EXPECT_GT(normal(s, t).dot(centroid(s, t) - centre), 0.0) << t;
}

TEST(OrientFaces, LeavesAnOutwardSceneAlone) {
  ewis::Scene s = scene_of("torus", ewis::make_torus(Vector3d(1, 2, 3), Vector3d(0, 1, 1), 30, 6));
  const ewis::Scene before = s;
  const ewis::OrientationRepair r = ewis::orient_faces_outward(s);
  EXPECT_EQ(r.flipped_triangles, 0u);
  EXPECT_EQ(r.components, 1u);
  EXPECT_EQ(r.open_components, 0u);
  EXPECT_EQ(s.triangles, before.triangles);
  EXPECT_EQ(s.elements[0].reoriented_triangles, 0u);
}

TEST(OrientFaces, TurnsAShapeWrittenInsideOutOutward) {
  // A torus (not convex: the volume's sign, not the direction from a centre, decides) inside out.
  ewis::Mesh m = ewis::make_torus(Vector3d(1, 2, 3), Vector3d(0, 1, 1), 30, 6);
  const double outward_volume = volume(scene_of("torus", m), 0);
  reverse(m);
  ewis::Scene s = scene_of("torus", m);
  EXPECT_LT(volume(s, 0), 0.0);
  const ewis::OrientationRepair r = ewis::orient_faces_outward(s);
  EXPECT_EQ(r.flipped_triangles, m.triangles.size());
  EXPECT_EQ(r.elements_changed, 1u);
  EXPECT_EQ(s.elements[0].reoriented_triangles, m.triangles.size());
  EXPECT_NEAR(volume(s, 0), outward_volume, 1e-9 * outward_volume);
  const double torus_volume = 2.0 * M_PI * M_PI * 30.0 * 6.0 * 6.0;  // (the 24-gon tube holds 1.2 % less)
  EXPECT_NEAR(outward_volume, torus_volume, 0.02 * torus_volume);
}

TEST(OrientFaces, WindsFacesTurnedAtRandomLikeTheirNeighbours) {
  ewis::Mesh m = ewis::make_box(Vector3d(-10, -4, -2), Vector3d(30, 4, 6));
  std::mt19937 rng(5);
  std::size_t turned = 0;
  for (Eigen::Vector3i& t : m.triangles)
    if (rng() % 2) {
      std::swap(t[1], t[2]);
      ++turned;
    }
  ASSERT_GT(turned, 0u);
  ewis::Scene s = scene_of("box", m);
  const ewis::OrientationRepair r = ewis::orient_faces_outward(s);
  EXPECT_EQ(r.flipped_triangles, turned);
  expect_box_outward(s, Vector3d(10, 0, 2));
}

TEST(OrientFaces, WeldsVerticesAnExporterSplitAtHardEdges) {
  // Each triangle with its own three vertices (as exporters write faces with their own normals), inside out: one
  // closed component once the corners are welded by position, not twelve open ones.
  const ewis::Mesh box = ewis::make_box(Vector3d(0, 0, 0), Vector3d(20, 10, 5));
  ewis::Mesh split;
  for (const Eigen::Vector3i& t : box.triangles) {
    const int base = int(split.vertices.size());
    for (int k : {0, 2, 1}) split.vertices.push_back(box.vertices[std::size_t(t[k])]);
    split.triangles.emplace_back(base, base + 1, base + 2);
  }
  ewis::Scene s = scene_of("box", split);
  const ewis::OrientationRepair r = ewis::orient_faces_outward(s);
  EXPECT_EQ(r.components, 1u);
  EXPECT_EQ(r.open_components, 0u);
  EXPECT_EQ(r.flipped_triangles, box.triangles.size());
  expect_box_outward(s, Vector3d(10, 5, 2.5));
}

TEST(OrientFaces, AnOpenSheetKeepsTheWindingMostOfItsAreaWasGiven) {
  // A strip of three triangles in the plane z = 0: the two large ones wound down (-z), the small one up. An open
  // sheet has no inside: it is made consistent with the larger part, not turned to face up.
  ewis::Mesh m;
  m.vertices = {{0, 0, 0}, {10, 0, 0}, {0, 10, 0}, {10, 10, 0}, {11, 10, 0}};
  m.triangles = {{0, 2, 1}, {1, 2, 3}, {1, 4, 3}};  // down, down (its neighbour's shared edge run the other way), up
  ewis::Scene s = scene_of("sheet", m);
  ASSERT_LT(normal(s, 0).z(), 0.0);
  ASSERT_LT(normal(s, 1).z(), 0.0);
  ASSERT_GT(normal(s, 2).z(), 0.0);
  const ewis::OrientationRepair r = ewis::orient_faces_outward(s);
  EXPECT_EQ(r.open_components, 1u);
  EXPECT_EQ(r.flipped_triangles, 1u);
  for (std::size_t t = 0; t < 3; ++t) EXPECT_LT(normal(s, t).z(), 0.0) << t;
  // ... and made two-sided: each triangle again, facing up, after the element's own.
  EXPECT_EQ(r.two_sided_triangles, 3u);
  ASSERT_EQ(s.triangles.size(), 6u);
  ASSERT_EQ(s.elements[0].triangle_count, 6u);
  for (std::size_t t = 3; t < 6; ++t) EXPECT_GT(normal(s, t).z(), 0.0) << t;
  EXPECT_NEAR(s.elements[0].area_mm2, 2.0 * (50.0 + 50.0 + 5.0), 1e-9);
  // A second pass (or the scene written and read again) finds both sides there: nothing changes.
  const ewis::Scene once = s;
  const ewis::OrientationRepair again = ewis::orient_faces_outward(s);
  EXPECT_EQ(again.flipped_triangles, 0u);
  EXPECT_EQ(again.two_sided_triangles, 0u);
  EXPECT_EQ(s.triangles, once.triangles);
}

TEST(OrientFaces, OnlyOpenPiecesGetASecondSideAndLaterElementsMoveAlong) {
  // An element of a closed box and an open sheet (the box's top face again, lifted), then a closed element: the sheet's
  // two triangles are added after the first element's own, and the second element's range moves by two.
  const ewis::Mesh box = ewis::make_box(Vector3d(0, 0, 0), Vector3d(10, 10, 10));
  ewis::Mesh first = box;
  const int base = int(first.vertices.size());
  for (const Eigen::Vector3f& v : {Eigen::Vector3f(0, 0, 20), Eigen::Vector3f(10, 0, 20), Eigen::Vector3f(0, 10, 20),
                                   Eigen::Vector3f(10, 10, 20)})
    first.vertices.push_back(v);
  first.triangles.emplace_back(base, base + 1, base + 3);
  first.triangles.emplace_back(base, base + 3, base + 2);
  ewis::Scene s = scene_of("first", first);
  ewis::add_element(s, "second", box.vertices, box.triangles);
  const ewis::OrientationRepair r = ewis::orient_faces_outward(s);
  EXPECT_EQ(r.components, 3u);
  EXPECT_EQ(r.open_components, 1u);
  EXPECT_EQ(r.two_sided_triangles, 2u);
  ASSERT_EQ(s.elements[0].triangle_count, 16u);
  EXPECT_EQ(s.elements[1].first_triangle, 16u);
  EXPECT_EQ(s.elements[1].triangle_count, 12u);
  ASSERT_EQ(s.triangle_element.size(), 28u);
  for (std::size_t t = 0; t < 28; ++t) EXPECT_EQ(s.triangle_element[t], t < 16 ? 0u : 1u) << t;
  EXPECT_NEAR(volume(s, 1), 1000.0, 1e-6);
  EXPECT_GT(normal(s, 12).z(), 0.0);
  EXPECT_LT(normal(s, 14).z(), 0.0);
}

TEST(OrientFaces, SolidsTouchingAlongAnEdgeStayClosed) {
  // One element, as a structure is often written: a 6 mm plate and a wall standing on it along its edge, with the
  // corners they share written once (the edges there are used by four triangles). Each box is closed on its own:
  // outward, nothing two-sided (the plate's underside, added facing up, held a registration 6 mm low).
  for (const bool inside_out : {false, true}) {
    const ewis::Mesh plate = ewis::make_box(Vector3d(-300, -240, -6), Vector3d(300, 240, 0));
    ewis::Mesh wall = ewis::make_box(Vector3d(-300, -240, 0), Vector3d(300, -226, 40));
    if (inside_out) reverse(wall);
    ewis::Mesh both = plate;
    for (const Eigen::Vector3i& t : wall.triangles)
      both.triangles.push_back(t + Eigen::Vector3i::Constant(int(both.vertices.size())));
    both.vertices.insert(both.vertices.end(), wall.vertices.begin(), wall.vertices.end());
    // the wall's corners at z = 0 are the plate's: one vertex each
    for (Eigen::Vector3i& t : both.triangles)
      for (int k = 0; k < 3; ++k)
        for (int v = 0; v < int(plate.vertices.size()); ++v)
          if (t[k] >= int(plate.vertices.size()) && both.vertices[std::size_t(t[k])] == plate.vertices[std::size_t(v)]) t[k] = v;
    ewis::Scene s = scene_of("structure", both);
    const ewis::OrientationRepair r = ewis::orient_faces_outward(s);
    EXPECT_EQ(r.components, 2u) << inside_out;
    EXPECT_EQ(r.open_components, 0u) << inside_out;
    EXPECT_EQ(r.two_sided_triangles, 0u) << inside_out;
    EXPECT_EQ(r.flipped_triangles, inside_out ? wall.triangles.size() : 0u);
    ASSERT_EQ(s.triangles.size(), 24u);
    for (std::size_t t = 0; t < 24; ++t)
      EXPECT_GT(normal(s, t).dot(centroid(s, t) - (t < 12 ? Vector3d(0, 0, -3) : Vector3d(0, -233, 20))), 0.0) << t;
  }
}

TEST(OrientFaces, EachElementAndEachPieceOnItsOwn) {
  // One element of two boxes (one inside out), and an outward element after it: only the wrong box turns.
  ewis::Mesh a = ewis::make_box(Vector3d(0, 0, 0), Vector3d(10, 10, 10));
  ewis::Mesh b = ewis::make_box(Vector3d(20, 0, 0), Vector3d(30, 10, 10));
  reverse(b);
  ewis::Mesh both = a;
  for (const Eigen::Vector3i& t : b.triangles)
    both.triangles.push_back(t + Eigen::Vector3i::Constant(int(both.vertices.size())));
  both.vertices.insert(both.vertices.end(), b.vertices.begin(), b.vertices.end());
  ewis::Scene s = scene_of("pair", both);
  const ewis::Mesh c = ewis::make_box(Vector3d(0, 20, 0), Vector3d(10, 30, 10));
  ewis::add_element(s, "third", c.vertices, c.triangles);
  const ewis::OrientationRepair r = ewis::orient_faces_outward(s);
  EXPECT_EQ(r.components, 3u);
  EXPECT_EQ(r.flipped_triangles, b.triangles.size());
  EXPECT_EQ(s.elements[0].reoriented_triangles, b.triangles.size());
  EXPECT_EQ(s.elements[1].reoriented_triangles, 0u);
  EXPECT_NEAR(volume(s, 0), 2000.0, 1e-6);
  EXPECT_NEAR(volume(s, 1), 1000.0, 1e-6);
}

TEST(OrientFaces, OnlyTheSelectedElements) {
  ewis::Mesh m = ewis::make_box(Vector3d(0, 0, 0), Vector3d(10, 10, 10));
  reverse(m);
  ewis::Scene s = scene_of("rigid", m);
  ewis::add_element(s, "cable", m.vertices, m.triangles);
  const ewis::OrientationRepair r = ewis::orient_faces_outward(s, {true, false});
  EXPECT_EQ(r.flipped_triangles, 12u);
  EXPECT_NEAR(volume(s, 0), 1000.0, 1e-6);
  EXPECT_NEAR(volume(s, 1), -1000.0, 1e-6);
  EXPECT_EQ(s.elements[1].reoriented_triangles, 0u);
}

TEST(OrientFaces, AMirroredFrameKeepsAMeshOutward) {
  // The simulator's L brackets stand in frames (along, side, up) whose side may point either way.
  ewis::Mesh m = ewis::make_box(Vector3d(-5, -2, -1), Vector3d(5, 2, 1));
  Eigen::Matrix3d mirror;
  mirror << 0, 1, 0, 1, 0, 0, 0, 0, 1;  // x and y swapped: determinant -1
  ewis::transform_mesh(m, mirror, Vector3d(3, 4, 5));
  ewis::Scene s = scene_of("bracket", m);
  EXPECT_NEAR(volume(s, 0), 80.0, 1e-6);
  EXPECT_EQ(ewis::orient_faces_outward(s).flipped_triangles, 0u);
}

TEST(OrientFaces, AFileWrittenInsideOutReadAndTurned) {
  // A unit cube written clockwise (inward), as some exporters do, and a second object outward.
  const std::string path = (ewis::test::own_tmp_dir("scene") / "inside_out.obj").string();
  {
    std::ofstream f(path);
    f << "o cube\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
         "f 1 2 3\nf 1 3 4\nf 5 8 7\nf 5 7 6\nf 1 5 6\nf 1 6 2\nf 2 6 7\nf 2 7 3\nf 3 7 8\nf 3 8 4\nf 4 8 5\nf 4 5 1\n"
         "o tetra\nv 5 0 0\nv 6 0 0\nv 5 1 0\nv 5 0 1\nf 9 11 10\nf 9 10 12\nf 10 11 12\nf 9 12 11\n";
  }
  ewis::Scene s = ewis::load_scene(path);
  ASSERT_EQ(s.elements.size(), 2u);
  EXPECT_LT(volume(s, 0), 0.0);  // read as written
  const ewis::OrientationRepair r = ewis::orient_faces_outward(s);
  EXPECT_EQ(r.flipped_triangles, 12u);
  EXPECT_EQ(s.elements[0].reoriented_triangles, 12u);
  EXPECT_EQ(s.elements[1].reoriented_triangles, 0u);
  EXPECT_NEAR(volume(s, 0), 1.0, 1e-6);
  EXPECT_GT(volume(s, 1), 0.0);
}

}  // namespace
