// qBMPacsBrowser.cxx - see qBMPacsBrowser.h.
#include "qBMPacsBrowser.h"

#include "bmPacsConnection.h"
#include "bmSeriesFolder.h"

#include <QDialogButtonBox>
#include <QDir>
#include <QFileDialog>
#include <QFormLayout>
#include <QFutureWatcher>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QLabel>
#include <QLineEdit>
#include <QPushButton>
#include <QSpinBox>
#include <QStandardPaths>
#include <QTableWidget>
#include <QVBoxLayout>
#include <QtConcurrent/QtConcurrentRun>

#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

/// What a request gives back to the GUI thread: the series found, or the fetch, or why it failed.
struct Outcome {
  bool fetch = false;
  std::vector<bm::PacsSeries> series; ///< Find's rows
  bm::SeriesFetch fetched;            ///< Fetch's result
  std::string folder;                 ///< Fetch's folder
  std::string server;                 ///< the server, as errors name it
  std::string error;                  ///< empty on success
};

enum Column { kPatient, kStudyDate, kAccession, kDescription, kModality, kInstances, kColumns };

QString Text(const std::string& s) {
  return QString::fromStdString(s);
}

} // namespace

class qBMPacsBrowserPrivate {
  Q_DECLARE_PUBLIC(qBMPacsBrowser);

public:
  explicit qBMPacsBrowserPrivate(qBMPacsBrowser& object) : q_ptr(&object) {}
  void init();
  /// Runs `job` off the GUI thread; its Outcome comes back to finish().
  void start(std::function<Outcome()> job, const QString& status);
  void finish(const Outcome& outcome);
  void showResults(const std::vector<bm::PacsSeries>& series);
  void updateButtons();
  /// A line edit named for the tests, showing `hint` while empty and `tip` on hover.
  QLineEdit* lineEdit(const char* name, const QString& hint, const QString& tip) {
    auto* e = new QLineEdit(this->q_ptr);
    e->setObjectName(name);
    e->setPlaceholderText(hint);
    e->setToolTip(tip);
    return e;
  }

  qBMPacsBrowser* const q_ptr;
  QLineEdit* Server = nullptr;
  QLineEdit* CallingAet = nullptr;
  QSpinBox* Timeout = nullptr;
  QLineEdit* PatientId = nullptr;
  QLineEdit* PatientName = nullptr;
  QLineEdit* Accession = nullptr;
  QPushButton* Find = nullptr;
  QTableWidget* Results = nullptr;
  QLineEdit* Folder = nullptr;
  QPushButton* BrowseFolder = nullptr;
  QPushButton* Fetch = nullptr;
  QLabel* Status = nullptr;
  QFutureWatcher<Outcome> Watcher;
  /// From start() until its outcome is shown (GUI thread only; the watcher may say finished
  /// before its signal arrives).
  bool Busy = false;
  /// The series the table lists, and the server that listed them (Fetch asks that one).
  std::vector<bm::PacsSeries> Found;
  std::unique_ptr<bm::PacsConnection> FoundOn;
};

