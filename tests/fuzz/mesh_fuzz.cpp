// libFuzzer target: one mesh reader (GEOBRUSH_FUZZ_FORMAT) on arbitrary bytes. Every input must
// give a mesh or a MeshError; anything else (a crash, a sanitizer report, another exception, a
// hang or unbounded memory) is a finding.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "geobrush/mesh_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  try {
    geobrush::readMeshBytes(bytes, geobrush::MeshFormat::GEOBRUSH_FUZZ_FORMAT, "fuzz");
  } catch (const geobrush::MeshError&) {
  }
  try {
    geobrush::readMeshBytes(bytes, geobrush::MeshFormat::GEOBRUSH_FUZZ_FORMAT, "fuzz",
                            {.repairNonManifold = true});
  } catch (const geobrush::MeshError&) {
  }
  return 0;
}
