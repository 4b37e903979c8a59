#include "atomic_file.hpp"

#include <unistd.h>

#include <atomic>
#include <stdexcept>
#include <string>

namespace geobrush {

std::filesystem::path temporaryPathFor(const std::filesystem::path& target) {
  static std::atomic<unsigned> counter{0};
  // ".name.tmp-PID-N.ext": hidden, unique, and the extension still names the format.
  std::string name = ".";
  name += target.stem().string();
  name += ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
  name += target.extension().string();
  return target.parent_path() / name;
}

void writeFileAtomically(const std::filesystem::path& target,
                         const std::function<void(const std::filesystem::path& tmp)>& write) {
  const auto tmp = temporaryPathFor(target);
  try {
    write(tmp);
    std::filesystem::rename(tmp, target);
  } catch (...) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    throw;
  }
}

}  // namespace geobrush
