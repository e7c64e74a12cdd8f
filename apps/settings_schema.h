#pragma once
// Every render setting, declared once: one row per setting gives its shot-script key (the command-line
// option is the same word with '-' for '_'), type, range or names, one-line doc, group, the methods it
// applies to and where it is accepted. Defaults are not repeated here: a row reads them from a
// default-constructed RenderSettings (or from whatever settings a command starts from, e.g. converge's).
// From this table come the options of `render`, `view` and `converge` (settings_options.h), the
// shot-script reader (apps/shot_script.cpp), the viewer's widgets (apps/viewer/hud.cpp) and
// docs/settings.md (`candela render --help-markdown`). Adding a setting is one row here plus the code
// that uses it (docs/design.md, "Adding a setting").
#include <functional>
#include <string>
#include <vector>

#include "apps/renderer.h"

namespace candela {

enum class SettingType {
  Int,     // whole number in [min, max] (or one of `values`)
  Float,   // number in [min, max]
  Flag,    // true or false; the command line has --NAME and its `off_option`
  Choice,  // one of `names`
};

enum class SettingGroup { Frame, RestirDi, RestirGi, Denoiser };

// Where a setting is accepted (bits of Setting::scope).
enum SettingScope : unsigned {
  kCommandLine = 1,  // `candela render` and `candela view`
  kScript = 2,       // shot scripts
  kViewer = 4,       // a widget in the viewer's HUD
  kConverge = 8,     // `candela converge` (not where its --methods names decide the setting)
  kEverywhere = 15,
};

// Methods a setting applies to (bits of Setting::methods).
enum MethodBits : unsigned {
  kPt = 1,
  kDirect = 2,
  kRestirDi = 4,
  kRestir = 8,
  kAllMethods = 15,
  kRestirMethods = kRestirDi | kRestir,
};

struct Setting {
  std::string key;  // shot-script key, "di_neighbours"
  SettingGroup group;
  SettingType type;
  std::string doc;  // one line, no method prefix (methods says that)
  unsigned methods = kAllMethods;
  unsigned scope = kEverywhere;
  double min = 0.0, max = 0.0;     // Int, Float: the accepted range
  double widget_max = 0.0;         // Int, Float: the viewer slider's upper end where it is below max (0: max)
  std::vector<int> values;         // Int: when not empty, the only values accepted
  std::vector<std::string> names;  // Choice: the accepted names
  std::string off_option;          // Flag: the option that sets it false (without "--")
  std::string refusal;             // not in kScript: why a script may not give it
  // The value in `settings`: the number (Int, Float), 0 or 1 (Flag) or the index into `names` (Choice).
  std::function<double(const RenderSettings&)> get;
  std::function<void(RenderSettings&, double)> set;
  // Where set (or null: always): whether the setting matters for these settings beyond the method (the
  // viewer greys out its widget otherwise), e.g. the a-trous kernel only with SVGF.
  std::function<bool(const RenderSettings&)> relevant;

  std::string option() const;                         // "--di-neighbours"
  std::string format(const RenderSettings& s) const;  // the value as the command line writes it
  std::string range_text() const;                     // "0..31", "3 or 5", "none, basic, pairwise", "flag"
  bool applies(const RenderSettings& s) const;        // the method is one of `methods`, and relevant
  int name_index(const std::string& name) const;      // Choice: the index of `name` in `names`, or -1
  // Whether `v` is a value of the row: Int and Float within [min, max] (NaN is not), Int a whole number and one
  // of `values` where given, Flag 0 or 1, Choice an index into `names`.
  bool accepts(double v) const;
};

// Every row, in the order of the docs (by group).
const std::vector<Setting>& settings_schema();
// The row with this script key, or null.
const Setting* find_setting(const std::string& key);
const char* setting_group_name(SettingGroup group);  // "Frame", "ReSTIR DI", ...
std::string method_list(unsigned methods);           // "restir-di, restir"
// docs/settings.md's generated part: one Markdown table per group (`candela render --help-markdown`).
std::string settings_markdown();

}  // namespace candela
