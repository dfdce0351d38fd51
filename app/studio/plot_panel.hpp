#pragma once

#include <QColor>
#include <QPoint>
#include <QString>
#include <QVector>
#include <QWidget>
#include <vector>

class QCustomPlot;
class QCPAxisRect;
class QCPItemStraightLine;

namespace trainsim::studio {

/// Colours shared by every plot: a measurement, the truth, and three axes.
inline const QColor kMeasuredColour(31, 119, 180);
inline const QColor kTruthColour(20, 20, 20);
inline const QColor kAxisColours[3] = {QColor(214, 39, 40), QColor(44, 160, 44),
                                       QColor(31, 119, 180)};

/// Nanoseconds to seconds, for time axes.
QVector<double> seconds(const QVector<double>& t_ns);

/// One line of a plot.
struct Series {
  QString name;
  QVector<double> x, y;
  QColor colour;
  bool dots = false;  ///< markers only (events, sparse fixes), no line
};

/// One row of a stacked plot: a y axis and its series.
struct PlotRow {
  QString y_label;  ///< "quantity [unit]": the unit titles the axis, the quantity the row
  std::vector<Series> series;
};

/// Stacked plots sharing one x axis (QCustomPlot): drag to pan, wheel to zoom (x on every row
/// at once; with Ctrl the row's y), double-click to fit. A click puts a cursor at that x on
/// every row and emits xSelected.
class PlotPanel : public QWidget {
  Q_OBJECT

 public:
  explicit PlotPanel(QWidget* parent = nullptr);

  void setRows(const QString& x_label, const std::vector<PlotRow>& rows);
  void setCursor(double x);
  void fit();

  /// For tests: the plot widget (to click on).
  QWidget* plotWidget() const;
  int rowCount() const { return static_cast<int>(rects_.size()); }
  /// Data of series `index` in row `row` as (x, y) pairs, in order.
  std::vector<std::pair<double, double>> data(int row, int index) const;
  QString seriesName(int row, int index) const;
  /// Where (x, middle of the y range) of row `row` is, in plotWidget() pixels.
  QPoint pixelOf(int row, double x) const;

 signals:
  void xSelected(double x);

 private:
  void syncX(const QCPAxisRect* from);

  QCustomPlot* plot_;
  std::vector<QCPAxisRect*> rects_;
  std::vector<QCPItemStraightLine*> cursors_;
  bool syncing_ = false;
  QPoint press_;
};

}  // namespace trainsim::studio
