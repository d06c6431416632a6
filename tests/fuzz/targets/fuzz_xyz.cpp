// libFuzzer target: the XYZ point-cloud reader on the input bytes (in memory, as read_cloud hands them over).
// Anything malformed must end in ewis::InputError; a result must satisfy check_cloud.
#include <cstdint>
#include <string_view>

#include "fuzz_common.hpp"
#include "readers.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  try {
    // Millimetres, then metres: the unit scale must not turn finite input into inf without dropping it.
    ewis_fuzz::check_cloud(ewis::io_detail::read_xyz("fuzz.xyz", bytes, 1.0f));
    ewis_fuzz::check_cloud(ewis::io_detail::read_xyz("fuzz.xyz", bytes, 1000.0f));
  } catch (const ewis::InputError&) {
  }
  return 0;
}
