// read_obj_mesh against the Assimp 5.2 path (import_with_assimp) on the same OBJ files: same elements, order,
// triangles, vertex numbering and degenerate count; and errors with file and line on malformed input.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include "ewis/core/error.hpp"
#include "ewis/scene/scene.hpp"
#include "import_assimp.hpp"
#include "read_obj_mesh.hpp"
#include "test_tmp.hpp"

namespace {

namespace fs = std::filesystem;

std::string write_text(const std::string& name, const std::string& text) {
  const fs::path dir = ewis::test::own_tmp_dir("obj");
  const std::string p = (dir / name).string();
  std::ofstream(p, std::ios::binary) << text;
  return p;
}

// Vertices compared to a few float ulps: Assimp's fast_atof is not correctly rounded, std::from_chars is.
void expect_same_scene(const ewis::Scene& ours, const ewis::Scene& assimp, const std::string& what) {
  ASSERT_EQ(ours.elements.size(), assimp.elements.size()) << what;
  for (std::size_t e = 0; e < ours.elements.size(); ++e) {
    EXPECT_EQ(ours.elements[e].name, assimp.elements[e].name) << what;
    EXPECT_EQ(ours.elements[e].first_triangle, assimp.elements[e].first_triangle) << what;
    EXPECT_EQ(ours.elements[e].triangle_count, assimp.elements[e].triangle_count) << what;
    EXPECT_NEAR(ours.elements[e].area_mm2, assimp.elements[e].area_mm2, 1e-6 * assimp.elements[e].area_mm2) << what;
  }
  ASSERT_EQ(ours.vertices.size(), assimp.vertices.size()) << what;
  ASSERT_EQ(ours.triangles.size(), assimp.triangles.size()) << what;
  EXPECT_EQ(ours.triangle_element, assimp.triangle_element) << what;
  for (std::size_t t = 0; t < ours.triangles.size(); ++t)
    EXPECT_EQ(ours.triangles[t], assimp.triangles[t]) << what << " triangle " << t;
  for (std::size_t v = 0; v < ours.vertices.size(); ++v) {
    const Eigen::Vector3f& a = ours.vertices[v];
    const Eigen::Vector3f& b = assimp.vertices[v];
    if (!a.allFinite() || !b.allFinite()) continue;
    EXPECT_LE((a - b).norm(), 1e-6f * std::max(1.0f, b.norm())) << what << " vertex " << v;
  }
}

// Reads `text` both ways and compares; returns our Scene.
ewis::Scene both(const std::string& name, const std::string& text) {
  const std::string p = write_text(name + ".obj", text);
  std::size_t ours_dropped = 77, assimp_dropped = 99;
  ewis::Scene ours = ewis::detail::read_obj_mesh(p, &ours_dropped);
  const ewis::Scene assimp = ewis::detail::import_with_assimp(p, &assimp_dropped);
  expect_same_scene(ours, assimp, name);
  EXPECT_EQ(ours_dropped, assimp_dropped) << name;
  return ours;
}

const std::string kSix = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\n";

TEST(ReadObjMesh, ObjectsGroupsAndNamesAsAssimp) {
  // Faces before any o/g: Assimp's object "defaultobject" (the Assimp path named the element so).
  EXPECT_EQ(both("noobj", kSix + "f 1 2 3\nf 1 3 4\n").elements[0].name, "defaultobject");
  // `g a b` is one group "a b"; the rest of the line is the name, blanks after it kept.
  const ewis::Scene g = both("gmulti", kSix + "g a b\nf 1 2 3\ng  c  d  \nf 1 3 4\ng tab\t\nf 2 5 6\n");
  ASSERT_EQ(g.elements.size(), 3u);
  EXPECT_EQ(g.elements[0].name, "a b");
  EXPECT_EQ(g.elements[1].name, "c  d  ");
  EXPECT_EQ(g.elements[2].name, "tab\t");
  // `o a b` is object "a".
  EXPECT_EQ(both("omulti", kSix + "o a b\nf 1 2 3\n").elements[0].name, "a");
  // `g` without a name: ignored while no group was active, else an object "" (named after the file).
  const ewis::Scene gn = both("gnoname", kSix + "f 1 2 3\ng\nf 1 3 4\ng first\nf 2 5 6\ng\nf 1 2 4\n");
  ASSERT_EQ(gn.elements.size(), 3u);
  EXPECT_EQ(gn.elements[0].name, "defaultobject");
  EXPECT_EQ(gn.elements[0].triangle_count, 2u);
  EXPECT_EQ(gn.elements[2].name, "gnoname");
  // `o` without a name: ignored.
  EXPECT_EQ(both("ononame", kSix + "o first\nf 1 2 3\no\nf 1 3 4\n").elements.size(), 1u);
  // A group name seen again is merged into its element, in order of first appearance; the active group again
  // does nothing; `o` naming the current object continues its mesh.
  const ewis::Scene m = both("gsame", kSix + "g a\nf 1 2 3\ng b\nf 2 5 6\ng a\nf 1 3 4\ng a\nf 2 6 3\n"
                                             "o a\nf 1 2 4\no c\nf 2 5 3\no c\nf 1 5 6\n");
  ASSERT_EQ(m.elements.size(), 3u);
  EXPECT_EQ(m.elements[0].name, "a");
  EXPECT_EQ(m.elements[0].triangle_count, 4u);
  EXPECT_EQ(m.elements[1].triangle_count, 1u);
  EXPECT_EQ(m.elements[2].triangle_count, 2u);
  // Names Assimp reserves fall back to the mesh (material) name or the file stem.
  const ewis::Scene r = both("reserved", kSix + "o ROOT\nf 1 2 3\nusemtl red\nf 1 3 4\nusemtl blue\nf 2 5 6\n"
                                                "o <x>\nf 1 2 4\n");
  ASSERT_EQ(r.elements.size(), 2u);
  EXPECT_EQ(r.elements[0].name, "reserved");
  EXPECT_EQ(r.elements[1].name, "blue");
}

TEST(ReadObjMesh, MaterialsSplitMeshesButNotElements) {
  both("mtl", kSix + "mtllib none.mtl\no a\nf 1 2 3\nusemtl red\nf 1 3 4\nusemtl blue\nf 2 5 6\nf 1 2 3\n"
                     "usemtl red\nf 1 3 4\nusemtl red\nf 2 6 3\n");
  both("mtl2", kSix + "usemtl red\no a\nf 1 2 3\nusemtl blue\nf 1 3 4\no b\nusemtl blue\nf 2 5 6\nusemtl red\n"
                      "f 2 6 3\n");
  both("mtlfirst", kSix + "usemtl red\nf 1 2 3\nusemtl blue\nf 1 3 4\nusemtl  \nf 2 5 6\n");
  both("mtlgroup", kSix + "g G\nf 1 2 3\nusemtl red\nf 1 3 4\nusemtl blue\nf 1 3 4\ng H\nf 1 2 3\n");
}

TEST(ReadObjMesh, PolygonsAreTriangulatedAsAssimp) {
  const std::string poly = "v 0 0 0\nv 2 0 0\nv 3 1 0\nv 2 2 0\nv 0 2 0\nv -1 1 0\nv 1 -1 0\nv 4 3 1\n";
  both("polygons", poly + "o A\nf 1 2 3\nf 1 2 3 4\nf 1 2 3 4 5\nf 7 2 3 4 5 6\nf 7 2 3 4 5 6 1\n"
                          "f 2 3 4 5 6 1 7\no B\nf 8 1 2 3\n");
  // Concave quads start their fan at the concave corner; collinear corners give Assimp's zero-area triangles.
  both("quads", "v 0 0 0\nv 2 0 0\nv 0.5 0.5 0\nv 0 2 0\nv 1 0 0\nv 2 2 0\no A\nf 1 2 3 4\nf 2 3 4 1\n"
                "f 3 4 1 2\nf 4 1 2 3\nf 1 5 2 6\nf 1 1 2 4\nf 1 2 2 2\n");
  both("collinear", "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 2 2 0\nv 0 2 0\no A\nf 1 2 3 4 5\nf 2 3 4 5 1\n"
                    "f 3 4 5 1 2\nf 1 2 3 2 1\n");
}

TEST(ReadObjMesh, VerticesIndicesAndSyntaxAsAssimp) {
  // Lines and points add their vertices to the mesh (Assimp numbers them too), and are not triangles.
  both("lines", kSix + "o A\nl 5 6\nf 1 2 3\np 4\nl 1 2 3 4\nf 1 2\n");
  both("homogeneous", "v 0 0 0 2\nv 2 0 0 2\nv 0 2 0 0.5\nv 1 1 1 1 0 0\no A\nf 1 2 3\nf 1 2 4\n");
  both("crlf", "# comment\r\nv 0 0 0\r\nv 1 0 0\r\nv 1 1 0\r\ng grp\r\ns 1\r\nf 1 2 3\r\n\r\n");
  both("continued", "v 0 0 0\nv 1 0 \\\n0\nv 1 1 0\ng grp\nf 1 2\\\n 3\n");
  both("numbers", "v 0 0 0\nv 1,5 0 0\nv 1e-05 1E+2 -0\nv +1 -0.25 3.\nv 123.456787 -98765.4321 0.000123\n"
                  "g grp\nf 1 2 3\nf 1 2 4\nf 2 3 4 5\n");
  both("relative", kSix + "g grp\nf -6 -5 -4\nf -1 -2 -3\nv 5 5 5\nf -1 -2 -3\n");
  // (With vt/vn, Assimp keeps corners with different normals or uvs apart; here they agree.)
  both("slashes", kSix + "vt 0 0\nvn 0 0 1\ng grp\nf 1/1/1 2/1/1 3/1/1\nf 1//1 3//1 4//1\nf 2/1/1 5/1/1 6/1/1\n");
  both("comments", kSix + "# head\nvp 0.5\no A # trailing\nf 1 2 3\ncstype bspline\ndeg 3\nend\n"
                          "mg 1\nf 1 3 4\n");
  both("nan", "v 0 0 0\nv nan 0 0\nv 1 1 0\nv 0 1 0\nv inf 0 0\ng grp\nf 1 2 3\nf 1 3 4\nf 1 5 3\n");
  both("degenerate", "o thing\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nf 1 2 3\nf 1 2 4\nf 1 1 3\nv 0 0 0\n"
                     "f 1 5 2\nv -0 0 0\nf 6 2 3\n");
  // A face may use vertices defined further down.
  both("forward", "o A\nf 1 2 3\nf 4 2 1\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf -1 -2 -3\n");
}

TEST(ReadObjMesh, RandomScenesAsAssimp) {
  // Random soups: several objects and groups (some repeated), materials, shared vertices, polygons of 3-6
  // convex corners (on circles) and relative indices.
  std::mt19937 rng(11);
  for (int trial = 0; trial < 6; ++trial) {
    std::string text;
    int defined = 0;
    for (int block = 0; block < 12; ++block) {
      const int kind = int(rng() % 4);
      const std::string name = "part" + std::to_string(rng() % 5);
      if (kind == 0) text += "o " + name + "\n";
      if (kind == 1) text += "g " + name + "\n";
      if (kind == 2) text += "usemtl m" + std::to_string(rng() % 3) + "\n";
      const int n = 3 + int(rng() % 4);
      const double cx = rng() % 100, cy = rng() % 100, z = rng() % 7;
      for (int k = 0; k < n; ++k) {
        const double a = 6.283185307179586 * k / n;
        text += "v " + std::to_string(cx + 3 * std::cos(a)) + " " + std::to_string(cy + 3 * std::sin(a)) + " " +
                std::to_string(z) + "\n";
      }
      defined += n;
      text += "f";
      for (int k = 0; k < n; ++k) {
        text += ' ';  // (not " " + to_string: g++ 12 warns -Wrestrict on that inside char_traits)
        text += std::to_string(rng() % 2 ? defined - n + k + 1 : k - n);
      }
      text += "\n";
      if (defined > n) text += "f " + std::to_string(defined) + " " + std::to_string(defined - n) + " 1\n";
    }
    // A repeated `o` right after another object is not compared: Assimp 5.2 then adds to the other object.
    if (text.find("o ") != std::string::npos) {
      std::string fixed;
      std::string last_o;
      std::size_t pos = 0;
      while (pos < text.size()) {
        const std::size_t nl = text.find('\n', pos);
        std::string line = text.substr(pos, nl - pos);
        if (line.rfind("o ", 0) == 0) line = "g " + line.substr(2);
        fixed += line + "\n";
        pos = nl + 1;
      }
      text = fixed;
    }
    both("random" + std::to_string(trial), text);
  }
}

TEST(ReadObjMesh, WhereAssimpMisreadsWeReadAsWritten) {
  const auto read = [](const std::string& name, const std::string& text) {
    return ewis::detail::read_obj_mesh(write_text(name + ".obj", text), nullptr);
  };
  // `o a` again after `o b` adds to a (Assimp 5.2 added the faces to b's mesh).
  const ewis::Scene o = read("orepeat", kSix + "o a\nf 1 2 3\no b\nf 2 5 6\no a\nf 1 3 4\n");
  ASSERT_EQ(o.elements.size(), 2u);
  EXPECT_EQ(o.elements[0].name, "a");
  EXPECT_EQ(o.elements[0].triangle_count, 2u);
  EXPECT_EQ(o.elements[1].triangle_count, 1u);
  EXPECT_NEAR(o.elements[0].area_mm2, 1.0, 1e-9);
  // Indented lines, ".5", a UTF-8 BOM (Assimp skipped such vertex lines and then misnumbered the faces).
  const ewis::Scene s = read("lenient", "\xEF\xBB\xBFv 0 0 0\n  v .5 0 0\n\tv 0 .5 0\n  g grp\n  f 1 2 3\n");
  ASSERT_EQ(s.elements.size(), 1u);
  EXPECT_EQ(s.elements[0].name, "grp");
  EXPECT_NEAR(s.elements[0].area_mm2, 0.125, 1e-9);
  // A comment after a face's corners (Assimp 5.2 read '#' as an index and failed).
  EXPECT_EQ(read("facecomment", kSix + "f 1 2 3 # tail\n").triangle_count(), 1u);
}

// The message names the file and, for a problem in a line, the line.
void expect_error(const std::string& name, const std::string& text, const std::string& part) {
  const std::string p = write_text(name + ".obj", text);
  try {
    ewis::detail::read_obj_mesh(p, nullptr);
    ADD_FAILURE() << name << ": no error";
  } catch (const ewis::InputError& e) {
    EXPECT_EQ(e.file(), p) << name;
    EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << name << ": " << e.what();
  }
}

TEST(ReadObjMesh, MalformedInputThrowsWithFileAndLine) {
  const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  expect_error("index0", tri + "f 0 1 2\n", "line 4: face index 0");
  expect_error("range", tri + "o a\nf 1 2 9\n", "line 5: face index 9 but the file has 3 vertices");
  expect_error("huge", tri + "f 1 2 99999999999999999999999\n", "line 4: malformed face index");
  expect_error("huge2", tri + "f 1 2 4294967298\n", "line 4: face index 4294967298");
  expect_error("relative", tri + "f -4 1 2\n", "line 4: relative face index -4");
  expect_error("joined", tri + "f 1 2\\\n3\n", "face index 23");  // '\' joins without a blank, as in Assimp
  expect_error("noverts", "o a\nf 1 2 3\n", "face index 1 but the file has 0 vertices");
  expect_error("number", "v 0 0 0\nv 1 x 0\n", "line 2: malformed number 'x'");
  expect_error("number2", "v 0 0 0\nv 1 2e 0\n", "line 2: malformed number '2e'");
  expect_error("short", "v 0 0\n", "line 1: a vertex needs 3, 4 (x y z w) or 6 (x y z r g b) numbers, found 2");
  expect_error("five", "v 0 0 0 1 1\n", "found 5");
  expect_error("many", "v 0 0 0 1 1 1 1 1\n", "found more than 6");
  expect_error("w0", "v 0 0 0 0\n", "line 1: vertex with w = 0");
  expect_error("face", tri + "f 1 2 3x\n", "line 4: malformed face index '3x'");
  expect_error("truncated", tri + "f 1 2 3\nf 1 2 3\nv 0 0", "line 6: a vertex needs");
  expect_error("cut", tri + "f 1/", "mesh has no triangles");  // "1/" is vertex 1: a point
  expect_error("cut2", tri + "f 1 2 -", "line 4: malformed face index '-'");
  expect_error("points", tri, "mesh has no triangles");
  expect_error("lines", tri + "l 1 2 3\np 1\nf 1 2\n", "mesh has no triangles");
  expect_error("flat", tri + "f 1 1 2\n", "only degenerate");
  expect_error("empty", "", "mesh has no triangles");
  expect_error("comments", "# nothing\n\n\n", "mesh has no triangles");
  const std::string missing = write_text("missing.obj", "");
  fs::remove(missing);
  EXPECT_THROW(ewis::detail::read_obj_mesh(missing, nullptr), ewis::InputError);
}

TEST(ReadObjMesh, BinaryGarbageNeverCrashes) {
  std::mt19937 rng(5);
  const std::string alphabet = "vfolgp /-\\#\n\r\t0123456789.e,+ nai\x00\xff";
  for (int trial = 0; trial < 300; ++trial) {
    std::string text;
    const int len = int(rng() % 400);
    for (int i = 0; i < len; ++i)
      text += trial % 2 ? char(rng() % 256) : alphabet[rng() % alphabet.size()];
    if (trial % 3 == 0) text = "v 0 0 0\nv 1 0 0\nv 0 1 0\n" + text;
    const std::string p = write_text("garbage.obj", text);
    try {
      std::size_t dropped = 0;
      const ewis::Scene s = ewis::detail::read_obj_mesh(p, &dropped);
      for (const auto& t : s.triangles)
        for (int k = 0; k < 3; ++k) ASSERT_LT(std::size_t(t[k]), s.vertices.size());
    } catch (const ewis::InputError&) {
    }
  }
}

TEST(ReadObjMesh, LoadSceneRoutesObjByExtension) {
  const std::string text = kSix + "o part\nf 1 2 3\n";
  for (const std::string name : {"upper.OBJ", "lower.obj"}) {
    const ewis::Scene s = ewis::load_scene(write_text(name, text));
    ASSERT_EQ(s.elements.size(), 1u);
    EXPECT_EQ(s.elements[0].name, "part");
  }
  EXPECT_THROW(ewis::load_scene(write_text("empty.obj", "")), ewis::InputError);
}

}  // namespace
