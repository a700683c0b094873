// qBMPacsBrowser.h - the CT section's PACS study browser (a dialog opened by "From PACS..."):
// a server, either "AET@HOST:PORT" (DICOM's network protocol) or a DICOMweb root
// ("http(s)://HOST:PORT/dicom-web"); a query by patient ID or name (DICOM wildcards * and ?) and
// accession number; Find lists the matching CT series (patient, study date, accession, series
// description, modality, instances); Fetch brings the selected series into a folder of its own
// under "Fetch into" (default: the per-user cache, <cache>/pacs/<Series Instance UID>), or reuses
// that folder when it already holds the series whole, and says so with seriesFetched().
//
// Computes nothing: the server text is parsed, queried and fetched by bm::PacsConnection and
// bm::FetchSeriesInto (Logic/Dicom). Find and Fetch run off the GUI thread (QtConcurrent, one
// request at a time); while one runs, Find and Fetch are disabled and the status line says what
// is happening; it then shows the result or the error, which names the server and why. The
// destructor waits for a running request (bounded by the timeout). Object names (ServerLineEdit,
// PatientIdLineEdit, PatientNameLineEdit, AccessionLineEdit, TimeoutSpinBox, FindButton,
// ResultsTable, FolderLineEdit, FetchButton, StatusLabel) address it from the tests.
//
// Units: s (timeout).
#pragma once

#include <QDialog>
#include <QScopedPointer>
#include <QString>

class qBMPacsBrowserPrivate;

class qBMPacsBrowser : public QDialog {
  Q_OBJECT

public:
  using Superclass = QDialog;
  explicit qBMPacsBrowser(QWidget* parent = nullptr);
  /// Waits for a running Find or Fetch (at most about the timeout).
  ~qBMPacsBrowser() override;

  /// The server as typed: "[AET@]HOST:PORT" or a DICOMweb root. Default "".
  QString server() const;
  void setServer(const QString& text);
  /// Our application entity title for a DICOM server (as the PACS knows us). Default "BMSIM".
  QString callingAet() const;
  void setCallingAet(const QString& aet);
  /// The timeout of the connection and of each message or request, s. Default 30, range
  /// [1, 3600].
  int timeoutS() const;
  void setTimeoutS(int seconds);
  /// The folder a series is fetched under, into <folder>/<Series Instance UID>. Default
  /// QStandardPaths::CacheLocation + "/pacs".
  QString fetchFolder() const;
  void setFetchFolder(const QString& folder);
  /// The series the last Find listed (rows of the results table).
  int seriesCount() const;
  /// Whether a Find or Fetch is running.
  bool isBusy() const;
  /// The status line: what is running, the last result, or why it failed.
  QString statusText() const;

public Q_SLOTS:
  /// Starts a query for the CT series matching the query fields; returns at once.
  void find();
  /// Starts fetching the selected series; returns at once. Does nothing without a selection.
  void fetchSelected();

Q_SIGNALS:
  /// A fetch ended with the series in `folder` (`instances` files; fetched now or reused).
  void seriesFetched(const QString& folder, int instances);
  /// A Find or Fetch ended, whether it succeeded or not.
  void requestFinished();

protected:
  QScopedPointer<qBMPacsBrowserPrivate> d_ptr;

private:
  Q_DECLARE_PRIVATE(qBMPacsBrowser);
  Q_DISABLE_COPY(qBMPacsBrowser);
};
