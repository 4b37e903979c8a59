#include "atomic_file.hpp"

#include <unistd.h>

#include <atomic>
#include <stdexcept>
#include <string>

#include "geobrush/text.hpp"

namespace geobrush {
namespace {

namespace fs = std::filesystem;

// As many links as the kernel follows before it gives up (Linux's MAXSYMLINKS).
constexpr int kMaxLinks = 40;

const char* describe(fs::file_type type) {
  switch (type) {
    case fs::file_type::directory:
      return "a folder";
    case fs::file_type::block:
    case fs::file_type::character:
      return "a device";
    case fs::file_type::fifo:
      return "a FIFO";
    case fs::file_type::socket:
      return "a socket";
    default:
      return "not a regular file";
  }
}

std::runtime_error notReplaceable(const fs::path& target, const std::string& why) {
  return std::runtime_error(quotePath(target) + ": " + why +
                            "; only a regular file (or a link to one) is replaced");
}

}  // namespace

fs::path temporaryPathFor(const fs::path& target) {
  static std::atomic<unsigned> counter{0};
  // ".name.tmp-PID-N.ext": hidden, unique, and the extension still names the format.
  std::string name = ".";
  name += target.stem().string();
  name += ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
  name += target.extension().string();
  return target.parent_path() / name;
}

fs::path replaceableTarget(const fs::path& target) {
  fs::path path = target;
  for (int links = 0;; ++links) {
    std::error_code ec;
    const fs::file_status status = fs::symlink_status(path, ec);
    // A missing file (or folder on the way) is created by the write, or its error names it.
    if (status.type() == fs::file_type::not_found) return path;
    if (ec) throw notReplaceable(target, "cannot inspect it: " + ec.message());
    if (fs::is_regular_file(status)) return path;
    if (!fs::is_symlink(status)) {
      const std::string what = describe(status.type());
      throw notReplaceable(target, path == target ? "is " + what : "leads to " + what);
    }
    if (links == kMaxLinks) throw notReplaceable(target, "too many levels of symbolic links");
    const fs::path link = fs::read_symlink(path, ec);
    if (ec) throw notReplaceable(target, "cannot read the link: " + ec.message());
    path = link.is_absolute() ? link : path.parent_path() / link;
  }
}

void replaceWithTemporary(const fs::path& tmp, const fs::path& target) {
  const fs::path file = replaceableTarget(target);
  std::error_code ec;
  fs::rename(tmp, file, ec);
  if (ec) throw std::runtime_error(quotePath(target) + ": cannot replace it: " + ec.message());
}

void writeFileAtomically(const fs::path& target,
                         const std::function<void(const fs::path& tmp)>& write) {
  const auto tmp = temporaryPathFor(replaceableTarget(target));
  try {
    write(tmp);
    replaceWithTemporary(tmp, target);
  } catch (...) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw;
  }
}

}  // namespace geobrush
