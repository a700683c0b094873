// qBMToolWidget.cxx - see qBMToolWidget.h.
#include "qBMToolWidget.h"

#include "ui_qBMToolWidget.h"

#include "bmPanelLogic.h"
#include "vtkBMToolSource.h"
#include "vtkNew.h"

#include <QDoubleSpinBox>
#include <QJsonDocument>
#include <QJsonObject>
#include <QLabel>
#include <QList>
#include <QPair>
#include <QSpinBox>

class qBMToolWidgetPrivate : public Ui_qBMToolWidget {
  Q_DECLARE_PUBLIC(qBMToolWidget);

public:
  explicit qBMToolWidgetPrivate(qBMToolWidget& object) : q_ptr(&object) {}
  void init();
  /// One editor per parameter of the chosen tool type, at the logic's (default) values.
  void rebuildParameterEditors();
  /// Hands the editors' values to the logic as the tool's parameters.
  void applyParameters();
  void updateSummary() { this->ToolSummaryLabel->setText(this->q_ptr->toolSummary()); }

  qBMToolWidget* const q_ptr;
  /// The logic the section is bound to: holds the chosen tool, describes and validates it.
  vtkNew<vtkBMToolSource> Logic;
  /// Parameter editors by key (QDoubleSpinBox or QSpinBox).
  QList<QPair<QString, QWidget*>> ParameterEditors;
};

void qBMToolWidgetPrivate::init() {
  Q_Q(qBMToolWidget);
  this->setupUi(q);
  // Item order follows vtkBMToolSource::ToolTypes.
  this->ToolTypeComboBox->clear();
  this->ToolTypeComboBox->addItem(qBMToolWidget::tr("Twist drill"), int(vtkBMToolSource::DRILL));
  this->ToolTypeComboBox->addItem(qBMToolWidget::tr("Glenoid reamer"),
                                  int(vtkBMToolSource::REAMER));
  this->ToolTypeComboBox->addItem(qBMToolWidget::tr("Spherical burr"), int(vtkBMToolSource::BURR));
  this->ToolTypeComboBox->setCurrentIndex(this->Logic->GetToolType());
  this->ResolutionSpinBox->setRange(3, 1024);
  this->ResolutionSpinBox->setValue(this->Logic->GetResolution());
  QObject::connect(this->ToolTypeComboBox, QOverload<int>::of(&QComboBox::currentIndexChanged), q,
                   &qBMToolWidget::setToolType);
  QObject::connect(this->ResolutionSpinBox, QOverload<int>::of(&QSpinBox::valueChanged), q,
                   &qBMToolWidget::setResolution);
  QObject::connect(this->AddToolButton, &QPushButton::clicked, q, [this, q]() {
    // The edited parameters go with the tool; invalid ones add nothing and say why.
    if (!this->Logic->GetToolIsValid()) {
      q->setStatusMessage(qBMToolWidget::tr("Cannot add the tool: %1")
                              .arg(QString::fromUtf8(this->Logic->GetToolError())));
      return;
    }
    Q_EMIT q->addToolRequested(q->toolType(), q->resolution());
  });
  this->rebuildParameterEditors();
  this->updateSummary();
}

void qBMToolWidgetPrivate::rebuildParameterEditors() {
  Q_Q(qBMToolWidget);
  for (const auto& editor : this->ParameterEditors)
    this->ToolParametersLayout->removeRow(editor.second);
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
    const std::string key = it.key().toStdString();
    editor->setObjectName(it.key());
    editor->setToolTip(QString::fromStdString(bm::PanelLogic::ParameterToolTip(key)));
    auto* label = new QLabel(QString::fromStdString(bm::PanelLogic::ParameterLabel(key)) + ':',
                             this->ToolParametersWidget);
    label->setToolTip(editor->toolTip());
    label->setBuddy(editor);
    this->ToolParametersLayout->addRow(label, editor);
    this->ParameterEditors.append({it.key(), editor});
  }
}

void qBMToolWidgetPrivate::applyParameters() {
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

qBMToolWidget::qBMToolWidget(QWidget* parent)
    : Superclass(parent), d_ptr(new qBMToolWidgetPrivate(*this)) {
  Q_D(qBMToolWidget);
  d->init();
}

qBMToolWidget::~qBMToolWidget() = default;

int qBMToolWidget::toolType() const {
  Q_D(const qBMToolWidget);
  return d->Logic->GetToolType();
}

int qBMToolWidget::resolution() const {
  Q_D(const qBMToolWidget);
  return d->Logic->GetResolution();
}

bool qBMToolWidget::isToolValid() const {
  Q_D(const qBMToolWidget);
  return d->Logic->GetToolIsValid();
}

QString qBMToolWidget::toolSummary() const {
  Q_D(const qBMToolWidget);
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

QString qBMToolWidget::toolSpecification() const {
  Q_D(const qBMToolWidget);
  return QString::fromUtf8(d->Logic->GetToolSpecification());
}

void qBMToolWidget::setToolType(int type) {
  Q_D(qBMToolWidget);
  if (type < vtkBMToolSource::DRILL || type > vtkBMToolSource::BURR || type == toolType())
    return;
  d->Logic->SetToolType(type);
  const QSignalBlocker blocker(d->ToolTypeComboBox);
  d->ToolTypeComboBox->setCurrentIndex(type);
  d->rebuildParameterEditors();
  d->updateSummary();
  Q_EMIT toolTypeChanged(type);
}

bool qBMToolWidget::setToolParameter(const QString& key, double value) {
  Q_D(qBMToolWidget);
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

QString qBMToolWidget::statusMessage() const {
  Q_D(const qBMToolWidget);
  return d->StatusLabel->text();
}

void qBMToolWidget::setStatusMessage(const QString& message) {
  Q_D(qBMToolWidget);
  d->StatusLabel->setText(message);
}

void qBMToolWidget::setResolution(int facets) {
  Q_D(qBMToolWidget);
  d->Logic->SetResolution(facets);
  const QSignalBlocker blocker(d->ResolutionSpinBox);
  d->ResolutionSpinBox->setValue(d->Logic->GetResolution());
}
