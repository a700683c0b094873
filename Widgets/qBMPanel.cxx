// qBMPanel.cxx - see qBMPanel.h.
#include "qBMPanel.h"

#include "ui_qBMPanel.h"

#include "bmBenchmarkTable.h"
#include "bmScene.h"
#include "vtkBMSessionSource.h"
#include "vtkBMToolSource.h"

#include "QVTKOpenGLNativeWidget.h"
#include "vtkAxis.h"
#include "vtkChartXY.h"
#include "vtkContextScene.h"
#include "vtkContextView.h"
#include "vtkDoubleArray.h"
#include "vtkGenericOpenGLRenderWindow.h"
#include "vtkNew.h"
#include "vtkPlot.h"
#include "vtkTable.h"

#include <QCheckBox>
#include <QDoubleSpinBox>
#include <QFileDialog>
#include <QFileInfo>
#include <QPair>
#include <QList>
#include <QHash>
#include <QFormLayout>
#include <QJsonDocument>
#include <QJsonObject>
#include <QLabel>
#include <QLineEdit>
#include <QSpinBox>
#include <QStandardItemModel>

#include <algorithm>
#include <exception>
#include <memory>
#include <optional>
#include <string>

namespace {
/// Columns of the history table the charts read (vtkBMSessionSource's output port 2).
const char* const kHistoryColumns[] = {"time_s", "thrust_N", "torque_Nmm", "frame_ms"};
} // namespace

class qBMPanelPrivate : public Ui_qBMPanel {
  Q_DECLARE_PUBLIC(qBMPanel);

public:
  explicit qBMPanelPrivate(qBMPanel& object) : q_ptr(&object) {}
  void init();
  void initCharts();
  /// Shows the logic's description of the chosen tool.
  void updateSummary();
  /// One editor per parameter of the chosen tool type, at the logic's (default) values.
  void rebuildParameterEditors();
  /// Hands the editors' values to the logic as the tool's parameters.
  void applyParameters();
  /// Shows the benchmark's nearest measured cell for the chosen scene, resolutions and method.
  void updateExpectedCost();
  /// The Pause button as the session's state: checked and reading "Resume" while paused.
  void showPaused(bool paused);
  /// A chart of `columns` (after time_s) against time in a new widget under the session group.
  QVTKOpenGLNativeWidget* addChart(vtkChartXY* chart, vtkContextView* view, const char* title,
                                   const char* leftColumn, const char* rightColumn);
  void renderCharts();

  qBMPanel* const q_ptr;
  /// The logic the panel is bound to: holds the chosen tool, describes and validates it.
  vtkNew<vtkBMToolSource> Logic;
  /// Parameter editors by key (QDoubleSpinBox or QSpinBox).
  QList<QPair<QString, QWidget*>> ParameterEditors;
  /// The measured costs, or why they could not be read.
  std::optional<bm::BenchmarkTable> Bench;
  QString BenchError;
  QString TouchStatus;
  /// The charts' copy of the session history.
  vtkNew<vtkTable> History;
  vtkNew<vtkContextView> ForceView, FrameView;
  vtkNew<vtkChartXY> ForceChart, FrameChart;
  QVTKOpenGLNativeWidget* ForceChartWidget = nullptr;
  QVTKOpenGLNativeWidget* FrameChartWidget = nullptr;
  /// The last CT preview's suggested entry point, mm (empty: none yet).
  QVector<double> SuggestedEntry;

  void initCT();
  QVector<QDoubleSpinBox*> roiBoxes() const {
    return {this->RoiX0SpinBox, this->RoiY0SpinBox, this->RoiZ0SpinBox,
            this->RoiX1SpinBox, this->RoiY1SpinBox, this->RoiZ1SpinBox};
  }
  QVector<QDoubleSpinBox*> axisBoxes() const {
    return {this->AxisXSpinBox, this->AxisYSpinBox, this->AxisZSpinBox};
  }
  QVector<QDoubleSpinBox*> entryBoxes() const {
    return {this->EntryXSpinBox, this->EntryYSpinBox, this->EntryZSpinBox};
  }
};

