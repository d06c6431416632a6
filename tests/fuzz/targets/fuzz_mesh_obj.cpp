// libFuzzer target: CAD loading through Assimp (load_scene) of a .obj file. load_scene takes a path, so each
// input is written to a RAM-backed temporary file. Malformed meshes must end in ewis::InputError.
#include <cstdint>

#include "fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static ewis_fuzz::TempFile file("obj");
  const std::string& path = file.write(data, size);
  try {
    std::size_t degenerate = 0;
    ewis_fuzz::check_scene(ewis::load_scene(path, &degenerate));
  } catch (const ewis::InputError&) {
  }
  return 0;
}
