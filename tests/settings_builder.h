#pragma once
// The one way tests build RenderSettings: by the settings schema's keys (apps/settings_schema.h), as a shot
// script gives them, so a test reads like the command it stands for:
//   RenderSettings s = testing::settings({{"width", 64}, {"method", "restir-di"}, {"jitter", false}});
// A second argument is the settings to start from. An unknown key or name, or a value outside its row,
// throws std::invalid_argument naming the key (the test fails there). Members that are not settings (test
// switches, internal parameters) are set on the result by hand.
#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

#include "apps/settings_names.h"
#include "apps/settings_schema.h"

namespace candela::testing {

// A setting's value as a test writes it: a number or flag, or a choice's name.
struct SettingValue {
  template <class T, std::enable_if_t<std::is_arithmetic_v<T>, int> = 0>
  SettingValue(T value) : number(double(value)) {}
  SettingValue(const char* choice) : name(choice), is_name(true) {}
  SettingValue(std::string choice) : name(std::move(choice)), is_name(true) {}
  double number = 0.0;
  std::string name;
  bool is_name = false;
};

inline RenderSettings settings(std::initializer_list<std::pair<const char*, SettingValue>> values,
                               RenderSettings base = {}) {
  for (const auto& [key, value] : values) {
    const Setting* row = find_setting(key);
    if (!row) throw std::invalid_argument(std::string("testing::settings: no setting '") + key + "'");
    auto fail = [&](const std::string& what) {
      throw std::invalid_argument(std::string("testing::settings: ") + key + ": " + what + " (" + row->range_text() +
                                  ")");
    };
    double x = value.number;
    if (row->type == SettingType::Choice) {
      if (!value.is_name) fail("expected a name");
      x = double(row->name_index(value.name));
      if (x < 0.0) fail("'" + value.name + "' is not a name");
    } else if (value.is_name) {
      fail("expected a number");
    } else if (!row->accepts(x)) {
      fail(std::to_string(x) + " is not a value of the setting");
    }
    row->set(base, x);
  }
  return base;
}

}  // namespace candela::testing
