#include "run_controller.hpp"

#include <QMetaObject>
#include <cmath>

#include "trainsim/core/error.hpp"
#include "trainsim/core/progress.hpp"

namespace trainsim::studio {

RunController::RunController(QObject* parent) : QObject(parent) {}

RunController::~RunController() {
  cancel_ = true;
  if (worker_.joinable())
    worker_.join();
}

bool RunController::start(const scenario::Scenario& scenario, const QString& out, bool force) {
  if (running_)
    return false;
  if (worker_.joinable())
    worker_.join();
  running_ = true;
  cancel_ = false;
  worker_ = std::thread([this, scenario, out, force] {
    int code = 0;
    QString message;
    try {
      ProgressReporter reporter(ProgressMode::kNone);
      reporter.setListener([this](const ProgressUpdate& u) {
        QString text = QString("%1: %2 / %3 %4")
                           .arg(QString::fromUtf8(u.stage.data(), static_cast<int>(u.stage.size())))
                           .arg(u.done)
                           .arg(u.total)
                           .arg(QString::fromUtf8(u.unit.data(), static_cast<int>(u.unit.size())));
        if (std::isfinite(u.eta_s) && u.done < u.total)
          text += QString(", ETA %1 s").arg(u.eta_s, 0, 'f', 0);
        const double fraction = u.fraction;
        QMetaObject::invokeMethod(
            this, [this, fraction, text] { emit progress(fraction, text); }, Qt::QueuedConnection);
      });
      sim::GenerateOptions options;
      options.out = out.toStdString();
      options.policy.force = force;
      options.progress = &reporter;
      options.cancel = &cancel_;
      const sim::GenerateReport report = sim::generate(scenario, options);
      message =
          QString("dataset written to %1: %2 trajectory samples").arg(out).arg(report.samples);
    } catch (const Cancelled& e) {
      code = 130;
      message = QString::fromUtf8(e.what());
    } catch (const std::exception& e) {
      code = exitCodeFor(e);
      message = QString::fromUtf8(e.what());
    }
    QMetaObject::invokeMethod(
        this,
        [this, code, message, out] {
          running_ = false;
          emit finished(code, message, out);
        },
        Qt::QueuedConnection);
  });
  return true;
}

void RunController::cancel() {
  cancel_ = true;
}

}  // namespace trainsim::studio
