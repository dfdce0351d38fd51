#pragma once

#include <QWidget>
#include <memory>

#include "plan_service.hpp"

class QCustomPlot;
class QCPGraph;

namespace trainsim::studio {

/// The 2D plan view (east/north, equal scale): every track coloured by block type, chainage
/// labels, violation markers and the train. Drag to pan, wheel to zoom, double-click to fit.
class PlanView2D : public QWidget {
  Q_OBJECT

 public:
  explicit PlanView2D(QWidget* parent = nullptr);

  void setPlan(std::shared_ptr<const PlanSnapshot> plan);
  void markTrain(const TrainPose& pose);
  void fit();

  /// Number of violation markers drawn (for tests).
  int violationCount() const;

 protected:
  void resizeEvent(QResizeEvent* event) override;

 private:
  QCustomPlot* plot_;
  QCPGraph* violations_ = nullptr;
  QCPGraph* train_ = nullptr;
};

}  // namespace trainsim::studio
