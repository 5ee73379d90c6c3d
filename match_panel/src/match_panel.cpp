#include "match_panel.h"

#include <QComboBox>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QLabel>
#include <QSizePolicy>
#include <QPushButton>
#include <QTimer>
#include <QVBoxLayout>

#include <pluginlib/class_list_macros.hpp>

#include <chrono>

namespace match_panel {

namespace {

const char* colourOf(int level) {
  switch (level) {
    case 0: return "#2e7d32";  // OK
    case 1: return "#e65100";  // WARN
    case 2: return "#c62828";  // ERROR
    default: return "#6a1b9a";  // STALE
  }
}

QString html(const std::string& s) { return QString::fromStdString(s).toHtmlEscaped(); }

const int kDevicesShown = 8;  // the worst ones; the rest are counted
const char* const kListing = "strategy list";

}  // namespace

MatchPanel::MatchPanel(QWidget* parent) : rviz::Panel(parent) {
  auto* form = new QFormLayout;
  robot_ = new QLabel;
  state_ = new QLabel;
  clock_ = new QLabel;
  clock_->setStyleSheet("font-size: 20pt; font-weight: bold;");
  score_ = new QLabel;
  score_->setStyleSheet("font-size: 14pt; font-weight: bold;");
  active_ = new QLabel;
  active_->setWordWrap(true);
  trigger_ = new QLabel;
  form->addRow("Robot:", robot_);
  form->addRow("Match:", state_);
  form->addRow("Clock:", clock_);
  form->addRow("Score:", score_);
  form->addRow("Active:", active_);
  form->addRow("Trigger:", trigger_);

  strategies_ = new QComboBox;
  switch_ = new QPushButton("Switch");
  auto* strategy_row = new QHBoxLayout;
  strategy_row->addWidget(strategies_, 1);
  strategy_row->addWidget(switch_);
  form->addRow("Strategy:", strategy_row);

  start_ = new QPushButton("Start (pull cord)");
  emergency_ = new QPushButton("EMERGENCY: deactivate effectors");
  emergency_->setStyleSheet("background-color: #c62828; color: white; font-weight: bold;");
  answer_ = new QLabel;
  answer_->setWordWrap(true);
  diagnostics_ = new QLabel;
  diagnostics_->setTextFormat(Qt::RichText);
  diagnostics_->setWordWrap(true);
  diagnostics_->setAlignment(Qt::AlignTop | Qt::AlignLeft);

  // Every line wraps, and no label asks for the width of its text: a long "not ready: ..." grows
  // the panel downwards, never the dock sideways over the 3D view.
  form->setRowWrapPolicy(QFormLayout::WrapLongRows);
  for (QLabel* l : {robot_, state_, score_, active_, trigger_, answer_, diagnostics_}) {
    l->setWordWrap(true);
    l->setSizePolicy(QSizePolicy::Ignored, QSizePolicy::Preferred);
    l->setMinimumWidth(0);
  }

  auto* layout = new QVBoxLayout;
  layout->addLayout(form);
  layout->addWidget(start_);
  layout->addWidget(emergency_);
  layout->addWidget(answer_);
  layout->addWidget(new QLabel("<b>Diagnostics</b>"));
  layout->addWidget(diagnostics_, 1);
  setLayout(layout);

  connect(start_, SIGNAL(clicked()), this, SLOT(startClicked()));
  connect(switch_, SIGNAL(clicked()), this, SLOT(switchClicked()));
  connect(emergency_, SIGNAL(clicked()), this, SLOT(emergencyClicked()));
  timer_ = new QTimer(this);
  connect(timer_, SIGNAL(timeout()), this, SLOT(render()));
}

MatchPanel::~MatchPanel() {
  timer_->stop();
  if (pending_.valid()) pending_.wait();  // the worker uses the model: let it finish first
}

void MatchPanel::onInitialize() {
  model_.reset(new PanelModel);
  timer_->start(200);  // 5 Hz: smooth enough for tenths that move, cheap for rviz
  render();
}

void MatchPanel::run(const std::string& what, std::function<ServiceResult()> action) {
  if (pending_.valid()) {
    answer_->setText(QString::fromStdString(pending_what_ + ": still waiting for the answer"));
    return;
  }
  pending_what_ = what;
  pending_ = std::async(std::launch::async, std::move(action));
  answer_->setText(QString::fromStdString(what + " ..."));
}

void MatchPanel::startClicked() {
  run("start", [this] { return model_->startMatch(); });
}

void MatchPanel::switchClicked() {
  const std::string name = strategies_->currentText().toStdString();
  if (name.empty()) return;
  run("switch to " + name, [this, name] { return model_->switchStrategy(name); });
}

void MatchPanel::emergencyClicked() {
  run("emergency", [this] { return model_->emergencyStop(); });
}

void MatchPanel::render() {
  if (!model_) return;
  if (pending_.valid() && pending_.wait_for(std::chrono::seconds(0)) == std::future_status::ready) {
    const ServiceResult r = pending_.get();  // get() leaves the future invalid: the next click may run
    answer_->setText(QString("%1: %2 %3").arg(html(pending_what_), r.ok ? "ok" : "FAILED", html(r.message)));
    answer_->setStyleSheet(r.ok ? "" : "color: #c62828;");
    if (pending_what_ == kListing && !r.ok) listed_ = false;  // the brain did not answer: ask again
  }
  const Snapshot s = model_->snapshot(ros::Time::now());
  robot_->setText(html(s.robot_name));
  if (!s.have_status) {
    state_->setText("no /brain/match_status");
  } else {
    QString state = html(s.state + " (" + s.strategy + ")");
    if (s.state == "waiting_for_start") state += s.ready ? QString(" - ready") : " - " + html(s.readiness);
    state_->setText(state);
    // The list once, as soon as the brain is there (not on every render: it is a service call).
    if (!listed_ && !pending_.valid()) {
      listed_ = true;
      run(kListing, [this] { return model_->refreshStrategies(); });
    }
  }
  clock_->setText(QString::fromStdString(s.clock));
  score_->setText(QString::fromStdString(s.score));
  active_->setText(s.active_path.empty() ? QString("\xe2\x80\x94") : html(s.active_path));
  trigger_->setText(s.last_trigger.empty() ? QString("none yet") : html(s.last_trigger));

  // Refill the combo box only when the list changed, so an open selection is not reset.
  QStringList names;
  for (const auto& n : s.strategies) names << QString::fromStdString(n);
  QStringList shown;
  for (int i = 0; i < strategies_->count(); ++i) shown << strategies_->itemText(i);
  if (names != shown) {
    strategies_->clear();
    strategies_->addItems(names);
    strategies_->setCurrentText(QString::fromStdString(s.strategy));
  }

  QString diag;
  int n = 0;
  for (const auto& d : s.devices) {
    if (n++ == kDevicesShown) {
      diag += QString("%1 more").arg(s.devices.size() - kDevicesShown);
      break;
    }
    diag += QString("<span style='color:%1'><b>%2</b></span> %3: %4<br>")
                .arg(colourOf(d.level), html(levelName(d.level)), html(d.name), html(d.message));
  }
  diagnostics_->setText(s.devices.empty() ? QString("no /diagnostics") : diag);
}

}  // namespace match_panel

PLUGINLIB_EXPORT_CLASS(match_panel::MatchPanel, rviz::Panel)