void qBMPanelPrivate::initCT() {
  Q_Q(qBMPanel);
  this->ThresholdSpinBox->setRange(-2000.0, 10000.0);
  this->ThresholdSpinBox->setDecimals(0);
  this->ThresholdSpinBox->setSingleStep(50.0);
  this->ThresholdSpinBox->setValue(200.0);
  for (QDoubleSpinBox* box : this->roiBoxes() + this->entryBoxes()) {
    box->setRange(-10000.0, 10000.0);
    box->setDecimals(2);
  }
  for (QDoubleSpinBox* box : this->axisBoxes()) {
    box->setRange(-1.0, 1.0);
    box->setDecimals(3);
    box->setSingleStep(0.1);
  }
  this->AxisZSpinBox->setValue(1.0);
  this->CTResolutionSpinBox->setRange(8, 1024);
  this->CTResolutionSpinBox->setValue(96);
  this->UseSuggestedEntryButton->setEnabled(false);
  QObject::connect(this->PreviewCTButton, &QPushButton::clicked, q,
                   [q]() { Q_EMIT q->previewCTRequested(); });
  QObject::connect(this->UseSuggestedEntryButton, &QPushButton::clicked, q,
                   [this, q]() { q->setEntry(this->SuggestedEntry); });
  QObject::connect(this->BrowseCTFileButton, &QPushButton::clicked, q, [this, q]() {
    const QString path = QFileDialog::getOpenFileName(
        q, qBMPanel::tr("CT file"), this->CTFileLineEdit->text(),
        qBMPanel::tr("CT volumes (*.nrrd *.nhdr *.mha *.mhd *.nii *.nii.gz *.dcm);;All files (*)"));
    if (!path.isEmpty())
      this->CTFileLineEdit->setText(path);
  });
  QObject::connect(this->BrowseCTFolderButton, &QPushButton::clicked, q, [this, q]() {
    const QString path = QFileDialog::getExistingDirectory(q, qBMPanel::tr("DICOM folder"),
                                                           this->CTFileLineEdit->text());
    if (!path.isEmpty())
      this->CTFileLineEdit->setText(path);
  });
}