void qBMPacsBrowserPrivate::init() {
  Q_Q(qBMPacsBrowser);
  q->setObjectName("PacsBrowser");
  q->setWindowTitle(qBMPacsBrowser::tr("CT from PACS"));
  auto* layout = new QVBoxLayout(q);
  auto* form = new QFormLayout;
  layout->addLayout(form);
  this->Server = this->lineEdit(
      "ServerLineEdit", "ORTHANC@pacs.example.org:4242 or https://pacs.example.org/dicom-web",
      qBMPacsBrowser::tr("The PACS: its DICOM address AET@HOST:PORT (DIMSE), or its DICOMweb "
                         "root http(s)://HOST:PORT/dicom-web (QIDO-RS, WADO-RS)"));
  form->addRow(qBMPacsBrowser::tr("Server:"), this->Server);
  this->CallingAet = this->lineEdit(
      "CallingAetLineEdit", "BMSIM",
      qBMPacsBrowser::tr("Our application entity title, as the PACS knows us (DICOM address "
                         "only; register it on the PACS as a modality)"));
  this->CallingAet->setText("BMSIM");
  this->CallingAet->setMaxLength(16);
  this->Timeout = new QSpinBox(q);
  this->Timeout->setObjectName("TimeoutSpinBox");
  this->Timeout->setRange(1, 3600);
  this->Timeout->setValue(30);
  this->Timeout->setSuffix(" s");
  this->Timeout->setToolTip(
      qBMPacsBrowser::tr("How long to wait for the connection and each answer"));
  auto* aetRow = new QHBoxLayout;
  aetRow->addWidget(this->CallingAet);
  aetRow->addWidget(new QLabel(qBMPacsBrowser::tr("Timeout:"), q));
  aetRow->addWidget(this->Timeout);
  form->addRow(qBMPacsBrowser::tr("Our AET:"), aetRow);
  const QString wildcards = qBMPacsBrowser::tr("wildcards * and ? allowed; empty: any");
  this->PatientId = this->lineEdit("PatientIdLineEdit", qBMPacsBrowser::tr("any"),
                                   qBMPacsBrowser::tr("The patient's ID (%1)").arg(wildcards));
  form->addRow(qBMPacsBrowser::tr("Patient ID:"), this->PatientId);
  this->PatientName =
      this->lineEdit("PatientNameLineEdit", qBMPacsBrowser::tr("any, e.g. Smith^J*"),
                     qBMPacsBrowser::tr("The patient's name, FAMILY^GIVEN (%1)").arg(wildcards));
  form->addRow(qBMPacsBrowser::tr("Patient name:"), this->PatientName);
  this->Accession = this->lineEdit("AccessionLineEdit", qBMPacsBrowser::tr("any"),
                                   qBMPacsBrowser::tr("The study's accession number"));
  auto* findRow = new QHBoxLayout;
  findRow->addWidget(this->Accession);
  this->Find = new QPushButton(qBMPacsBrowser::tr("Find"), q);
  this->Find->setObjectName("FindButton");
  this->Find->setToolTip(qBMPacsBrowser::tr("List the CT series matching the fields above"));
  this->Find->setDefault(true);
  findRow->addWidget(this->Find);
  form->addRow(qBMPacsBrowser::tr("Accession:"), findRow);

  this->Results = new QTableWidget(0, kColumns, q);
  this->Results->setObjectName("ResultsTable");
  this->Results->setHorizontalHeaderLabels(
      {qBMPacsBrowser::tr("Patient"), qBMPacsBrowser::tr("Study date"),
       qBMPacsBrowser::tr("Accession"), qBMPacsBrowser::tr("Series"),
       qBMPacsBrowser::tr("Modality"), qBMPacsBrowser::tr("Instances")});
  this->Results->setSelectionBehavior(QAbstractItemView::SelectRows);
  this->Results->setSelectionMode(QAbstractItemView::SingleSelection);
  this->Results->setEditTriggers(QAbstractItemView::NoEditTriggers);
  this->Results->verticalHeader()->setVisible(false);
  this->Results->horizontalHeader()->setStretchLastSection(true);
  layout->addWidget(this->Results, 1);

  auto* fetchRow = new QHBoxLayout;
  fetchRow->addWidget(new QLabel(qBMPacsBrowser::tr("Fetch into:"), q));
  this->Folder = this->lineEdit(
      "FolderLineEdit", "",
      qBMPacsBrowser::tr("The series goes into a folder of its own here, named by its Series "
                         "Instance UID; a folder that already holds it whole is reused"));
  this->Folder->setText(QStandardPaths::writableLocation(QStandardPaths::CacheLocation) + "/pacs");
  fetchRow->addWidget(this->Folder, 1);
  this->BrowseFolder = new QPushButton(qBMPacsBrowser::tr("..."), q);
  this->BrowseFolder->setObjectName("BrowseFolderButton");
  fetchRow->addWidget(this->BrowseFolder);
  this->Fetch = new QPushButton(qBMPacsBrowser::tr("Fetch"), q);
  this->Fetch->setObjectName("FetchButton");
  this->Fetch->setToolTip(
      qBMPacsBrowser::tr("Fetch the selected series and make it the CT section's CT"));
  fetchRow->addWidget(this->Fetch);
  layout->addLayout(fetchRow);

  this->Status = new QLabel(q);
  this->Status->setObjectName("StatusLabel");
  this->Status->setWordWrap(true);
  this->Status->setTextInteractionFlags(Qt::TextSelectableByMouse);
  layout->addWidget(this->Status);
  auto* close = new QDialogButtonBox(QDialogButtonBox::Close, q);
  layout->addWidget(close);

  QObject::connect(close, &QDialogButtonBox::rejected, q, &QDialog::hide);
  QObject::connect(this->Find, &QPushButton::clicked, q, &qBMPacsBrowser::find);
  QObject::connect(this->Fetch, &QPushButton::clicked, q, &qBMPacsBrowser::fetchSelected);
  QObject::connect(this->Results, &QTableWidget::itemSelectionChanged, q,
                   [this]() { this->updateButtons(); });
  QObject::connect(this->BrowseFolder, &QPushButton::clicked, q, [this, q]() {
    const QString path = QFileDialog::getExistingDirectory(
        q, qBMPacsBrowser::tr("Fetch series into"), this->Folder->text());
    if (!path.isEmpty())
      this->Folder->setText(path);
  });
  QObject::connect(&this->Watcher, &QFutureWatcher<Outcome>::finished, q,
                   [this]() { this->finish(this->Watcher.result()); });
  q->resize(760, 420);
  this->updateButtons();
}

