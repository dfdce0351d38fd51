// trainsim-studio [SCENARIO]: the desktop studio. Opens SCENARIO (or the built-in default).

#include <QVTKOpenGLNativeWidget.h>
#include <QApplication>
#include <QCommandLineParser>
#include <QSurfaceFormat>
#include <QTimer>

#include "main_window.hpp"
#include "trainsim/core/version.hpp"

int main(int argc, char** argv) {
  // VTK's Qt widget needs its OpenGL format before the application exists.
  QSurfaceFormat::setDefaultFormat(QVTKOpenGLNativeWidget::defaultFormat());
  QApplication app(argc, argv);
  QApplication::setApplicationName("TrainSim Studio");
  QApplication::setApplicationVersion(
      QString::fromUtf8(trainsim::version().data(), static_cast<int>(trainsim::version().size())));
  QCommandLineParser parser;
  parser.setApplicationDescription("TrainSim Studio: design routes, run and plot the results");
  parser.addHelpOption();
  parser.addVersionOption();
  parser.addPositionalArgument("scenario", "Scenario JSON to open (default: the built-in one)");
  parser.process(app);

  trainsim::studio::MainWindow window;
  window.show();
  const QStringList args = parser.positionalArguments();
  if (!args.isEmpty())
    QTimer::singleShot(0, &window, [&window, path = args.front()] { window.openScenario(path); });
  return QApplication::exec();
}