void qBMPanelPrivate::init() {
  Q_Q(qBMPanel);
  this->setupUi(q);
  // Item order follows vtkBMToolSource::ToolTypes.
  this->ToolTypeComboBox->clear();
  this->ToolTypeComboBox->addItem(qBMPanel::tr("Twist drill"), int(vtkBMToolSource::DRILL));
  this->ToolTypeComboBox->addItem(qBMPanel::tr("Glenoid reamer"), int(vtkBMToolSource::REAMER));
  this->ToolTypeComboBox->addItem(qBMPanel::tr("Spherical burr"), int(vtkBMToolSource::BURR));
  this->ToolTypeComboBox->setCurrentIndex(this->Logic->GetToolType());
  this->ResolutionSpinBox->setRange(3, 1024);
  this->ResolutionSpinBox->setValue(this->Logic->GetResolution());

  QObject::connect(this->ToolTypeComboBox, QOverload<int>::of(&QComboBox::currentIndexChanged), q,
                   &qBMPanel::setToolType);
  QObject::connect(this->ResolutionSpinBox, QOverload<int>::of(&QSpinBox::valueChanged), q,
                   &qBMPanel::setResolution);
  QObject::connect(this->AddToolButton, &QPushButton::clicked, q, [this, q]() {
    // The edited parameters go with the tool; invalid ones add nothing and say why.
    if (!this->Logic->GetToolIsValid()) {
      q->setStatusMessage(qBMPanel::tr("Cannot add the tool: %1")
                              .arg(QString::fromUtf8(this->Logic->GetToolError())));
      return;
    }
    Q_EMIT q->addToolRequested(q->toolType(), q->resolution());
  });
  this->rebuildParameterEditors();
  this->updateSummary();

  // Session controls.
  for (const std::string& name : bm::Scene::BuiltinNames())
    this->SceneComboBox->addItem(QString::fromStdString(name));
  this->SceneComboBox->setCurrentText(QStringLiteral("glenoid"));
  this->VoxmapResolutionSpinBox->setRange(0, 4096);
  this->VoxmapResolutionSpinBox->setSpecialValueText(qBMPanel::tr("scene's"));
  this->ShellResolutionSpinBox->setRange(0, 4096);
  this->ShellResolutionSpinBox->setSpecialValueText(qBMPanel::tr("scene's"));
  this->MethodComboBox->addItem(qBMPanel::tr("Scene's"), int(vtkBMSessionSource::SCENE_METHOD));
  this->MethodComboBox->addItem(qBMPanel::tr("Lazar (Faieghi et al.)"),
                                int(vtkBMSessionSource::LAZAR));
  this->MethodComboBox->addItem(qBMPanel::tr("Zheng et al."), int(vtkBMSessionSource::ZHENG));
  try {
    this->Bench = bm::BenchmarkTable::Load(bm::BenchmarkTable::DefaultPath());
  } catch (const std::exception& e) {
    this->BenchError = QString::fromUtf8(e.what());
  }
  QObject::connect(this->SceneComboBox, &QComboBox::currentTextChanged, q,
                   [this]() { this->updateExpectedCost(); });
  QObject::connect(this->VoxmapResolutionSpinBox, QOverload<int>::of(&QSpinBox::valueChanged), q,
                   [this]() { this->updateExpectedCost(); });
  QObject::connect(this->ShellResolutionSpinBox, QOverload<int>::of(&QSpinBox::valueChanged), q,
                   [this]() { this->updateExpectedCost(); });
  QObject::connect(this->MethodComboBox, QOverload<int>::of(&QComboBox::currentIndexChanged), q,
                   [this]() { this->updateExpectedCost(); });
  this->updateExpectedCost();

  this->DeviceComboBox->addItem(qBMPanel::tr("Scripted"), int(vtkBMSessionSource::SCRIPTED));
  this->DeviceComboBox->addItem(qBMPanel::tr("Mouse proxy"), int(vtkBMSessionSource::MOUSE));
  this->DeviceComboBox->addItem(qBMPanel::tr("Touch (OpenHaptics)"),
                                int(vtkBMSessionSource::TOUCH));
  this->TouchStatus = QString::fromStdString(vtkBMSessionSource::ProbeTouch());
  if (auto* model = qobject_cast<QStandardItemModel*>(this->DeviceComboBox->model()))
    if (QStandardItem* touch = model->item(2)) {
      touch->setEnabled(this->TouchStatus.isEmpty());
      touch->setToolTip(this->TouchStatus);
    }
  this->TouchStatusLabel->setText(
      this->TouchStatus.isEmpty() ? qBMPanel::tr("Touch: ready.")
                                  : qBMPanel::tr("Touch unavailable: %1").arg(this->TouchStatus));
  this->ToolDepthSpinBox->setRange(-20.0, 20.0);
  this->ToolDepthSpinBox->setSingleStep(0.1);
  this->ToolDepthSpinBox->setDecimals(2);
  this->ToolDepthSpinBox->setValue(-2.0);
  QObject::connect(this->StartButton, &QPushButton::clicked, q, [q]() {
    Q_EMIT q->startSessionRequested(q->sceneName(), q->voxmapResolution(), q->shellResolution(),
                                    q->deviceType());
  });
  this->showPaused(false);
  QObject::connect(this->PauseButton, &QPushButton::toggled, q, [this, q](bool paused) {
    this->showPaused(paused);
    Q_EMIT q->pauseSessionRequested(paused);
  });
  QObject::connect(this->StopButton, &QPushButton::clicked, q,
                   [q]() { Q_EMIT q->stopSessionRequested(); });
  QObject::connect(this->ToolDepthSpinBox, QOverload<double>::of(&QDoubleSpinBox::valueChanged), q,
                   [q](double depth) { Q_EMIT q->toolDepthChanged(depth); });
  QObject::connect(this->SaveBoneButton, &QPushButton::clicked, q, [this, q]() {
    const QString file = qBMPanel::withVoxmapExtension(q->boneFile());
    this->BoneFileLineEdit->setText(file);
    Q_EMIT q->saveBoneRequested(file);
  });
  QObject::connect(this->BrowseBoneButton, &QPushButton::clicked, q, [this, q]() {
    const QString nrrd = qBMPanel::tr("NRRD voxmap (*.nrrd)");
    const QString mha = qBMPanel::tr("MetaImage voxmap (*.mha)");
    QString chosen = nrrd;
    const QString path =
        QFileDialog::getSaveFileName(q, qBMPanel::tr("Bone file"), this->BoneFileLineEdit->text(),
                                     nrrd + ";;" + mha, &chosen, QFileDialog::DontConfirmOverwrite);
    if (!path.isEmpty())
      this->BoneFileLineEdit->setText(
          qBMPanel::withVoxmapExtension(path, chosen == mha ? "mha" : "nrrd"));
  });
  QObject::connect(this->VolumeCheckBox, &QCheckBox::toggled, q,
                   [q](bool on) { Q_EMIT q->volumeRenderingToggled(on); });
  this->initCT();
  this->initCharts();
  q->setSessionStatus(QString(), false);
}

