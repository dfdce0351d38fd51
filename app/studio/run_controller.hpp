#pragma once

#include <QObject>
#include <QString>
#include <atomic>
#include <memory>
#include <thread>

#include "trainsim/scenario/scenario.hpp"
#include "trainsim/sim/generate.hpp"

namespace trainsim::studio {

/// Runs `trainsim generate` (sim::generate, the CLI's code path and dataset writer) on a
/// worker thread, reporting progress and honouring cancel. Signals arrive on the GUI thread.
class RunController : public QObject {
  Q_OBJECT

 public:
  explicit RunController(QObject* parent = nullptr);
  ~RunController() override;

  /// Starts a run into `out`; `force` starts over in a folder that holds a dataset. Returns
  /// false (and does nothing) while another run is going.
  bool start(const scenario::Scenario& scenario, const QString& out, bool force);
  void cancel();
  bool running() const { return running_; }

 signals:
  /// `fraction` of the current stage in [0, 1]; `text` names the stage, rate and ETA.
  void progress(double fraction, const QString& text);
  /// The run ended: ok, cancelled, or failed with `message` (the CLI's error text);
  /// `exit_code` is what the CLI would return (0, 1 or 2; 130 when cancelled).
  void finished(int exit_code, const QString& message, const QString& out);

 private:
  std::thread worker_;
  std::atomic<bool> cancel_{false};
  bool running_ = false;
};

}  // namespace trainsim::studio
