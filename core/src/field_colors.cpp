#include "geobrush/field_colors.hpp"

#include <QtGui/QColor>
#include <QtGui/QPainter>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "gui_application.hpp"

namespace geobrush {
namespace {

// The value at fraction q of the sorted values (nearest rank).
double quantile(std::vector<double> sorted, double q) {
  std::sort(sorted.begin(), sorted.end());
  return sorted[std::size_t(std::lround(q * double(sorted.size() - 1)))];
}

Rgb mix(const Rgb& a, const Rgb& b, double t) {
  return {float(a[0] + t * (b[0] - a[0])), float(a[1] + t * (b[1] - a[1])),
          float(a[2] + t * (b[2] - a[2]))};
}

// Moreland's cool-to-warm ends and a near-white middle; a dark-to-light ramp for one sign.
constexpr Rgb kCool{0.23f, 0.30f, 0.75f}, kMiddle{0.87f, 0.87f, 0.87f}, kWarm{0.71f, 0.02f, 0.15f};
constexpr Rgb kDark{0.10f, 0.10f, 0.35f}, kLight{0.99f, 0.90f, 0.45f};

Rgb colorAt(double t, bool diverging) {
  t = std::clamp(t, 0.0, 1.0);
  if (!diverging) return mix(kDark, kLight, t);
  return t < 0.5 ? mix(kCool, kMiddle, 2 * t) : mix(kMiddle, kWarm, 2 * t - 1);
}

std::string formatted(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", value);
  return text;
}

}  // namespace

FieldRange fieldRange(const std::vector<double>& values) {
  std::vector<double> finite;
  for (double v : values)
    if (std::isfinite(v)) finite.push_back(v);
  FieldRange range;
  if (finite.empty()) return range;
  const auto [lo, hi] = std::minmax_element(finite.begin(), finite.end());
  if (*lo < 0.0 && *hi > 0.0) {
    std::vector<double> magnitude;
    for (double v : finite)
      magnitude.push_back(std::abs(v));
    const double m = quantile(magnitude, 0.98);
    range = {-m, m, true};
  } else {
    range = {quantile(finite, 0.02), quantile(finite, 0.98), false};
  }
  if (!(range.high > range.low)) {
    const double middle = 0.5 * (range.low + range.high);
    range.low = middle - 0.5;
    range.high = middle + 0.5;
  }
  return range;
}

std::vector<Rgb> fieldColors(const std::vector<double>& values, const FieldRange& range) {
  std::vector<Rgb> colors;
  colors.reserve(values.size());
  for (double v : values)
    colors.push_back(std::isfinite(v)
                         ? colorAt((v - range.low) / (range.high - range.low), range.diverging)
                         : Rgb{0.5f, 0.5f, 0.5f});
  return colors;
}

bool drawFieldLegend(Image& image, const std::string& name, const FieldRange& range,
                     int pixelSize) {
  return paintOn(image, pixelSize, [&](QPainter& painter) {
    const int margin = pixelSize, barWidth = std::min(image.width / 3, 12 * pixelSize);
    const int barHeight = pixelSize, top = image.height - margin - barHeight - pixelSize - 4;
    painter.fillRect(margin / 2, top - pixelSize - 8, barWidth + margin, 3 * pixelSize + 16,
                     QColor(255, 255, 255, 220));
    for (int x = 0; x < barWidth; ++x) {
      const Rgb c = colorAt(double(x) / std::max(barWidth - 1, 1), range.diverging);
      painter.fillRect(margin + x, top, 1, barHeight,
                       QColor::fromRgbF(double(c[0]), double(c[1]), double(c[2])));
    }
    painter.setPen(QColor(20, 20, 20));
    const int below = top + barHeight + pixelSize + 2;
    painter.drawText(margin, top - 4, QString::fromStdString(name));
    painter.drawText(margin, below, QString::fromStdString(formatted(range.low)));
    const QString high = QString::fromStdString(formatted(range.high));
    painter.drawText(margin + barWidth - painter.fontMetrics().horizontalAdvance(high), below,
                     high);
  });
}

}  // namespace geobrush