QVTKOpenGLNativeWidget* qBMPanelPrivate::addChart(vtkChartXY* chart, vtkContextView* view,
                                                  const char* title, const char* leftColumn,
                                                  const char* rightColumn) {
  auto* widget = new QVTKOpenGLNativeWidget(this->ChartsWidget);
  widget->setMinimumHeight(140);
  vtkNew<vtkGenericOpenGLRenderWindow> window;
  widget->setRenderWindow(window);
  view->SetRenderWindow(window);
  view->GetScene()->AddItem(chart);
  chart->SetTitle(title);
  chart->SetShowLegend(true);
  chart->GetAxis(vtkAxis::BOTTOM)->SetTitle("time (s)");
  vtkPlot* left = chart->AddPlot(vtkChart::LINE);
  left->SetInputData(this->History, "time_s", leftColumn);
  left->SetColor(30, 90, 200, 255);
  chart->GetAxis(vtkAxis::LEFT)->SetTitle(leftColumn);
  if (rightColumn) {
    vtkPlot* right = chart->AddPlot(vtkChart::LINE);
    right->SetInputData(this->History, "time_s", rightColumn);
    right->SetColor(200, 60, 40, 255);
    chart->SetPlotCorner(right, 1); // right axis: N mm beside N
    chart->GetAxis(vtkAxis::RIGHT)->SetTitle(rightColumn);
  }
  this->ChartsLayout->addWidget(widget);
  return widget;
}

void qBMPanelPrivate::initCharts() {
  for (const char* name : kHistoryColumns) {
    vtkNew<vtkDoubleArray> column;
    column->SetName(name);
    this->History->AddColumn(column);
  }
  this->ForceChartWidget = this->addChart(this->ForceChart, this->ForceView,
                                          "Thrust (N) and torque (N mm)", "thrust_N", "torque_Nmm");
  this->ForceChartWidget->setObjectName("ForceChartWidget");
  this->FrameChartWidget = this->addChart(this->FrameChart, this->FrameView,
                                          "Haptic frame time (ms)", "frame_ms", nullptr);
  this->FrameChartWidget->setObjectName("FrameChartWidget");
  this->renderCharts();
}

void qBMPanelPrivate::renderCharts() {
  // A line needs two points: the plots stay hidden until the history has them.
  const bool drawable = this->History->GetNumberOfRows() >= 2;
  for (vtkChartXY* chart : {this->ForceChart.GetPointer(), this->FrameChart.GetPointer()}) {
    for (vtkIdType i = 0; i < chart->GetNumberOfPlots(); ++i)
      chart->GetPlot(i)->SetVisible(drawable);
    if (drawable)
      chart->RecalculateBounds();
  }
  for (QVTKOpenGLNativeWidget* widget : {this->ForceChartWidget, this->FrameChartWidget})
    if (widget->isVisible())
      widget->renderWindow()->Render();
}

void qBMPanelPrivate::updateSummary() {
  Q_Q(qBMPanel);
  this->ToolSummaryLabel->setText(q->toolSummary());
}

void qBMPanelPrivate::rebuildParameterEditors() {
  Q_Q(qBMPanel);
  for (const auto& editor : this->ParameterEditors) {
    this->ToolParametersLayout->removeRow(editor.second);
  }
  this->ParameterEditors.clear();
  this->Logic->SetParameters(nullptr); // the type's defaults
  const QJsonObject spec =
      QJsonDocument::fromJson(QByteArray(this->Logic->GetToolSpecification())).object();
  for (auto it = spec.begin(); it != spec.end(); ++it) {
    if (it.key() == QLatin1String("type") || !it.value().isDouble())
      continue;
    QWidget* editor = nullptr;
    if (it.key() == QLatin1String("lips")) {
      auto* box = new QSpinBox(this->ToolParametersWidget);
      box->setRange(0, 64);
      box->setValue(it.value().toInt());
      QObject::connect(box, QOverload<int>::of(&QSpinBox::valueChanged), q,
                       [this]() { this->applyParameters(); });
      editor = box;
    } else {
      auto* box = new QDoubleSpinBox(this->ToolParametersWidget);
      box->setRange(-1000.0, 1000.0);
      box->setDecimals(3);
      box->setSingleStep(0.1);
      box->setValue(it.value().toDouble());
      QObject::connect(box, QOverload<double>::of(&QDoubleSpinBox::valueChanged), q,
                       [this]() { this->applyParameters(); });
      editor = box;
    }
    editor->setObjectName(it.key());
    editor->setToolTip(qBMPanel::parameterToolTip(it.key()));
    auto* label = new QLabel(qBMPanel::parameterLabel(it.key()) + QLatin1Char(':'),
                             this->ToolParametersWidget);
    label->setToolTip(editor->toolTip());
    this->ToolParametersLayout->addRow(label, editor);
    this->ParameterEditors.append({it.key(), editor});
  }
}

