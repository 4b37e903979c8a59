#include "geobrush/image.hpp"

#include <QtCore/QCoreApplication>
#include <QtCore/QDir>
#include <QtCore/QString>
#include <QtGui/QFont>
#include <QtGui/QFontDatabase>
#include <QtGui/QGuiApplication>
#include <QtGui/QImage>
#include <QtGui/QPainter>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <stdexcept>

#include "atomic_file.hpp"
#include "gui_application.hpp"

namespace geobrush {
namespace {

QString toQString(const std::filesystem::path& path) {
  return QString::fromStdString(path.string());
}

}  // namespace

Hash Image::contentHash() const {
  Hasher hasher;
  hasher.str(kTypeId).u64(std::uint64_t(width)).u64(std::uint64_t(height));
  return hasher.span(std::span<const std::uint8_t>(rgba)).digest();
}

std::string Image::summary() const {
  return "image: " + std::to_string(width) + "x" + std::to_string(height) + " RGBA8";
}

void writePng(const Image& image, const std::filesystem::path& path) {
  const std::string where = "writePng: " + path.string() + ": ";
  if (image.width <= 0 || image.height <= 0 ||
      image.rgba.size() != 4ull * image.width * image.height)
    throw std::runtime_error(where + "the image is empty or its pixel buffer has the wrong size");
  // QImage only wraps the pixels here; save() reads them.
  const QImage wrapped(image.rgba.data(), image.width, image.height, 4 * image.width,
                       QImage::Format_RGBA8888);
  writeFileAtomically(path, [&](const std::filesystem::path& temporary) {
    if (!wrapped.save(toQString(temporary), "PNG"))
      throw std::runtime_error(where + "cannot write " + temporary.string());
  });
}

Image readPng(const std::filesystem::path& path) {
  QImage decoded;
  if (!decoded.load(toQString(path)))
    throw std::runtime_error("readPng: " + path.string() +
                             ": cannot read it or it is not an image in a known format");
  decoded.convertTo(QImage::Format_RGBA8888);
  Image image(decoded.width(), decoded.height());
  const std::size_t rowBytes = 4ull * image.width;
  for (int y = 0; y < image.height; ++y)
    std::memcpy(image.pixel(0, y), decoded.constScanLine(y), rowBytes);
  return image;
}

namespace {

// Whether Qt can find a plugin for the platform it is asked for: without one, QGuiApplication
// aborts the process instead of failing.
bool platformPluginInstalled() {
  const QString platform =
      QString::fromLocal8Bit(std::getenv("QT_QPA_PLATFORM")).section(':', 0, 0);
  QStringList folders = QCoreApplication::libraryPaths();
  for (QString& folder : folders)
    folder += "/platforms";
  if (const char* own = std::getenv("QT_QPA_PLATFORM_PLUGIN_PATH"))
    folders.prepend(QString::fromLocal8Bit(own));
  for (const QString& folder : folders)
    if (!QDir(folder).entryList({"*q" + platform + ".*"}, QDir::Files).isEmpty()) return true;
  return false;
}

}  // namespace

bool ensureGuiApplication() {
  static std::once_flag once;
  std::call_once(once, [] {
    if (QCoreApplication::instance()) return;
    if (!std::getenv("QT_QPA_PLATFORM")) ::setenv("QT_QPA_PLATFORM", "offscreen", 0);
    if (!platformPluginInstalled()) return;
    static int argc = 1;
    static char name[] = "geobrush";
    static char* argv[] = {name, nullptr};
    // Qt's start-up notes (e.g. no XDG_RUNTIME_DIR) are not the program's to print; why Qt gives
    // up (no platform plugin, after which it aborts) is.
    const QtMessageHandler previous = qInstallMessageHandler(
        [](QtMsgType type, const QMessageLogContext&, const QString& message) {
          if (type == QtFatalMsg || type == QtCriticalMsg)
            std::fprintf(stderr, "Qt: %s\n", message.toLocal8Bit().constData());
        });
    new QGuiApplication(argc, argv);
    qInstallMessageHandler(previous);
  });
  return qobject_cast<QGuiApplication*>(QCoreApplication::instance()) != nullptr;
}

bool paintOn(Image& image, int pixelSize, const std::function<void(QPainter&)>& draw) {
  if (image.width <= 0 || image.height <= 0 || !ensureGuiApplication()) return false;
  if (QFontDatabase::families().isEmpty()) return false;
  QImage canvas(image.rgba.data(), image.width, image.height, 4 * image.width,
                QImage::Format_RGBA8888);
  QPainter painter(&canvas);
  QFont font("DejaVu Sans");
  font.setPixelSize(pixelSize);
  painter.setFont(font);
  draw(painter);
  return true;
}

bool drawLabel(Image& image, const std::string& text, int pixelSize) {
  return paintOn(image, pixelSize, [&](QPainter& painter) {
    const QString label = QString::fromStdString(text);
    const int margin = pixelSize / 2;
    QRect box = painter.fontMetrics().boundingRect(label);
    box.moveTopLeft({margin, margin});
    painter.fillRect(box.adjusted(-margin / 2, -margin / 2, margin / 2, margin / 2),
                     QColor(255, 255, 255, 220));
    painter.setPen(QColor(20, 20, 20));
    painter.drawText(box, Qt::AlignLeft | Qt::AlignVCenter, label);
  });
}

}  // namespace geobrush
