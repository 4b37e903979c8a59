// Qt's font and painting classes need a QGuiApplication.
#pragma once

namespace geobrush {

// Makes an offscreen QGuiApplication, kept until the process exits, in a program without one (the
// command line, a Python interpreter); false where none can be had (another kind of application
// runs).
bool ensureGuiApplication();

}  // namespace geobrush