void qBMPanelPrivate::applyParameters() {
  QJsonObject params;
  for (const auto& editor : this->ParameterEditors) {
    if (auto* box = qobject_cast<QSpinBox*>(editor.second))
      params.insert(editor.first, box->value());
    else if (auto* dbox = qobject_cast<QDoubleSpinBox*>(editor.second))
      params.insert(editor.first, dbox->value());
  }
  this->Logic->SetParameters(QJsonDocument(params).toJson(QJsonDocument::Compact).constData());
  this->updateSummary();
}

void qBMPanelPrivate::updateExpectedCost() {
  Q_Q(qBMPanel);
  if (!this->Bench) {
    this->ResolutionCostLabel->setText(qBMPanel::tr("No measured costs: %1").arg(this->BenchError));
    return;
  }
  bm::Scene scene;
  try {
    const std::string name = q->sceneName().toStdString();
    const auto builtin = bm::Scene::BuiltinNames();
    scene = std::find(builtin.begin(), builtin.end(), name) != builtin.end()
                ? bm::Scene::Builtin(name)
                : bm::Scene::Load(name);
    // The resolutions a session would run at (vtkBMSessionSource: a voxmap set alone scales the
    // scene's shell alike).
    if (q->voxmapResolution() > 0 && q->shellResolution() <= 0)
      scene = scene.WithVoxmapResolution(q->voxmapResolution());
  } catch (const std::exception& e) {
    this->ResolutionCostLabel->setText(
        qBMPanel::tr("Expected cost unknown: %1").arg(QString::fromUtf8(e.what())));
    return;
  }
  const int voxmap = q->voxmapResolution() > 0 ? q->voxmapResolution() : scene.voxmapResolution;
  const int shell = q->shellResolution() > 0 ? q->shellResolution() : scene.shellResolution;
  const int m = q->method();
  const std::string method = m == vtkBMSessionSource::LAZAR   ? "lazar"
                             : m == vtkBMSessionSource::ZHENG ? "zheng"
                                                              : bm::ToString(scene.method);
  const bm::BenchmarkCell* cell = this->Bench->Nearest(method, scene.backend, shell, voxmap);
  if (!cell) {
    this->ResolutionCostLabel->setText(
        qBMPanel::tr("Expected cost unknown: no %1 / %2 cell was measured")
            .arg(QString::fromStdString(method), QString::fromStdString(scene.backend)));
    return;
  }
  this->ResolutionCostLabel->setText(
      qBMPanel::tr("Expected (%1, shell %2 / voxmap %3, nearest measured: %4 / %5): frame "
                   "%6 ms median, %7 ms p99; force error %8 %")
          .arg(QString::fromStdString(method))
          .arg(shell)
          .arg(voxmap)
          .arg(cell->shell)
          .arg(cell->voxmap)
          .arg(cell->medianMs, 0, 'g', 3)
          .arg(cell->p99Ms, 0, 'g', 3)
          .arg(cell->forceError * 100.0, 0, 'g', 2));
}

qBMPanel::qBMPanel(QWidget* parent) : Superclass(parent), d_ptr(new qBMPanelPrivate(*this)) {
  Q_D(qBMPanel);
  d->init();
}

qBMPanel::~qBMPanel() = default;

int qBMPanel::toolType() const {
  Q_D(const qBMPanel);
  return d->Logic->GetToolType();
}

int qBMPanel::resolution() const {
  Q_D(const qBMPanel);
  return d->Logic->GetResolution();
}

QString qBMPanel::toolSummary() const {
  Q_D(const qBMPanel);
  vtkBMToolSource* logic = d->Logic;
  if (!logic->GetToolIsValid())
    return tr("Invalid tool parameters: %1").arg(QString::fromUtf8(logic->GetToolError()));
  double range[2];
  logic->GetAxialRange(range);
  return tr("%1 lips, outer radius %2 mm, length %3 mm")
      .arg(logic->GetNumberOfLips())
      .arg(logic->GetOuterRadius(), 0, 'f', 2)
      .arg(range[1] - range[0], 0, 'f', 2);
}

QString qBMPanel::toolSpecification() const {
  Q_D(const qBMPanel);
  return QString::fromUtf8(d->Logic->GetToolSpecification());
}

void qBMPanel::setToolType(int type) {
  Q_D(qBMPanel);
  if (type < vtkBMToolSource::DRILL || type > vtkBMToolSource::BURR || type == toolType())
    return;
  d->Logic->SetToolType(type);
  const QSignalBlocker blocker(d->ToolTypeComboBox);
  d->ToolTypeComboBox->setCurrentIndex(type);
  d->rebuildParameterEditors();
  d->updateSummary();
  Q_EMIT toolTypeChanged(type);
}

