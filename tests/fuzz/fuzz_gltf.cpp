// libFuzzer target: the glTF/GLB loader. Any input must load or throw InputError; a crash, a sanitizer
// report, a CHECK failure or any other exception is a finding. Bytes starting with the GLB magic are
// loaded as .glb, the rest as .gltf.
#include <cstring>

#include "engine/check.h"
#include "tests/fuzz/exercise.h"
#include "tests/fuzz/fuzz_input_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  bool glb = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
  try {
    candela::fuzz::exercise_gltf(candela::fuzz::write_input_file(data, size, glb ? "glb" : "gltf"));
  } catch (const candela::InputError&) {
    // a clean refusal
  }
  return 0;
}
