// Qt's font and painting classes need a QGuiApplication.
#pragma once

#include <functional>

#include "geobrush/image.hpp"

class QPainter;

namespace geobrush {

// Makes an offscreen QGuiApplication, kept until the process exits, in a program without one (the
// command line, a Python interpreter); false where none can be had (another kind of application
// runs).
bool ensureGuiApplication();

// Calls `draw` with a painter over the image's pixels set to DejaVu Sans (or the system's
// default) `pixelSize` pixels high; false, leaving the image as it was, when no font can be had.
bool paintOn(Image& image, int pixelSize, const std::function<void(QPainter&)>& draw);

}  // namespace geobrush