bool qBMPanel::setToolParameter(const QString& key, double value) {
  Q_D(qBMPanel);
  for (const auto& editor : d->ParameterEditors)
    if (editor.first == key) {
      if (auto* box = qobject_cast<QSpinBox*>(editor.second))
        box->setValue(int(value));
      else if (auto* dbox = qobject_cast<QDoubleSpinBox*>(editor.second))
        dbox->setValue(value);
      return true;
    }
  return false;
}

QString qBMPanel::statusMessage() const {
  Q_D(const qBMPanel);
  return d->StatusLabel->text();
}

void qBMPanel::setStatusMessage(const QString& message) {
  Q_D(qBMPanel);
  d->StatusLabel->setText(message);
}

void qBMPanel::setResolution(int facets) {
  Q_D(qBMPanel);
  d->Logic->SetResolution(facets);
  const QSignalBlocker blocker(d->ResolutionSpinBox);
  d->ResolutionSpinBox->setValue(d->Logic->GetResolution());
}

QString qBMPanel::sceneName() const {
  Q_D(const qBMPanel);
  return d->SceneComboBox->currentText();
}

int qBMPanel::voxmapResolution() const {
  Q_D(const qBMPanel);
  return d->VoxmapResolutionSpinBox->value();
}

int qBMPanel::shellResolution() const {
  Q_D(const qBMPanel);
  return d->ShellResolutionSpinBox->value();
}

int qBMPanel::deviceType() const {
  Q_D(const qBMPanel);
  return d->DeviceComboBox->currentData().toInt();
}

double qBMPanel::toolDepth() const {
  Q_D(const qBMPanel);
  return d->ToolDepthSpinBox->value();
}

bool qBMPanel::useChosenTool() const {
  Q_D(const qBMPanel);
  return d->UseToolCheckBox->isChecked();
}

int qBMPanel::method() const {
  Q_D(const qBMPanel);
  return d->MethodComboBox->currentData().toInt();
}

QString qBMPanel::withVoxmapExtension(const QString& path, const QString& defaultSuffix) {
  // Only a name with no extension at all gets one: another extension is the user's choice, and
  // the save refuses it naming the formats.
  if (path.isEmpty() || !QFileInfo(path).suffix().isEmpty())
    return path;
  return path + "." + defaultSuffix;
}

QString qBMPanel::parameterLabel(const QString& key) {
  static const QList<QPair<QString, QString>> units = {
      {"_mm", "mm"}, {"_deg", "deg"}, {"_rpm", "rpm"}, {"_n", "N"}};
  QString words = key, unit;
  for (const auto& u : units)
    if (words.endsWith(u.first)) {
      words.chop(u.first.size());
      unit = u.second;
      break;
    }
  words.replace(QLatin1Char('_'), QLatin1Char(' '));
  if (!words.isEmpty())
    words[0] = words[0].toUpper();
  return unit.isEmpty() ? words : QString("%1 (%2)").arg(words, unit);
}

QString qBMPanel::parameterToolTip(const QString& key) {
  static const QHash<QString, const char*> tips = {
      {"alpha_deg", QT_TR_NOOP("Angle of the reamer's lips to the face, deg")},
      {"arc_centre_offset_mm", QT_TR_NOOP("Distance of the lip arc's centre from the axis, mm")},
      {"arc_radius_mm", QT_TR_NOOP("Radius of the lips' arc, mm")},
      {"chisel_angle_deg", QT_TR_NOOP("Drill chisel edge angle, deg")},
      {"flute_length_mm", QT_TR_NOOP("Length of the drill's flutes, mm")},
      {"head_thickness_mm", QT_TR_NOOP("Axial thickness of the reamer head behind its rim, mm")},
      {"helix_angle_deg", QT_TR_NOOP("Drill helix angle, deg")},
      {"lips", QT_TR_NOOP("Number of cutting lips (flutes)")},
      {"nipple_length_mm",
       QT_TR_NOOP("How far the guide nipple reaches beyond the face, mm (0 = no nipple)")},
      {"nipple_radius_mm", QT_TR_NOOP("Radius of the central guide nipple, mm (0 = none)")},
      {"outer_radius_mm", QT_TR_NOOP("Outer radius where the lips end, mm (half the diameter)")},
      {"point_angle_deg", QT_TR_NOOP("Drill point angle, deg")},
      {"radius_mm", QT_TR_NOOP("Burr radius, mm")},
      {"rake_deg", QT_TR_NOOP("Normal rake angle of the lips, deg")},
      {"shaft_length_mm", QT_TR_NOOP("Modelled length of the shaft behind the head, mm")},
      {"shaft_radius_mm", QT_TR_NOOP("Radius of the shaft, mm")},
      {"web_half_width_mm", QT_TR_NOOP("Half the drill's web thickness at the point, mm")}};
  const auto it = tips.find(key);
  return it != tips.end() ? tr(it.value()) : tr("Tool parameter: %1").arg(parameterLabel(key));
}

