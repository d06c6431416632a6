// A simulated CAD scene written as OBJ (what `ewis simulate` writes as scene.obj) reads back the same through
// our OBJ reader and through the Assimp path: names, order, triangle counts, areas, vertices.
#include <gtest/gtest.h>

#include <filesystem>

#include "ewis/scene/scene.hpp"
#include "ewis/sim/scene_generator.hpp"
#include "import_assimp.hpp"
#include "read_obj_mesh.hpp"
#include "test_tmp.hpp"

namespace {

TEST(SceneObjReaders, SimulatedSceneReadsTheSameBothWays) {
  const std::filesystem::path dir = ewis::test::own_tmp_dir("sim_obj");
  for (std::uint64_t seed : {7u, 12u}) {
    ewis::sim::SceneParams params;
    params.seed = seed;
    params.defect = seed == 7 ? ewis::sim::DefectKind::Clearance : ewis::sim::DefectKind::None;
    const ewis::Scene cad = ewis::sim::nominal_scene(ewis::sim::generate_scene(params));
    const std::string path = (dir / ("scene" + std::to_string(seed) + ".obj")).string();
    ewis::write_obj(cad, path);

    std::size_t ours_dropped = 1, assimp_dropped = 2;
    const ewis::Scene ours = ewis::detail::read_obj_mesh(path, &ours_dropped);
    const ewis::Scene assimp = ewis::detail::import_with_assimp(path, &assimp_dropped);
    EXPECT_EQ(ours_dropped, assimp_dropped);
    ASSERT_EQ(ours.elements.size(), assimp.elements.size());
    ASSERT_EQ(ours.elements.size(), cad.elements.size());
    for (std::size_t e = 0; e < ours.elements.size(); ++e) {
      const ewis::Element& a = ours.elements[e];
      const ewis::Element& b = assimp.elements[e];
      EXPECT_EQ(a.name, b.name);
      EXPECT_EQ(a.first_triangle, b.first_triangle);
      EXPECT_EQ(a.triangle_count, b.triangle_count);
      EXPECT_NEAR(a.area_mm2, b.area_mm2, 1e-6 * b.area_mm2) << a.name;
      // write_obj writes the shortest text that reads back to each float: ours reads back every bit.
      EXPECT_NEAR(a.area_mm2, cad.elements[e].area_mm2, 1e-12 * cad.elements[e].area_mm2) << a.name;
    }
    ASSERT_EQ(ours.vertices.size(), assimp.vertices.size());
    EXPECT_EQ(ours.triangles, assimp.triangles);
    EXPECT_EQ(ours.triangle_element, assimp.triangle_element);
    std::size_t differ = 0;
    for (std::size_t v = 0; v < ours.vertices.size(); ++v) {
      const float scale = std::max(1.0f, assimp.vertices[v].norm());
      EXPECT_LE((ours.vertices[v] - assimp.vertices[v]).norm(), 1e-6f * scale);
      differ += ours.vertices[v] != assimp.vertices[v];
    }
    RecordProperty("vertices_differing_in_last_bits_seed" + std::to_string(seed), int(differ));
  }
}

}  // namespace