void qBMPacsBrowserPrivate::updateButtons() {
  const bool busy = this->Busy;
  this->Find->setEnabled(!busy);
  this->Fetch->setEnabled(!busy && this->FoundOn &&
                          !this->Results->selectionModel()->selectedRows().isEmpty());
}

void qBMPacsBrowserPrivate::start(std::function<Outcome()> job, const QString& status) {
  this->Status->setText(status);
  this->Busy = true;
  this->Watcher.setFuture(QtConcurrent::run([job]() {
    // The clients' errors (std::runtime_error, std::invalid_argument) name the server and why.
    try {
      return job();
    } catch (const std::exception& e) {
      Outcome failed;
      failed.error = e.what();
      return failed;
    }
  }));
  this->updateButtons();
}

void qBMPacsBrowserPrivate::finish(const Outcome& outcome) {
  Q_Q(qBMPacsBrowser);
  this->Busy = false;
  this->updateButtons();
  if (!outcome.error.empty()) {
    this->Status->setText(qBMPacsBrowser::tr("Failed: %1").arg(Text(outcome.error)));
  } else if (!outcome.fetch) {
    this->showResults(outcome.series);
    this->Status->setText(
        outcome.series.empty()
            ? qBMPacsBrowser::tr("No CT series matched on %1.").arg(Text(outcome.server))
            : qBMPacsBrowser::tr("%1 CT series on %2: select one and Fetch.")
                  .arg(outcome.series.size())
                  .arg(Text(outcome.server)));
  } else {
    const QString folder = Text(outcome.folder);
    const int n = outcome.fetched.instances;
    const QString instances =
        n == 1 ? qBMPacsBrowser::tr("1 instance") : qBMPacsBrowser::tr("%1 instances").arg(n);
    this->Status->setText(
        outcome.fetched.reused
            ? qBMPacsBrowser::tr("%1 already holds the series (%2): reused.").arg(folder, instances)
            : qBMPacsBrowser::tr("Fetched %1 from %2 into %3.")
                  .arg(instances, Text(outcome.server), folder));
    Q_EMIT q->seriesFetched(folder, outcome.fetched.instances);
  }
  Q_EMIT q->requestFinished();
}

void qBMPacsBrowserPrivate::showResults(const std::vector<bm::PacsSeries>& series) {
  this->Found = series;
  this->Results->clearSelection();
  this->Results->setRowCount(int(series.size()));
  for (int row = 0; row < int(series.size()); ++row) {
    const bm::PacsSeries& s = series[size_t(row)];
    QString date = Text(s.studyDate);
    if (date.size() == 8) // DICOM's YYYYMMDD
      date = date.left(4) + "-" + date.mid(4, 2) + "-" + date.mid(6, 2);
    const QString cells[kColumns] = {
        Text(s.patientName) + (s.patientId.empty() ? "" : " (" + Text(s.patientId) + ")"),
        date,
        Text(s.accessionNumber),
        Text(s.seriesDescription),
        Text(s.modality),
        s.instances >= 0 ? QString::number(s.instances) : QString("?")};
    for (int c = 0; c < kColumns; ++c) {
      auto* item = new QTableWidgetItem(cells[c]);
      item->setToolTip(qBMPacsBrowser::tr("Study %1\nSeries %2")
                           .arg(Text(s.studyInstanceUid), Text(s.seriesInstanceUid)));
      this->Results->setItem(row, c, item);
    }
  }
  this->Results->resizeColumnsToContents();
  if (series.size() == 1)
    this->Results->selectRow(0);
  this->updateButtons();
}

qBMPacsBrowser::qBMPacsBrowser(QWidget* parent)
    : Superclass(parent), d_ptr(new qBMPacsBrowserPrivate(*this)) {
  Q_D(qBMPacsBrowser);
  d->init();
}

qBMPacsBrowser::~qBMPacsBrowser() {
  Q_D(qBMPacsBrowser);
  // No result reaches a widget being destroyed; the request itself ends within its timeout.
  d->Watcher.disconnect();
  d->Watcher.waitForFinished();
}

