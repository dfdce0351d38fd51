#include "plot_panel.hpp"

#include <algorithm>

#include <qcustomplot.h>
#include <QVBoxLayout>
#include <cmath>
#include <utility>

namespace trainsim::studio {

QVector<double> seconds(const QVector<double>& t_ns) {
  QVector<double> out(t_ns.size());
  std::transform(t_ns.begin(), t_ns.end(), out.begin(), [](double t) { return t * 1e-9; });
  return out;
}

namespace {

// "acceleration [m/s²]" → ("acceleration", "m/s²"); a label without a bracketed unit is all
// quantity.
std::pair<QString, QString> splitLabel(const QString& label) {
  const auto open = label.lastIndexOf(" [");
  if (open < 0 || !label.endsWith(']'))
    return {label, QString()};
  return {label.left(open), label.mid(open + 2, label.size() - open - 3)};
}

}  // namespace

PlotPanel::PlotPanel(QWidget* parent) : QWidget(parent), plot_(new QCustomPlot(this)) {
  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(0, 0, 0, 0);
  layout->addWidget(plot_);
  plot_->setInteractions(QCP::iRangeDrag | QCP::iRangeZoom);
  plot_->setNoAntialiasingOnDrag(true);
  plot_->setAutoAddPlottableToLegend(false);  // each row has its own legend
  connect(plot_, &QCustomPlot::mousePress, this, [this](QMouseEvent* e) {
    press_ = e->pos();
    // Ctrl-drag pans/zooms y too; plain drag and wheel act on the shared x axis.
    for (QCPAxisRect* r : rects_)
      r->setRangeDrag(e->modifiers() & Qt::ControlModifier ? Qt::Horizontal | Qt::Vertical
                                                           : Qt::Horizontal);
  });
  connect(plot_, &QCustomPlot::mouseWheel, this, [this](QWheelEvent* e) {
    for (QCPAxisRect* r : rects_)
      r->setRangeZoom(e->modifiers() & Qt::ControlModifier ? Qt::Vertical : Qt::Horizontal);
  });
  connect(plot_, &QCustomPlot::mouseRelease, this, [this](QMouseEvent* e) {
    // A click (no drag) selects the x under the mouse.
    if ((e->pos() - press_).manhattanLength() > 3)
      return;
    for (QCPAxisRect* r : rects_) {
      if (r->rect().contains(e->pos())) {
        const double x = r->axis(QCPAxis::atBottom)->pixelToCoord(e->pos().x());
        setCursor(x);
        emit xSelected(x);
        return;
      }
    }
  });
  connect(plot_, &QCustomPlot::mouseDoubleClick, this, [this](QMouseEvent*) { fit(); });
}

void PlotPanel::setRows(const QString& x_label, const std::vector<PlotRow>& rows) {
  plot_->clearItems();
  plot_->clearPlottables();
  plot_->plotLayout()->clear();
  rects_.clear();
  cursors_.clear();
  auto* group = new QCPMarginGroup(plot_);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    auto* rect = new QCPAxisRect(plot_);
    plot_->plotLayout()->addElement(static_cast<int>(i), 0, rect);
    rect->setMarginGroup(QCP::msLeft | QCP::msRight, group);
    rect->setRangeDrag(Qt::Horizontal);
    rect->setRangeZoom(Qt::Horizontal);
    QCPAxis* x = rect->axis(QCPAxis::atBottom);
    QCPAxis* y = rect->axis(QCPAxis::atLeft);
    // Rows are short (four or more share the panel): the axis is titled with the unit alone and
    // the quantity is written in the row's top-left corner, since a whole title such as
    // "acceleration [m/s²]" is longer than the row is high and runs into its neighbours'.
    const auto [quantity, unit] = splitLabel(rows[i].y_label);
    y->setLabel(unit);
    y->ticker()->setTickCount(3);  // more labels than this overlap on a short row
    if (i + 1 == rows.size())
      x->setLabel(x_label);
    rect->setupFullAxesBox(true);
    auto* title = new QCPTextElement(plot_, quantity, QFont(font().family(), 8));
    title->setLayer("legend");
    title->setTextFlags(Qt::AlignLeft | Qt::AlignTop);
    title->setMargins(QMargins(6, 2, 0, 0));  // clear of the axis line
    rect->insetLayout()->addElement(title, Qt::AlignTop | Qt::AlignLeft);
    // The legend in one line, so that it stays within a short row.
    auto* legend = new QCPLegend;
    rect->insetLayout()->addElement(legend, Qt::AlignTop | Qt::AlignRight);
    legend->setLayer("legend");
    legend->setFillOrder(QCPLayoutGrid::foColumnsFirst);
    legend->setFont(QFont(font().family(), 8));
    legend->setBrush(QBrush(QColor(255, 255, 255, 200)));
    for (const Series& s : rows[i].series) {
      QCPGraph* g = plot_->addGraph(x, y);
      g->setName(s.name);
      g->setData(s.x, s.y, true);
      g->setPen(QPen(s.colour, 1.2));
      if (s.dots) {
        g->setLineStyle(QCPGraph::lsNone);
        g->setScatterStyle(QCPScatterStyle(QCPScatterStyle::ssCircle, s.colour, s.colour, 4));
      }
      g->setAdaptiveSampling(true);
      legend->addItem(new QCPPlottableLegendItem(legend, g));
    }
    connect(x, qOverload<const QCPRange&>(&QCPAxis::rangeChanged), this,
            [this, rect](const QCPRange&) { syncX(rect); });
    auto* cursor = new QCPItemStraightLine(plot_);
    cursor->setClipAxisRect(rect);
    cursor->point1->setAxes(x, y);
    cursor->point2->setAxes(x, y);
    cursor->setPen(QPen(QColor(200, 30, 30), 1.0, Qt::DashLine));
    cursor->setVisible(false);
    cursors_.push_back(cursor);
    rects_.push_back(rect);
  }
  fit();
}

