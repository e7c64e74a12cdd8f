// The settings schema (apps/settings_schema.h): every row reaches its own member, round-trips every value
// of its range, and the command line and shot scripts built from it set exactly that member.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>

#include "apps/settings_options.h"
#include "apps/settings_schema.h"
#include "apps/shot_script.h"
#include "engine/check.h"

namespace candela {
namespace {

// Values a row must accept: its range's ends and a middle value, each allowed value, each name, both
// flag states.
std::vector<double> test_values(const Setting& row) {
  switch (row.type) {
    case SettingType::Int:
      if (!row.values.empty()) return {row.values.begin(), row.values.end()};
      return {row.min, std::floor((row.min + row.max) / 2), row.max};
    case SettingType::Float: return {row.min, (row.min + row.max) / 2, row.max};
    case SettingType::Flag: return {0.0, 1.0};
    case SettingType::Choice: {
      std::vector<double> v;
      for (size_t i = 0; i < row.names.size(); ++i) v.push_back(double(i));
      return v;
    }
  }
  return {};
}

// A value of the row other than its default (the one tests set to see it arrive).
double other_value(const Setting& row, const RenderSettings& defaults) {
  for (double v : test_values(row))
    if (v != row.get(defaults)) return v;
  ADD_FAILURE() << row.key << " has a single value";
  return 0.0;
}

// The value as the command line and scripts write it.
std::string text_of(const Setting& row, double v) {
  RenderSettings s;
  row.set(s, v);
  return row.format(s);
}

// The rows' values in `s`, by key.
std::map<std::string, double> values_of(const RenderSettings& s) {
  std::map<std::string, double> out;
  for (const Setting& row : settings_schema()) out[row.key] = row.get(s);
  return out;
}

// Every row but `key` still has its value from `before`.
void expect_only_changed(const std::string& key, const RenderSettings& before, const RenderSettings& after) {
  const auto a = values_of(before), b = values_of(after);
  for (const auto& [k, v] : a)
    if (k != key) {
      EXPECT_EQ(b.at(k), v) << "setting " << key << " also changed " << k;
    }
}

TEST(SettingsSchema, KeysAndOptionsAreUniqueAndDocumented) {
  std::set<std::string> keys, options;
  for (const Setting& row : settings_schema()) {
    EXPECT_TRUE(keys.insert(row.key).second) << row.key;
    EXPECT_TRUE(options.insert(row.option()).second) << row.option();
    if (row.type == SettingType::Flag) {
      EXPECT_TRUE(options.insert("--" + row.off_option).second) << row.off_option;
    }
    EXPECT_FALSE(row.doc.empty()) << row.key;
    EXPECT_NE(row.methods, 0u) << row.key;
    if (!(row.scope & kScript)) {
      EXPECT_FALSE(row.refusal.empty()) << row.key << ": scripts are not told why";
    }
    EXPECT_EQ(find_setting(row.key), &row);
  }
  EXPECT_EQ(find_setting("no_such_setting"), nullptr);
}

TEST(SettingsSchema, DefaultsAreWithinTheirRows) {
  const RenderSettings defaults;
  for (const Setting& row : settings_schema()) {
    const double v = row.get(defaults);
    if (row.type == SettingType::Choice) {
      EXPECT_LT(size_t(v), row.names.size()) << row.key;
    } else if (!row.values.empty()) {
      EXPECT_NE(std::find(row.values.begin(), row.values.end(), int(v)), row.values.end()) << row.key;
    } else {
      EXPECT_TRUE(v >= row.min && v <= row.max) << row.key << " = " << v;
    }
  }
}

// set then get gives the value back (as the member's type holds it), and no other row moves: each row
// reaches a member of its own.
TEST(SettingsSchema, EveryRowSetsItsOwnMemberOverItsWholeRange) {
  for (const Setting& row : settings_schema()) {
    for (double v : test_values(row)) {
      RenderSettings s;
      row.set(s, v);
      const double expected = row.type == SettingType::Float ? double(float(v)) : v;
      EXPECT_EQ(row.get(s), expected) << row.key << " set to " << v;
      expect_only_changed(row.key, RenderSettings{}, s);
    }
  }
}

// `--OPTION VALUE` (flags: the option that gives the value) sets the row's member, and only it.
TEST(SettingsSchema, CommandLineSetsEveryRow) {
  for (unsigned scope : {unsigned(kCommandLine), unsigned(kConverge)}) {
    for (const Setting& row : settings_schema()) {
      if (!(row.scope & scope)) continue;
      RenderSettings s;
      CLI::App app;
      add_setting_options(app, s, scope);
      const double v = other_value(row, s);
      std::vector<std::string> args;
      if (row.type == SettingType::Flag)
        args = {v != 0.0 ? row.option() : "--" + row.off_option};
      else
        args = {row.option(), text_of(row, v)};
      std::reverse(args.begin(), args.end());  // CLI11 takes the arguments last first
      app.parse(args);
      EXPECT_EQ(row.get(s), row.type == SettingType::Float ? double(float(v)) : v) << row.option();
      expect_only_changed(row.key, RenderSettings{}, s);
    }
  }
}

TEST(SettingsSchema, CommandLineRejectsValuesOutsideTheRow) {
  for (const Setting& row : settings_schema()) {
    if (!(row.scope & kCommandLine) || row.type == SettingType::Flag) continue;
    RenderSettings s;
    CLI::App app;
    add_setting_options(app, s, kCommandLine);
    const std::string bad = row.type == SettingType::Choice ? "no-such-name"
                            : !row.values.empty()           ? "4"
                                                            : text_of(row, row.max) + "1";
    EXPECT_THROW(app.parse(std::vector<std::string>{bad, row.option()}), CLI::ValidationError)
        << row.option() << " " << bad;
  }
}

// Decimal settings refuse NaN and text; of a flag and its off option given several times, the last wins.
TEST(SettingsSchema, CommandLineRefusesNanAndTakesTheLastFlag) {
  for (const Setting& row : settings_schema()) {
    if (!(row.scope & kCommandLine)) continue;
    RenderSettings s;
    CLI::App app;
    add_setting_options(app, s, kCommandLine);
    if (row.type == SettingType::Float) {
      for (const char* bad : {"nan", "-nan", "1x"})
        EXPECT_THROW(app.parse(std::vector<std::string>{bad, row.option()}), CLI::ValidationError)
            << row.option() << " " << bad;
    } else if (row.type == SettingType::Flag) {
      const std::string on = row.option(), off = "--" + row.off_option;
      app.parse(std::vector<std::string>{off, on});  // reversed: `on` first, then `off`
      EXPECT_EQ(row.get(s), 0.0) << on << " " << off;
      app.parse(std::vector<std::string>{on, off});
      EXPECT_EQ(row.get(s), 1.0) << off << " " << on;
    }
  }
}

// A shot script with `"KEY": VALUE` sets the row's member, and only it; keys a script may not give are
// refused with the row's reason.
class ScriptFile {
 public:
  explicit ScriptFile(const std::string& entry) {
    path_ = std::filesystem::temp_directory_path() / ("candela_schema_" + std::to_string(::getpid()) + ".json");
    std::ofstream(path_) << "{\"scene\": \"builtin:cornell\", " << entry
                         << " \"output\": {\"images\": [\"out/f_%04d.png\"]}}";
  }
  ~ScriptFile() { std::filesystem::remove(path_); }
  std::string path() const { return path_.string(); }