QString qBMPanel::boneFile() const {
  Q_D(const qBMPanel);
  return d->BoneFileLineEdit->text();
}

bool qBMPanel::startFromBoneFile() const {
  Q_D(const qBMPanel);
  return d->StartFromFileCheckBox->isChecked();
}

bool qBMPanel::volumeRendering() const {
  Q_D(const qBMPanel);
  return d->VolumeCheckBox->isChecked();
}

QString qBMPanel::expectedCost() const {
  Q_D(const qBMPanel);
  return d->ResolutionCostLabel->text();
}

QString qBMPanel::touchStatus() const {
  Q_D(const qBMPanel);
  return d->TouchStatus;
}

void qBMPanel::setVoxmapResolution(int cells) {
  Q_D(qBMPanel);
  d->VoxmapResolutionSpinBox->setValue(cells);
}

void qBMPanel::setShellResolution(int cells) {
  Q_D(qBMPanel);
  d->ShellResolutionSpinBox->setValue(cells);
}

void qBMPanel::setDeviceType(int type) {
  Q_D(qBMPanel);
  const int index = d->DeviceComboBox->findData(type);
  if (index >= 0)
    d->DeviceComboBox->setCurrentIndex(index);
}

void qBMPanel::setMethod(int method) {
  Q_D(qBMPanel);
  const int index = d->MethodComboBox->findData(method);
  if (index >= 0)
    d->MethodComboBox->setCurrentIndex(index);
}

void qBMPanel::setUseChosenTool(bool use) {
  Q_D(qBMPanel);
  d->UseToolCheckBox->setChecked(use);
}

void qBMPanel::setBoneFile(const QString& path) {
  Q_D(qBMPanel);
  d->BoneFileLineEdit->setText(path);
}

void qBMPanel::setStartFromBoneFile(bool start) {
  Q_D(qBMPanel);
  d->StartFromFileCheckBox->setChecked(start);
}

void qBMPanel::setVolumeRendering(bool on) {
  Q_D(qBMPanel);
  d->VolumeCheckBox->setChecked(on);
}

void qBMPanel::setHistory(vtkTable* history) {
  Q_D(qBMPanel);
  vtkTable* table = d->History;
  for (const char* name : kHistoryColumns) {
    auto* mine = vtkDoubleArray::SafeDownCast(table->GetColumnByName(name));
    vtkDataArray* theirs =
        history ? vtkDataArray::SafeDownCast(history->GetColumnByName(name)) : nullptr;
    if (theirs)
      mine->DeepCopy(theirs);
    else
      mine->SetNumberOfTuples(0);
    mine->SetName(name);
  }
  table->Modified();
  d->renderCharts();
}

void qBMPanel::setSessionNumbers(double timeS, double depthMm, double removedMm3, double thrustN,
                                 double torqueNmm, double frameP99Ms) {
  Q_D(qBMPanel);
  d->SessionNumbersLabel->setText(
      tr("t %1 s, depth %2 mm, removed %3 mm^3\nthrust %4 N, torque %5 N mm, haptic frame p99 "
         "%6 ms")
          .arg(timeS, 0, 'f', 2)
          .arg(depthMm, 0, 'f', 2)
          .arg(removedMm3, 0, 'f', 1)
          .arg(thrustN, 0, 'f', 1)
          .arg(torqueNmm, 0, 'f', 0)
          .arg(frameP99Ms, 0, 'f', 2));
}

void qBMPanelPrivate::showPaused(bool paused) {
  const QSignalBlocker blocker(this->PauseButton);
  this->PauseButton->setChecked(paused);
  this->PauseButton->setText(paused ? qBMPanel::tr("Resume") : qBMPanel::tr("Pause"));
  this->PauseButton->setToolTip(paused ? qBMPanel::tr("Resume the paused session")
                                       : qBMPanel::tr("Pause the session (zero force on the "
                                                      "device; the cut is kept)"));
}

