// The studio's GUI suite (Qt Test): one main window driven through the slots in the order
// declared here. The design and plan cases are in studio_gui_test.cpp, the run's outputs
// (scans, pictures, scene, screenshots) in studio_gui_run_test.cpp.
#pragma once

#include <QObject>
#include <QString>
#include <QTemporaryDir>
#include <memory>

#include "main_window.hpp"

// Types `text` into a generated field and commits it as a user does (Return).
void typeInto(trainsim::studio::MainWindow& w, const QString& path, const QString& text);

class StudioGuiTest : public QObject {
  Q_OBJECT

 private slots:
  void initTestCase();
  void opensTheDefaultScenarioAndPlansIt();
  void editingACurveRadiusUpdatesThePlan();
  void anOutOfRangeValueIsMarkedAtItsField();
  void aTrainOrSensorEditDoesNotRebuildTheRouteOrLayout();
  void aRunGoesToTheEndAndTheImuPlotHoldsItsSamples();
  void theRunsScansAndPicturesAreShownWithTheirLabels();
  void lidarPointsOnThePictureLandWhereTheCameraSawThem();
  void aClickOnThePictureSaysWhatIsThere();
  void theSceneAroundAChainageIsWhatTheEnvironmentStreams();
  void selectingATimeMarksTheTrain();
  void cancelStopsARunWithoutAFinishedDataset();
  void aBrokenScenarioShowsTheValidatorsMessagesAndTheStudioStaysUsable();
  void screenshots();
  void cleanupTestCase();

 private:
  QTemporaryDir tmp_;
  std::unique_ptr<trainsim::studio::MainWindow> window_;
};
