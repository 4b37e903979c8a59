// Writing a file so that readers see the old file or the complete new one.
#pragma once

#include <filesystem>
#include <functional>

namespace geobrush {

// A temporary file name beside `target` (same folder, so rename is atomic),
// unique within the process, keeping the extension last.
std::filesystem::path temporaryPathFor(const std::filesystem::path& target);

// The file that writing `target` replaces: `target` itself when it is a regular file or does not
// exist yet, or the file that a symbolic link at `target` leads to (the link stays, the file it
// names is replaced). Throws std::runtime_error naming `target` when it is anything else (a
// device, FIFO, socket or folder): renaming a file over it would replace, say, /dev/full.
std::filesystem::path replaceableTarget(const std::filesystem::path& target);

// Renames the temporary file `tmp` (made beside replaceableTarget(target)) onto
// replaceableTarget(target), checked again now. Throws std::runtime_error naming `target`.
void replaceWithTemporary(const std::filesystem::path& tmp, const std::filesystem::path& target);

// Calls `write(tmp)` with tmp beside replaceableTarget(target), then replaceWithTemporary;
// removes tmp and rethrows if anything fails. Nothing is written when `target` cannot be replaced.
void writeFileAtomically(const std::filesystem::path& target,
                         const std::function<void(const std::filesystem::path& tmp)>& write);

}  // namespace geobrush
