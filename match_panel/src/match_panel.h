// The rviz panel: renders PanelModel snapshots at 5 Hz and forwards its buttons to the model.
// Button actions run on a worker thread (std::async) so a slow service never freezes rviz.
#pragma once

#ifndef Q_MOC_RUN
#include <rviz/panel.h>

#include <future>
#include <memory>
#include <string>

#include "match_panel/panel_model.h"
#endif

class QComboBox;
class QLabel;
class QPushButton;
class QTimer;

namespace match_panel {

class MatchPanel : public rviz::Panel {
  Q_OBJECT
 public:
  explicit MatchPanel(QWidget* parent = nullptr);
  ~MatchPanel() override;
  void onInitialize() override;

 private Q_SLOTS:
  void render();
  void startClicked();
  void switchClicked();
  void emergencyClicked();

 private:
  // Runs `action` on a worker thread unless one still runs; its answer shows when it is done.
  void run(const std::string& what, std::function<ServiceResult()> action);

  std::unique_ptr<PanelModel> model_;
  QLabel* robot_;
  QLabel* state_;
  QLabel* clock_;
  QLabel* score_;
  QLabel* active_;
  QLabel* trigger_;
  QLabel* diagnostics_;
  QLabel* answer_;
  QComboBox* strategies_;
  QPushButton* start_;
  QPushButton* switch_;
  QPushButton* emergency_;
  QTimer* timer_;
  std::future<ServiceResult> pending_;
  std::string pending_what_;
  bool listed_ = false;  // the strategy list was asked for once the brain answered
};

}  // namespace match_panel