void qBMPanel::setSessionState(const QString& state) {
  Q_D(qBMPanel);
  d->SessionStateLabel->setText(state.isEmpty() ? QString() : tr("Session %1").arg(state));
  // A session that paused itself (overrun, device fault, end of a trial) reads Resume too.
  if (state.startsWith(tr("paused")))
    d->showPaused(true);
  else if (state == tr("running") || state == tr("stopped") || state.isEmpty())
    d->showPaused(false);
}

void qBMPanel::setSessionStatus(const QString& message, bool running) {
  Q_D(qBMPanel);
  d->SessionStatusLabel->setText(message);
  d->StartButton->setEnabled(!running);
  d->PauseButton->setEnabled(running);
  d->StopButton->setEnabled(running);
  if (!running)
    d->showPaused(false);
}

QString qBMPanel::ctFileName() const {
  Q_D(const qBMPanel);
  return d->CTFileLineEdit->text();
}

double qBMPanel::thresholdHU() const {
  Q_D(const qBMPanel);
  return d->ThresholdSpinBox->value();
}

QVector<double> qBMPanel::roi() const {
  Q_D(const qBMPanel);
  QVector<double> box;
  for (QDoubleSpinBox* spin : d->roiBoxes())
    box.append(spin->value());
  return box;
}

int qBMPanel::ctResolution() const {
  Q_D(const qBMPanel);
  return d->CTResolutionSpinBox->value();
}

QVector<double> qBMPanel::axis() const {
  Q_D(const qBMPanel);
  QVector<double> v;
  for (QDoubleSpinBox* spin : d->axisBoxes())
    v.append(spin->value());
  return v;
}

QVector<double> qBMPanel::entry() const {
  Q_D(const qBMPanel);
  QVector<double> v;
  for (QDoubleSpinBox* spin : d->entryBoxes())
    v.append(spin->value());
  return v;
}

bool qBMPanel::useCTBone() const {
  Q_D(const qBMPanel);
  return d->UseCTCheckBox->isChecked();
}

void qBMPanel::setCTFileName(const QString& path) {
  Q_D(qBMPanel);
  d->CTFileLineEdit->setText(path);
}

void qBMPanel::setThresholdHU(double hu) {
  Q_D(qBMPanel);
  d->ThresholdSpinBox->setValue(hu);
}

void qBMPanel::setRoi(const QVector<double>& box) {
  Q_D(qBMPanel);
  const auto spins = d->roiBoxes();
  for (int i = 0; i < spins.size() && i < box.size(); ++i)
    spins[i]->setValue(box[i]);
}

void qBMPanel::setAxis(const QVector<double>& axis) {
  Q_D(qBMPanel);
  const auto spins = d->axisBoxes();
  for (int i = 0; i < spins.size() && i < axis.size(); ++i)
    spins[i]->setValue(axis[i]);
}

void qBMPanel::setEntry(const QVector<double>& entry) {
  Q_D(qBMPanel);
  const auto spins = d->entryBoxes();
  for (int i = 0; i < spins.size() && i < entry.size(); ++i)
    spins[i]->setValue(entry[i]);
}

void qBMPanel::setUseCTBone(bool use) {
  Q_D(qBMPanel);
  d->UseCTCheckBox->setChecked(use);
}

void qBMPanel::setCTPreview(qint64 boneVoxels, double boneVolumeMm3, const QVector<double>& bounds,
                            const QVector<double>& suggestedEntry, const QString& error) {
  Q_D(qBMPanel);
  if (!error.isEmpty() || bounds.size() < 6 || suggestedEntry.size() < 3) {
    d->SuggestedEntry.clear();
    d->UseSuggestedEntryButton->setEnabled(false);
    d->CTSummaryLabel->setText(tr("No CT bone: %1").arg(error));
    return;
  }
  d->SuggestedEntry = suggestedEntry;
  d->UseSuggestedEntryButton->setEnabled(true);
  d->CTSummaryLabel->setText(
      tr("Bone: %1 voxels, %2 mm^3 in [%3, %4] x [%5, %6] x [%7, %8] mm; suggested entry "
         "(%9, %10, %11) mm")
          .arg(boneVoxels)
          .arg(boneVolumeMm3, 0, 'f', 1)
          .arg(bounds[0], 0, 'f', 1)
          .arg(bounds[1], 0, 'f', 1)
          .arg(bounds[2], 0, 'f', 1)
          .arg(bounds[3], 0, 'f', 1)
          .arg(bounds[4], 0, 'f', 1)
          .arg(bounds[5], 0, 'f', 1)
          .arg(suggestedEntry[0], 0, 'f', 2)
          .arg(suggestedEntry[1], 0, 'f', 2)
          .arg(suggestedEntry[2], 0, 'f', 2));
}
