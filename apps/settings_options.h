#pragma once
// The command-line side of the settings schema: one CLI11 option per row.
#include <CLI/CLI.hpp>

#include "apps/settings_schema.h"

namespace candela {

// Adds an option for every schema row accepted in `scope` (kCommandLine or kConverge) to `command`; a
// parsed option writes its value into `settings`. The defaults shown are `settings`' values now. A flag
// gets --NAME and its off option; a number its range; a choice its names.
void add_setting_options(CLI::App& command, RenderSettings& settings, unsigned scope);

}  // namespace candela
