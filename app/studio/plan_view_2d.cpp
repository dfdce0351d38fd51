#include "plan_view_2d.hpp"

#include <qcustomplot.h>
#include <QVBoxLayout>
#include <cmath>
#include <map>

namespace trainsim::studio {

PlanView2D::PlanView2D(QWidget* parent) : QWidget(parent), plot_(new QCustomPlot(this)) {
  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(0, 0, 0, 0);
  layout->addWidget(plot_);
  plot_->setObjectName("plan2d");
  plot_->setInteractions(QCP::iRangeDrag | QCP::iRangeZoom);
  plot_->xAxis->setLabel("east [m]");
  plot_->yAxis->setLabel("north [m]");
  plot_->legend->setVisible(true);
  plot_->legend->setFont(QFont(font().family(), 8));
  plot_->legend->setBrush(QBrush(QColor(255, 255, 255, 210)));
  plot_->axisRect()->insetLayout()->setInsetAlignment(0, Qt::AlignTop | Qt::AlignLeft);
  connect(plot_, &QCustomPlot::mouseDoubleClick, this, [this](QMouseEvent*) { fit(); });
  // Keep one metre the same length on both axes whatever is zoomed or dragged.
  connect(plot_->xAxis, qOverload<const QCPRange&>(&QCPAxis::rangeChanged), this,
          [this](const QCPRange&) { plot_->yAxis->setScaleRatio(plot_->xAxis, 1.0); });
}

void PlanView2D::setPlan(std::shared_ptr<const PlanSnapshot> plan) {
  const bool first = plot_->plottableCount() == 0;
  plot_->clearPlottables();
  plot_->clearItems();
  // One curve per block type per track, broken (NaN) between stretches of other types.
  std::map<track::LayoutBlockType, bool> in_legend;
  for (const TrackLine& t : plan->tracks) {
    std::map<track::LayoutBlockType, QCPCurve*> curves;
    std::map<track::LayoutBlockType, std::size_t> last_segment;
    for (std::size_t i = 0; i < t.segment_type.size(); ++i) {
      const track::LayoutBlockType type = t.segment_type[i];
      QCPCurve*& c = curves[type];
      if (c == nullptr) {
        c = new QCPCurve(plot_->xAxis, plot_->yAxis);
        const Rgb rgb = blockColour(type);
        c->setPen(QPen(QColor(rgb.r, rgb.g, rgb.b), t.kind == track::TrackKind::kMain ? 2.5 : 1.6));
        c->setName(QString::fromUtf8(nameOf(type).data(), static_cast<int>(nameOf(type).size())));
        if (in_legend[type])
          c->removeFromLegend();
        in_legend[type] = true;
      } else if (last_segment[type] + 1 != i) {
        c->addData(NAN, NAN);
      }
      if (c->dataCount() == 0 || last_segment[type] + 1 != i)
        c->addData(t.points[i].x(), t.points[i].y());
      c->addData(t.points[i + 1].x(), t.points[i + 1].y());
      last_segment[type] = i;
    }
  }
  for (const ChainageMark& m : plan->chainage_marks) {
    auto* label = new QCPItemText(plot_);
    label->position->setCoords(m.position.x(), m.position.y());
    label->setText(QString("%1 km").arg(m.chainage_m / 1000.0, 0, 'f', 1));
    label->setFont(QFont(font().family(), 7));
    label->setColor(QColor(60, 60, 80));
    label->setPositionAlignment(Qt::AlignLeft | Qt::AlignBottom);
    label->setPadding(QMargins(3, 0, 0, 3));
  }
  violations_ = plot_->addGraph();
  violations_->setName("rule violation");
  violations_->setLineStyle(QCPGraph::lsNone);
  violations_->setScatterStyle(
      QCPScatterStyle(QCPScatterStyle::ssCircle, QColor(210, 30, 30), QColor(210, 30, 30, 90), 11));
  for (const ViolationMark& v : plan->violations)
    violations_->addData(v.position.x(), v.position.y());
  train_ = plot_->addGraph();
  train_->setName("train");
  train_->setLineStyle(QCPGraph::lsNone);
  train_->setScatterStyle(
      QCPScatterStyle(QCPScatterStyle::ssDiamond, QColor(200, 0, 0), QColor(200, 0, 0), 12));
  if (first)
    fit();
  else
    plot_->replot();
}

void PlanView2D::fit() {
  plot_->rescaleAxes();
  // Margins, then equal scale (the axis with more room per metre widens).
  plot_->xAxis->scaleRange(1.05);
  plot_->yAxis->scaleRange(1.05);
  const double sx = plot_->xAxis->range().size() / std::max(1, plot_->axisRect()->width());
  const double sy = plot_->yAxis->range().size() / std::max(1, plot_->axisRect()->height());
  if (sx > sy)
    plot_->yAxis->setScaleRatio(plot_->xAxis, 1.0);
  else
    plot_->xAxis->setScaleRatio(plot_->yAxis, 1.0);
  plot_->replot();
}

void PlanView2D::markTrain(const TrainPose& pose) {
  if (!train_)
    return;
  train_->data()->clear();
  train_->addData(pose.position.x(), pose.position.y());
  plot_->replot(QCustomPlot::rpQueuedReplot);
}

int PlanView2D::violationCount() const {
  return violations_ ? violations_->dataCount() : 0;
}

void PlanView2D::resizeEvent(QResizeEvent* event) {
  QWidget::resizeEvent(event);
  plot_->yAxis->setScaleRatio(plot_->xAxis, 1.0);
  plot_->replot(QCustomPlot::rpQueuedReplot);
}

}  // namespace trainsim::studio