void PlotPanel::syncX(const QCPAxisRect* from) {
  if (syncing_)
    return;
  syncing_ = true;
  const QCPRange range = from->axis(QCPAxis::atBottom)->range();
  for (QCPAxisRect* r : rects_) {
    if (r != from)
      r->axis(QCPAxis::atBottom)->setRange(range);
  }
  syncing_ = false;
  plot_->replot(QCustomPlot::rpQueuedReplot);
}

void PlotPanel::fit() {
  for (QCPAxisRect* r : rects_) {
    for (QCPGraph* g : r->graphs())
      g->rescaleAxes(g != r->graphs().front());
    // A margin around the data, and a visible range for constant series.
    QCPAxis* y = r->axis(QCPAxis::atLeft);
    const QCPRange range = y->range();
    if (range.size() < 1e-12)
      y->setRange(range.center() - 1.0, range.center() + 1.0);
    else
      y->scaleRange(1.12, range.center());
  }
  plot_->replot();
}

void PlotPanel::setCursor(double x) {
  for (QCPItemStraightLine* c : cursors_) {
    c->point1->setCoords(x, 0.0);
    c->point2->setCoords(x, 1.0);
    c->setVisible(true);
  }
  plot_->replot(QCustomPlot::rpQueuedReplot);
}

std::vector<std::pair<double, double>> PlotPanel::data(int row, int index) const {
  std::vector<std::pair<double, double>> out;
  const QCPGraph* g = rects_.at(static_cast<std::size_t>(row))->graphs().at(index);
  for (auto it = g->data()->constBegin(); it != g->data()->constEnd(); ++it)
    out.emplace_back(it->key, it->value);
  return out;
}

QWidget* PlotPanel::plotWidget() const {
  return plot_;
}

QPoint PlotPanel::pixelOf(int row, double x) const {
  const QCPAxisRect* r = rects_.at(static_cast<std::size_t>(row));
  const QCPAxis* y = r->axis(QCPAxis::atLeft);
  return {static_cast<int>(std::lround(r->axis(QCPAxis::atBottom)->coordToPixel(x))),
          static_cast<int>(std::lround(y->coordToPixel(y->range().center())))};
}

QString PlotPanel::seriesName(int row, int index) const {
  return rects_.at(static_cast<std::size_t>(row))->graphs().at(index)->name();
}

}  // namespace trainsim::studio