 private:
  std::filesystem::path path_;
};

TEST(SettingsSchema, ShotScriptsSetEveryRow) {
  for (const Setting& row : settings_schema()) {
    if (!(row.scope & kScript)) continue;
    RenderSettings base = read_shot_script(ScriptFile("").path()).settings;
    const double v = other_value(row, base);
    const std::string text = text_of(row, v);
    ScriptFile file("\"" + row.key + "\": " + (row.type == SettingType::Choice ? "\"" + text + "\"" : text) + ",");
    RenderSettings s = read_shot_script(file.path()).settings;
    EXPECT_EQ(row.get(s), row.type == SettingType::Float ? double(float(v)) : v) << row.key;
    expect_only_changed(row.key, base, s);
  }
}

TEST(SettingsSchema, ShotScriptsRefuseOutOfRangeAndForbiddenKeys) {
  for (const Setting& row : settings_schema()) {
    std::string bad;
    if (!(row.scope & kScript))
      bad = "1";
    else if (row.type == SettingType::Choice)
      bad = "\"no-such-name\"";
    else if (row.type == SettingType::Flag)
      bad = "3";
    else if (!row.values.empty())
      bad = "4";
    else
      bad = text_of(row, row.max) + "1";
    ScriptFile file("\"" + row.key + "\": " + bad + ",");
    try {
      read_shot_script(file.path());
      ADD_FAILURE() << row.key << ": " << bad << " accepted";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(": " + row.key + ": "), std::string::npos) << what;
      if (!(row.scope & kScript)) {
        EXPECT_NE(what.find(row.refusal), std::string::npos) << what;
      }
      if (row.type == SettingType::Int && (row.scope & kScript)) {
        EXPECT_NE(what.find(row.values.empty() ? ".." : " or "), std::string::npos) << what;
      }
    }
  }
}

TEST(SettingsSchema, MarkdownHasOneRowPerSetting) {
  const std::string md = settings_markdown();
  for (const Setting& row : settings_schema())
    EXPECT_NE(md.find("| `" + row.option() + "`"), std::string::npos) << row.key;
  size_t rows = 0;
  for (size_t at = md.find("\n| `--"); at != std::string::npos; at = md.find("\n| `--", at + 1)) ++rows;
  EXPECT_EQ(rows + (md.rfind("| `--", 0) == 0 ? 1 : 0), settings_schema().size());
}

}  // namespace
}  // namespace candela
