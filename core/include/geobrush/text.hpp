// Text from files and command lines, made safe to quote in a one-line message.
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>

namespace geobrush {

// How much of a quoted text a message shows.
inline constexpr std::size_t kExcerptLimit = 200;

// `text` with every byte that is not printable ASCII or part of a well-formed UTF-8 character
// (U+00A0 and above) written as an escape (\n, \t, \r, \\, \xHH), so that a message stays one
// line and sends nothing to the terminal but text. At most `limit` characters of `text` are
// shown; a longer text ends in "... (N bytes)".
std::string escapeText(std::string_view text, std::size_t limit = kExcerptLimit);

// escapeText between single quotes: 'text'.
std::string quoteText(std::string_view text, std::size_t limit = kExcerptLimit);
// A path as messages name it: quoteText of its native form, whole up to 4096 bytes.
std::string quotePath(const std::filesystem::path& path);

// Whether `text` is well-formed UTF-8 (what JSON, and so a graph file, can hold).
bool isUtf8(std::string_view text);

// One line for stderr: escapeText of a whole message, bounded by `limit` bytes of it.
std::string messageLine(std::string_view message, std::size_t limit = 2000);

// Numbers and points as messages show them: 4 and 6 significant digits, "(x, y, z)".
std::string numberText(double x);
std::string pointText(const Eigen::Vector3d& p);

}  // namespace geobrush