QString qBMPacsBrowser::server() const {
  Q_D(const qBMPacsBrowser);
  return d->Server->text();
}

void qBMPacsBrowser::setServer(const QString& text) {
  Q_D(qBMPacsBrowser);
  d->Server->setText(text);
}

QString qBMPacsBrowser::callingAet() const {
  Q_D(const qBMPacsBrowser);
  return d->CallingAet->text();
}

void qBMPacsBrowser::setCallingAet(const QString& aet) {
  Q_D(qBMPacsBrowser);
  d->CallingAet->setText(aet);
}

int qBMPacsBrowser::timeoutS() const {
  Q_D(const qBMPacsBrowser);
  return d->Timeout->value();
}

void qBMPacsBrowser::setTimeoutS(int seconds) {
  Q_D(qBMPacsBrowser);
  d->Timeout->setValue(seconds);
}

QString qBMPacsBrowser::fetchFolder() const {
  Q_D(const qBMPacsBrowser);
  return d->Folder->text();
}

void qBMPacsBrowser::setFetchFolder(const QString& folder) {
  Q_D(qBMPacsBrowser);
  d->Folder->setText(folder);
}

int qBMPacsBrowser::seriesCount() const {
  Q_D(const qBMPacsBrowser);
  return d->Results->rowCount();
}

bool qBMPacsBrowser::isBusy() const {
  Q_D(const qBMPacsBrowser);
  return d->Busy;
}

QString qBMPacsBrowser::statusText() const {
  Q_D(const qBMPacsBrowser);
  return d->Status->text();
}

void qBMPacsBrowser::find() {
  Q_D(qBMPacsBrowser);
  if (d->Busy)
    return;
  bm::PacsServer base;
  base.timeoutS = d->Timeout->value();
  if (!d->CallingAet->text().trimmed().isEmpty())
    base.callingAet = d->CallingAet->text().trimmed().toStdString();
  std::shared_ptr<const bm::PacsConnection> pacs;
  try {
    pacs =
        std::make_shared<const bm::PacsConnection>(d->Server->text().trimmed().toStdString(), base);
  } catch (const std::exception& e) {
    d->Status->setText(tr("Failed: %1").arg(Text(e.what())));
    Q_EMIT this->requestFinished();
    return;
  }
  bm::PacsQuery query;
  query.patientId = d->PatientId->text().trimmed().toStdString();
  query.patientName = d->PatientName->text().trimmed().toStdString();
  query.accessionNumber = d->Accession->text().trimmed().toStdString();
  // The table lists what this server found; Fetch asks the same server.
  d->showResults({});
  d->FoundOn = std::make_unique<bm::PacsConnection>(*pacs);
  d->start(
      [pacs, query]() {
        Outcome outcome;
        outcome.server = pacs->Name();
        outcome.series = pacs->FindSeries(query);
        return outcome;
      },
      tr("Finding CT series on %1...").arg(Text(pacs->Name())));
}

void qBMPacsBrowser::fetchSelected() {
  Q_D(qBMPacsBrowser);
  const QModelIndexList rows = d->Results->selectionModel()->selectedRows();
  if (d->Busy || !d->FoundOn || rows.isEmpty() || rows.first().row() >= int(d->Found.size()))
    return;
  const bm::PacsSeries series = d->Found[size_t(rows.first().row())];
  const auto pacs = std::make_shared<const bm::PacsConnection>(*d->FoundOn);
  if (d->Folder->text().trimmed().isEmpty()) {
    d->Status->setText(tr("Failed: name a folder to fetch into"));
    Q_EMIT this->requestFinished();
    return;
  }
  std::string folder;
  try {
    folder = bm::SeriesFolder(QDir::cleanPath(d->Folder->text().trimmed()).toStdString(),
                              series.seriesInstanceUid);
  } catch (const std::exception& e) {
    d->Status->setText(tr("Failed: %1").arg(Text(e.what())));
    Q_EMIT this->requestFinished();
    return;
  }
  d->start(
      [pacs, series, folder]() {
        Outcome outcome;
        outcome.fetch = true;
        outcome.server = pacs->Name();
        outcome.folder = folder;
        outcome.fetched = bm::FetchSeriesInto(*pacs, series, folder);
        return outcome;
      },
      tr("Fetching %1 (%2 instances) from %3 into %4...")
          .arg(series.seriesDescription.empty() ? tr("the series") : Text(series.seriesDescription))
          .arg(series.instances >= 0 ? QString::number(series.instances) : QString("?"))
          .arg(Text(pacs->Name()), Text(folder)));
}
