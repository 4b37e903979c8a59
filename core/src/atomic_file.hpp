// Writing a file so that readers see the old file or the complete new one.
#pragma once

#include <filesystem>
#include <functional>

namespace geobrush {

// A temporary file name beside `target` (same folder, so rename is atomic),
// unique within the process, keeping the extension last.
std::filesystem::path temporaryPathFor(const std::filesystem::path& target);

// Calls `write(tmp)`, then renames tmp onto `target`; removes tmp and
// rethrows if anything fails.
void writeFileAtomically(const std::filesystem::path& target,
                         const std::function<void(const std::filesystem::path& tmp)>& write);

}  // namespace geobrush
