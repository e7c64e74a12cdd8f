#pragma once
// Outputs written whole or not at all: the writer fills a hidden file beside the target, then renames it into place.
#include <filesystem>
#include <functional>
#include <ostream>
#include <string>

namespace candela {

// `target`'s directory / "." + name: a hidden file beside the target. (Built by appending: GCC 12 warned about
// "." + std::string&&, a false -Wrestrict positive, GCC bug 105329.)
inline std::filesystem::path hidden_beside(const std::filesystem::path& target, const std::string& name) {
  return target.parent_path() / std::string(".").append(name);
}

// Writes the text `write` puts into its stream to `path` through ".<file name>.tmp" beside it, renamed into place.
// On any failure (open, write, rename) the temporary file is removed and InputError names `path`.
void write_text_atomically(const std::string& path, const std::function<void(std::ostream&)>& write);

}  // namespace candela
