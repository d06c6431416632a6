// libFuzzer target: CAD loading of a PLY mesh. load_scene reads PLY with its own strict reader (Assimp 5.2's
// hangs and crashes on broken PLY): fuzz that reader in memory, then every 16th input also through load_scene
// from a file, so the path-level code (degenerate triangles, element building) is covered too.
#include <strings.h>

#include <cstdint>
#include <cstdlib>
#include <string>

#include "fuzz_common.hpp"
#include "read_ply_mesh.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  try {
    const ewis::detail::PlyMesh mesh = ewis::detail::read_ply_mesh("fuzz.ply", bytes);
    for (const auto& t : mesh.triangles)
      for (int k = 0; k < 3; ++k)
        if (t[k] < 0 || std::size_t(t[k]) >= mesh.vertices.size()) ewis_fuzz::broken("PLY face index out of range");
  } catch (const ewis::InputError&) {
  }
  // Findings 3 and 4 (RESULTS.md): a magic of "Ply", "pLy", ... is not recognised by load_scene, so Assimp's PLY
  // importer gets the file and crashes or hangs. EWIS_FUZZ_SKIP_KNOWN=1 skips those inputs until that is fixed.
  static const bool skip_known = std::getenv("EWIS_FUZZ_SKIP_KNOWN") != nullptr;
  if (skip_known && size >= 3 && ::strncasecmp(bytes.c_str(), "ply", 3) == 0 && bytes.compare(0, 3, "ply") != 0 &&
      bytes.compare(0, 3, "PLY") != 0)
    return 0;
  static std::size_t runs = 0;
  if (runs++ % 16 == 0) {
    static ewis_fuzz::TempFile file("ply");
    try {
      ewis_fuzz::check_scene(ewis::load_scene(file.write(data, size)));
    } catch (const ewis::InputError&) {
    }
  }
  return 0;
}
