#include "engine/atomic_files.h"

#include <fstream>

#include "engine/check.h"

namespace candela {

void write_text_atomically(const std::string& path, const std::function<void(std::ostream&)>& write) {
  const std::filesystem::path target(path);
  const std::filesystem::path tmp = hidden_beside(target, target.filename().string() + ".tmp");
  std::error_code ec;
  auto fail = [&](const std::string& why) {
    std::filesystem::remove(tmp, ec);
    throw InputError(path + ": " + why);
  };
  {
    std::ofstream f(tmp);
    if (!f) fail("cannot open for writing");
    write(f);
    f.close();  // flushes the stream's buffer: a write that fails there fails here, not unseen in the destructor
    if (!f) fail("write failed");
  }
  std::filesystem::rename(tmp, target, ec);
  if (ec) fail("cannot write: " + ec.message());
}

}  // namespace candela
