// The image value: 8-bit RGBA pixels, rows top to bottom.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "geobrush/value.hpp"

namespace geobrush {

class Image final : public Value {
 public:
  static constexpr std::string_view kTypeId = "geobrush.Image";

  Image() = default;
  Image(int width, int height) : width(width), height(height), rgba(4ull * width * height, 0) {}

  std::string_view typeId() const override { return kTypeId; }
  Hash contentHash() const override;
  std::string summary() const override;

  std::uint8_t* pixel(int x, int y) { return &rgba[4ull * (std::size_t(y) * width + x)]; }
  const std::uint8_t* pixel(int x, int y) const {
    return &rgba[4ull * (std::size_t(y) * width + x)];
  }

  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgba;
};

using ImagePtr = std::shared_ptr<const Image>;

// Encodes the image as PNG at `path` atomically (temporary file, then rename).
// Throws std::runtime_error naming the path on failure.
void writePng(const Image& image, const std::filesystem::path& path);
// Decodes a PNG (any format Qt reads) into RGBA8. Throws on failure.
Image readPng(const std::filesystem::path& path);

// Writes one line of dark text on a pale box at the image's top left corner, `pixelSize` pixels
// high (a label naming what the picture shows). Draws with Qt's fonts (DejaVu Sans, or the
// system's default): in a program without a QGuiApplication, an offscreen one is made for it.
// Returns false, leaving the image as it was, when no font can be found.
bool drawLabel(Image& image, const std::string& text, int pixelSize = 18);

}  // namespace geobrush
