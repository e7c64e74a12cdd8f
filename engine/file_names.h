#pragma once
// Names of the files that writers put beside their target before renaming them into place (the output appears
// whole or not at all).
#include <filesystem>
#include <string>

namespace candela {

// `target`'s directory / "." + name: a hidden file beside the target. (Built by appending: GCC 12 warned about
// "." + std::string&&, a false -Wrestrict positive, GCC bug 105329.)
inline std::filesystem::path hidden_beside(const std::filesystem::path& target, const std::string& name) {
  return target.parent_path() / std::string(".").append(name);
}

}  // namespace candela
