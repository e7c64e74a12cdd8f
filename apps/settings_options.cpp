#include "apps/settings_options.h"

#include <cstdlib>

namespace candela {

void add_setting_options(CLI::App& command, RenderSettings& settings, unsigned scope) {
  for (const Setting& row : settings_schema()) {
    if (!(row.scope & scope)) continue;
    const std::string doc = row.methods == kAllMethods ? row.doc : method_list(row.methods) + ": " + row.doc;
    const std::string fallback = row.format(settings);
    auto set = [&settings, &row](double v) { row.set(settings, v); };
    switch (row.type) {
      case SettingType::Int: {
        CLI::Option* o = command.add_option_function<int64_t>(
            row.option(), [set](const int64_t& v) { set(double(v)); }, doc);
        if (row.values.empty())
          o->check(CLI::Range(int64_t(row.min), int64_t(row.max)));
        else
          o->check(CLI::IsMember(row.values));
        o->default_str(fallback);
        break;
      }
      case SettingType::Float:
        command
            .add_option_function<double>(
                row.option(), [set](const double& v) { set(v); }, doc)
            ->check(CLI::Validator(
                [&row](std::string& text) {  // CLI::Range lets NaN through
                  char* end = nullptr;
                  const double v = std::strtod(text.c_str(), &end);
                  if (end == text.c_str() || *end != '\0') return "Value " + text + " is not a number";
                  if (!row.accepts(v)) return "Value " + text + " not in range " + row.range_text();
                  return std::string();
                },
                "FLOAT in [" + row.range_text() + "]"))
            ->default_str(fallback);
        break;
      case SettingType::Flag:
        command
            .add_flag_function(
                row.option() + ",!--" + row.off_option, [set](int64_t count) { set(count > 0); },
                doc + " (default: " + (fallback == "true" ? row.option() : "--" + row.off_option) + ")")
            ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);  // the last of --x / --no-x wins
        break;
      case SettingType::Choice:
        command
            .add_option_function<std::string>(
                row.option(), [set, &row](const std::string& name) { set(double(row.name_index(name))); }, doc)
            ->check(CLI::IsMember(row.names))
            ->default_str(fallback);
        break;
    }
  }
}

}  // namespace candela
