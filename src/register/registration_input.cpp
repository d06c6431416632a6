// Cloud or mesh, for `ewis register` (CONTRACT.md: S and T are files as for --scan or --cad).
#include "ewis/register/registration_input.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "ewis/core/error.hpp"
#include "ewis/scene/orient_faces.hpp"

namespace ewis {
namespace {

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

// A PLY header declares "element face N"; only the header (ASCII up to end_header, bounded) is read.
bool ply_has_faces(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot open file");
  std::string line;
  for (int lines = 0; lines < 10000 && std::getline(in, line); ++lines) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line == "end_header") break;
    std::istringstream ls(line);
    std::string word, name;
    long long count = 0;
    if (ls >> word >> name >> count && word == "element" && name == "face" && count > 0) return true;
  }
  return false;
}

}  // namespace

bool is_mesh_file(const std::string& path) {
  static const char* const mesh_ext[] = {".obj", ".stl", ".gltf", ".glb", ".off", ".3ds", ".dae", ".fbx",
                                         ".blend", ".x3d", ".dxf", ".lwo", ".ase", ".ifc", ".ac", ".3mf", ".amf",
                                         ".ms3d", ".x", ".smd", ".md2", ".md3", ".nff", ".raw", ".ter", ".hmp",
                                         ".cob", ".irr", ".q3d", ".q3s", ".ogex", ".mesh", ".b3d", ".ndo"};
  const std::string ext = lower_extension(path);
  if (ext == ".ply") return ply_has_faces(path);
  return std::find(std::begin(mesh_ext), std::end(mesh_ext), ext) != std::end(mesh_ext);
}

RegistrationInput read_registration_input(const std::string& path, LengthUnit cloud_unit) {
  RegistrationInput in;
  if (is_mesh_file(path)) {
    in.is_mesh = true;
    in.scene = load_scene(path);
    orient_faces_outward(in.scene);  // every element a target: which way its faces look is read (orient_faces.hpp)
  } else {
    in.cloud = read_cloud(path, cloud_unit).cloud;
    if (in.cloud.size() < 3) throw InputError(path, "fewer than 3 finite points to register");
  }
  return in;
}

}  // namespace ewis
