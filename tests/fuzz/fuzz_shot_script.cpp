// libFuzzer target: the shot-script reader and its first uses (tests/fuzz/exercise.h). Any input must pass
// or throw InputError; anything else is a finding.
#include "engine/check.h"
#include "tests/fuzz/exercise.h"
#include "tests/fuzz/fuzz_input_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    candela::fuzz::exercise_shot_script(candela::fuzz::write_input_file(data, size, "json"));
  } catch (const candela::InputError&) {
    // a clean refusal
  }
  return 0;
}
