// Every input the fuzzers (tests/fuzz, `make fuzz`) found crashing is kept in tests/data/fuzz/, named after
// its bug, and must now fail cleanly: an InputError naming the file and saying what is wrong.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <string>

#include "engine/check.h"
#include "tests/fuzz/exercise.h"

namespace candela {
namespace {

namespace fs = std::filesystem;

const std::string kFuzzData = std::string(CANDELA_SOURCE_DIR) + "/tests/data/fuzz";

// Bug (the start of its findings' paths under tests/data/fuzz) -> what their messages say after "PATH: ".
const std::map<std::string, std::string> kBugs = {
    // A number beyond double's range ("1e999"): nlohmann throws out_of_range (406), not parse_error, and
    // it escaped the shot-script reader and terminated the process.
    {"scripts/number_overflow_", "invalid JSON: number overflow parsing '"},
};

// The message of the InputError that exercising `path` throws, "" when it throws none.
std::string error_of(bool gltf, const std::string& path) {
  try {
    if (gltf)
      fuzz::exercise_gltf(path);
    else
      fuzz::exercise_shot_script(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(FuzzFindings, EachFailsCleanlyNamingTheFile) {
  std::map<std::string, int> findings_of_bug;
  for (const char* kind : {"gltf", "scripts"}) {
    if (!fs::is_directory(kFuzzData + "/" + kind)) continue;  // no findings of that kind
    for (const fs::directory_entry& entry : fs::directory_iterator(kFuzzData + "/" + kind)) {
      const std::string name = std::string(kind) + "/" + entry.path().filename().string();
      auto bug = std::find_if(kBugs.begin(), kBugs.end(), [&](const auto& b) { return name.rfind(b.first, 0) == 0; });
      ASSERT_NE(bug, kBugs.end()) << name << " is named after no bug listed in " << __FILE__;
      ++findings_of_bug[bug->first];
      const std::string path = entry.path().string();
      const std::string error = error_of(std::string(kind) == "gltf", path);
      EXPECT_EQ(error.rfind(path + ": ", 0), 0u) << error;
      EXPECT_NE(error.find(bug->second), std::string::npos) << name << ": " << error;
    }
  }
  for (const auto& [bug, message] : kBugs) EXPECT_GT(findings_of_bug[bug], 0) << "no file for " << bug;
}

}  // namespace
}  // namespace candela
