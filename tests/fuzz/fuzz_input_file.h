#pragma once
// Both loaders read files by path, so a fuzz target writes the fuzzer's bytes to a file of its own: one
// private directory per process (relative URIs inside the input then resolve to nothing), one name per
// extension.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <string>

namespace candela::fuzz {

// `bytes` written to DIR/input.EXTENSION (DIR made once per process); returns the path.
inline std::string write_input_file(const uint8_t* bytes, size_t size, const std::string& extension) {
  static const std::string dir = [] {
    char pattern[] = "/tmp/candela_fuzz_XXXXXX";
    if (!mkdtemp(pattern)) std::abort();
    return std::string(pattern);
  }();
  std::string path = dir + "/input." + extension;
  std::ofstream(path, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(bytes), std::streamsize(size));
  return path;
}

}  // namespace candela::fuzz
