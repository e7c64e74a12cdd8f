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
      auto it = std::find(row->names.begin(), row->names.end(), value.name);
      if (it == row->names.end()) fail("'" + value.name + "' is not a name");
      x = double(it - row->names.begin());
    } else if (value.is_name) {
      fail("expected a number");
    } else if (row->type != SettingType::Float && x != std::floor(x)) {
      fail(std::to_string(x) + " is not a whole number");
    } else if (row->type == SettingType::Flag ? x != 0.0 && x != 1.0 : !(x >= row->min && x <= row->max)) {
      fail(std::to_string(x) + " is out of range");
    } else if (!row->values.empty() && std::find(row->values.begin(), row->values.end(), int(x)) == row->values.end()) {
      fail(std::to_string(x) + " is not allowed");
    }
    row->set(base, x);
  }
  return base;
}

}  // namespace candela::testing
