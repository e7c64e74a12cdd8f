// Hostile input never crashes: JSON nested deeper than the bound is refused before any parser recurses
// (the pre-scan itself, and 100,000-level .gltf, .glb and shot-script files generated here at run time;
// the small fixtures in tests/data are tested with the other broken files).
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <string>

#include "apps/shot_script.h"
#include "engine/check.h"
#include "engine/gltf_loader.h"
#include "engine/input_limits.h"

namespace candela {
namespace {

std::string nested_arrays(int levels) { return std::string(size_t(levels), '[') + std::string(size_t(levels), ']'); }

// The message of the InputError that `fn` throws, "" when it throws none.
template <class Fn>
std::string input_error(Fn&& fn) {
  try {
    fn();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

std::string scan_error(const std::string& text) {
  return input_error([&] { check_json_nesting(text, "f.json"); });
}

const std::string kTooDeep = "JSON nested deeper than " + std::to_string(kMaxJsonDepth) + " levels";

TEST(JsonNesting, AcceptsTheLimitAndRefusesOneLevelMore) {
  EXPECT_EQ(scan_error(nested_arrays(kMaxJsonDepth)), "");
  EXPECT_EQ(scan_error(nested_arrays(kMaxJsonDepth + 1)), "f.json: " + kTooDeep);
}

TEST(JsonNesting, CountsObjectsAndArraysTogether) {
  std::string mixed;
  for (int i = 0; i <= kMaxJsonDepth; ++i) mixed += i % 2 ? "[" : "{\"k\":";
  EXPECT_NE(scan_error(mixed), "");
  // Siblings do not add up: many shallow values are fine.
  std::string wide = "[";
  for (int i = 0; i < 10000; ++i) wide += "[[]],";
  EXPECT_EQ(scan_error(wide + "[]]"), "");
}

TEST(JsonNesting, IgnoresBracketsInsideStringsAndHonoursEscapes) {
  // An escaped quote does not end the string, so the brackets after it are still inside it.
  EXPECT_EQ(scan_error("{\"k\": \"" + std::string(1000, '[') + "\\\"" + std::string(1000, '{') + "\"}"), "");
  // An escaped backslash does not escape the quote after it: the string ends and the brackets count.
  EXPECT_NE(scan_error("[\"\\\\\"," + nested_arrays(kMaxJsonDepth) + "]"), "");
}

// Writes `bytes` to a file in the test output directory and returns its path.
std::string write_file(const std::string& name, const std::string& bytes) {
  const std::string path = std::string(CANDELA_TEST_OUTPUT_DIR) + "/" + name;
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

// A GLB (12-byte header, then one JSON chunk) around `json`, padded to 4 bytes as the format requires.
std::string glb_with_json(std::string json) {
  json.append((4 - json.size() % 4) % 4, ' ');
  auto u32 = [](uint32_t v) {
    std::string s(4, '\0');
    std::memcpy(s.data(), &v, 4);
    return s;
  };
  return "glTF" + u32(2) + u32(uint32_t(20 + json.size())) + u32(uint32_t(json.size())) + "JSON" + json;
}

const std::string kDeep = nested_arrays(100000);

TEST(JsonNesting, GltfOf100000LevelsIsRefusedCleanly) {
  const std::string path =
      write_file("deep_100000.gltf", "{\"asset\": {\"version\": \"2.0\"}, \"extras\": " + kDeep + "}");
  EXPECT_EQ(input_error([&] { load_gltf(path); }), path + ": " + kTooDeep);
}

TEST(JsonNesting, GlbOf100000LevelsIsRefusedCleanly) {
  const std::string path =
      write_file("deep_100000.glb", glb_with_json("{\"asset\": {\"version\": \"2.0\"}, \"extras\": " + kDeep + "}"));
  EXPECT_EQ(input_error([&] { load_gltf(path); }), path + ": " + kTooDeep);
}

TEST(JsonNesting, ShotScriptOf100000LevelsIsRefusedCleanly) {
  const std::string path = write_file("deep_100000.json", "{\"scene\": \"builtin:cornell\", \"deep\": " + kDeep + "}");
  EXPECT_EQ(input_error([&] { read_shot_script(path); }), path + ": " + kTooDeep);
}

}  // namespace
}  // namespace candela
