#include "geobrush/text.hpp"

#include <array>
#include <sstream>

namespace geobrush {
namespace {

// The length of the well-formed UTF-8 character at the start of `text` that encodes U+00A0 or
// above (C1 controls and overlong forms are not text), or 0.
std::size_t utf8CharLength(std::string_view text) {
  const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(text[i]); };
  const unsigned char lead = byte(0);
  std::size_t length = 0;
  char32_t code = 0;
  if (lead >= 0xC2 && lead <= 0xDF) {
    length = 2, code = lead & 0x1F;
  } else if (lead >= 0xE0 && lead <= 0xEF) {
    length = 3, code = lead & 0x0F;
  } else if (lead >= 0xF0 && lead <= 0xF4) {
    length = 4, code = lead & 0x07;
  } else {
    return 0;
  }
  if (text.size() < length) return 0;
  for (std::size_t i = 1; i < length; ++i) {
    if ((byte(i) & 0xC0) != 0x80) return 0;
    code = (code << 6) | (byte(i) & 0x3F);
  }
  const char32_t least[] = {0, 0, 0xA0, 0x800, 0x10000};
  const bool surrogate = code >= 0xD800 && code <= 0xDFFF;
  if (code < least[length] || surrogate || code > 0x10FFFF) return 0;
  return length;
}

void appendEscaped(std::string& out, unsigned char c) {
  switch (c) {
    case '\n':
      out += "\\n";
      return;
    case '\t':
      out += "\\t";
      return;
    case '\r':
      out += "\\r";
      return;
    case '\\':
      out += "\\\\";
      return;
    default:
      break;
  }
  static constexpr std::array<char, 16> kHex{'0', '1', '2', '3', '4', '5', '6', '7',
                                             '8', '9', 'a', 'b', 'c', 'd', 'e', 'f'};
  out += "\\x";
  out += kHex[c >> 4];
  out += kHex[c & 0xF];
}

// Backslashes are escaped in quoted texts, so that an escape in the text and one we write differ;
// a whole message keeps them, as its quoted parts are escaped already.
std::string escape(std::string_view text, std::size_t limit, bool escapeBackslash) {
  std::string out;
  std::size_t i = 0;
  for (std::size_t shown = 0; i < text.size() && shown < limit; ++shown) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c >= 0x20 && c < 0x7F && (c != '\\' || !escapeBackslash)) {
      out += static_cast<char>(c);
      ++i;
    } else if (const std::size_t length = c >= 0x80 ? utf8CharLength(text.substr(i)) : 0) {
      out.append(text.substr(i, length));
      i += length;
    } else {
      appendEscaped(out, c);
      ++i;
    }
  }
  if (i < text.size()) out += "... (" + std::to_string(text.size()) + " bytes)";
  return out;
}

}  // namespace

std::string escapeText(std::string_view text, std::size_t limit) {
  return escape(text, limit, true);
}

std::string quoteText(std::string_view text, std::size_t limit) {
  // Appending, not "'" + ...: GCC 12 warns falsely (-Wrestrict) on a literal plus a temporary.
  std::string quoted = "'";
  quoted += escapeText(text, limit);
  quoted += '\'';
  return quoted;
}

bool isUtf8(std::string_view text) {
  for (std::size_t i = 0; i < text.size();) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c < 0x80) {
      ++i;
      continue;
    }
    // Two-byte forms of U+0080..U+009F are well-formed too, though escapeText escapes them.
    const bool c1Control = c == 0xC2 && i + 1 < text.size() &&
                           static_cast<unsigned char>(text[i + 1]) >= 0x80 &&
                           static_cast<unsigned char>(text[i + 1]) < 0xA0;
    const std::size_t length = c1Control ? 2 : utf8CharLength(text.substr(i));
    if (length == 0) return false;
    i += length;
  }
  return true;
}

std::string quotePath(const std::filesystem::path& path) {
  return quoteText(path.native(), 4096);
}

std::string messageLine(std::string_view message, std::size_t limit) {
  return escape(message, limit, false);
}

std::string numberText(double x) {
  std::ostringstream s;
  s.precision(4);
  s << x;
  return s.str();
}

std::string pointText(const Eigen::Vector3d& p) {
  std::ostringstream s;
  s.precision(6);
  s << "(" << p.x() << ", " << p.y() << ", " << p.z() << ")";
  return s.str();
}

}  // namespace geobrush
