// The CT section's PACS study browser (qBMPacsBrowser) against a real Orthanc on loopback
// (bmOrthancProcess.h) holding a small CT series: the server typed, Find clicked, the row's
// patient, study date, accession, description, modality and instances shown; Fetch puts the series
// in the per-user cache (<cache>/pacs/<Series Instance UID>) and makes that folder the CT path,
// as a chosen folder would; a second Fetch reuses the folder. The same over DICOMweb into another
// folder. A server that is down, and one that stopped after Find, give a status line naming the
// server and leave no folder; a silent server (a socket that never answers) keeps the GUI thread
// turning (a QTimer ticks while the request waits) with Find and Fetch disabled; a CT section
// destroyed while its request waits does not crash. A Qt program under Xvfb; a failed check ends
// it with status 1.
#include "bmOrthancProcess.h"
#include "bmCTImage.h"
#include "bmDicomSeriesWriter.h"
#include "bmPacsConnection.h"
#include "qBMCTWidget.h"
#include "qBMPacsBrowser.h"

#include <dcmtk/config/osconfig.h>

#include <dcmtk/dcmdata/dcdeftag.h>
#include <dcmtk/dcmdata/dcfilefo.h>

#include <QApplication>
#include <QElapsedTimer>
#include <QEventLoop>
#include <QLabel>
#include <QLineEdit>
#include <QPushButton>
#include <QTableWidget>
#include <QTimer>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {
int failures = 0;
const auto kStart = std::chrono::steady_clock::now();
void Expect(bool ok, const std::string& what) {
  std::printf("%5.1f s %s: %s\n",
              std::chrono::duration<double>(std::chrono::steady_clock::now() - kStart).count(),
              ok ? "ok" : "FAIL", what.c_str());
  std::fflush(stdout);
  failures += ok ? 0 : 1;
}

bool Has(const QString& text, const std::string& part) {
  return text.contains(QString::fromStdString(part));
}

// 16 x 12 x 10 voxels of 1 mm: a CT series of 10 instances.
bm::CTImage SmallCT() {
  bm::CTImage ct;
  ct.hu = bm::HUImage::New();
  bm::HUImage::RegionType region;
  region.SetSize({{16, 12, 10}});
  ct.hu->SetRegions(region);
  bm::HUImage::SpacingType spacing;
  spacing.Fill(1.0);
  ct.hu->SetSpacing(spacing);
  ct.hu->Allocate();
  float* v = ct.hu->GetBufferPointer();
  for (size_t i = 0; i < 16 * 12 * 10; ++i)
    v[i] = float(int(i % 1500) - 500);
  return ct;
}
constexpr int kInstances = 10;

/// The series' files with an accession number and study date, as a hospital's would carry.
std::vector<std::string> SeriesFiles(const fs::path& folder) {
  std::vector<std::string> files;
  for (const auto& e : fs::directory_iterator(folder)) {
    DcmFileFormat f;
    if (f.loadFile(e.path().string().c_str()).bad())
      continue;
    f.loadAllDataIntoMemory(); // written back to the same path
    f.getDataset()->putAndInsertString(DCM_AccessionNumber, "BM-ACC-7");
    f.getDataset()->putAndInsertString(DCM_StudyDate, "20240315");
    f.saveFile(e.path().string().c_str(), EXS_LittleEndianExplicit);
    files.push_back(e.path().string());
  }
  std::sort(files.begin(), files.end());
  return files;
}

int FileCount(const fs::path& folder) {
  std::error_code ec;
  if (!fs::is_directory(folder, ec))
    return -1;
  return int(std::distance(fs::directory_iterator(folder), fs::directory_iterator()));
}

/// Waits, turning the event loop, until the browser has ended `n` requests since the test began
/// counting, or `deadlineMs` passed. Returns whether it ended them.
class RequestCounter : public QObject {
public:
  explicit RequestCounter(qBMPacsBrowser* browser) {
    QObject::connect(browser, &qBMPacsBrowser::requestFinished, this, [this]() {
      ++this->Ended;
      this->Loop.quit();
    });
  }
  bool WaitFor(int n, int deadlineMs) {
    QElapsedTimer clock;
    clock.start();
    while (this->Ended < n && clock.elapsed() < deadlineMs) {
      QTimer::singleShot(int(std::max<qint64>(1, deadlineMs - clock.elapsed())), &this->Loop,
                         &QEventLoop::quit);
      this->Loop.exec();
    }
    return this->Ended >= n;
  }
  int Ended = 0;

private:
  QEventLoop Loop;
};

struct Browser {
  explicit Browser(qBMCTWidget& ct) : Dialog(ct.pacsBrowser()), Requests(ct.pacsBrowser()) {
    Server = Dialog->findChild<QLineEdit*>("ServerLineEdit");
    PatientId = Dialog->findChild<QLineEdit*>("PatientIdLineEdit");
    PatientName = Dialog->findChild<QLineEdit*>("PatientNameLineEdit");
    Accession = Dialog->findChild<QLineEdit*>("AccessionLineEdit");
    Folder = Dialog->findChild<QLineEdit*>("FolderLineEdit");
    Find = Dialog->findChild<QPushButton*>("FindButton");
    Fetch = Dialog->findChild<QPushButton*>("FetchButton");
    Results = Dialog->findChild<QTableWidget*>("ResultsTable");
    Status = Dialog->findChild<QLabel*>("StatusLabel");
  }
  bool Complete() const {
    return Server && PatientId && PatientName && Accession && Folder && Find && Fetch && Results &&
           Status;
  }
  QString Cell(int column) const {
    const QTableWidgetItem* item = Results->item(0, column);
    return item ? item->text() : QString();
  }
  qBMPacsBrowser* Dialog;
  RequestCounter Requests;
  QLineEdit *Server = nullptr, *PatientId = nullptr, *PatientName = nullptr, *Accession = nullptr,
            *Folder = nullptr;
  QPushButton *Find = nullptr, *Fetch = nullptr;
  QTableWidget* Results = nullptr;
  QLabel* Status = nullptr;
};

/// Find on `server` with the query given, then checks the one row against the series.
void FindTheSeries(Browser& b, const std::string& server, const QString& patientId,
                   const QString& patientName, const QString& accession, const char* face) {
  const std::string f = std::string(face) + ": ";
  b.Server->setText(QString::fromStdString(server));
  b.PatientId->setText(patientId);
  b.PatientName->setText(patientName);
  b.Accession->setText(accession);
  const int before = b.Requests.Ended;
  b.Find->click();
  Expect(!b.Find->isEnabled() && !b.Fetch->isEnabled() && b.Status->text().startsWith("Finding"),
         f + "while Find runs its buttons are disabled and the status says so (" +
             b.Status->text().toStdString() + ")");
  Expect(b.Requests.WaitFor(before + 1, 20000), f + "Find ends");
  Expect(b.Find->isEnabled(), f + "Find is enabled again");
  Expect(b.Results->rowCount() == 1, f + "one series found (" +
                                         std::to_string(b.Results->rowCount()) + " rows; " +
                                         b.Status->text().toStdString() + ")");
  if (b.Results->rowCount() != 1)
    return;
  Expect(b.Cell(0) == "Pacs^Test (BM-PACS-1)", f + "patient: " + b.Cell(0).toStdString());
  Expect(b.Cell(1) == "2024-03-15", f + "study date: " + b.Cell(1).toStdString());
  Expect(b.Cell(2) == "BM-ACC-7", f + "accession: " + b.Cell(2).toStdString());
  Expect(b.Cell(3) == "Pacs browser CT", f + "series description: " + b.Cell(3).toStdString());
  Expect(b.Cell(4) == "CT", f + "modality: " + b.Cell(4).toStdString());
  Expect(b.Cell(5) == QString::number(kInstances), f + "instances: " + b.Cell(5).toStdString());
}

/// Selects the row, clicks Fetch and waits.
void FetchTheSeries(Browser& b, const char* face) {
  b.Results->selectRow(0);
  Expect(b.Fetch->isEnabled(), std::string(face) + ": Fetch is enabled with a row selected");
  const int before = b.Requests.Ended;
  b.Fetch->click();
  Expect(!b.Find->isEnabled() && !b.Fetch->isEnabled() && b.Status->text().startsWith("Fetching"),
         std::string(face) +
             ": while Fetch runs its buttons are disabled and the status says so (" +
             b.Status->text().toStdString() + ")");
  Expect(b.Requests.WaitFor(before + 1, 20000), std::string(face) + ": Fetch ends");
}
} // namespace

int main(int argc, char* argv[]) {
  const auto started = std::chrono::steady_clock::now();
  const fs::path dir = fs::temp_directory_path() / ("bm-panel-pacs-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  // The per-user cache (QStandardPaths::CacheLocation) inside the test's folder.
  qputenv("XDG_CACHE_HOME", QByteArray::fromStdString((dir / "cache").string()));
  QApplication app(argc, argv);
  QApplication::setOrganizationName("BMTest");
  QApplication::setApplicationName("PanelPacs");
  const fs::path cache = dir / "cache" / "BMTest" / "PanelPacs" / "pacs";

  const bool dicomWeb = ::access(bmtest::OrthancProcess::kDicomWebPlugin, R_OK) == 0;
  if (!dicomWeb)
    std::printf("skipped: DICOMweb (%s is not installed)\n",
                bmtest::OrthancProcess::kDicomWebPlugin);
  try {
    bmtest::OrthancProcess orthanc(dir / "orthanc", dicomWeb);
    const std::string dimse = "ORTHANC@127.0.0.1:" + std::to_string(orthanc.Port);
    bm::DicomWriteOptions wo;
    wo.patientID = "BM-PACS-1";
    wo.patientName = "Pacs^Test";
    wo.seriesDescription = "Pacs browser CT";
    const std::string uid = bm::WriteDicomSeries(SmallCT(), (dir / "ct").string(), wo);
    bm::PacsConnection(dimse).StoreFiles(SeriesFiles(dir / "ct"));

    qBMCTWidget ct;
    ct.show();
    Expect(ct.pacsBrowser() != nullptr, "a build with DCMTK has the PACS browser");
    auto* fromPacs = ct.findChild<QPushButton*>("FromPacsButton");
    Expect(fromPacs != nullptr, "the CT section has From PACS...");
    if (!ct.pacsBrowser() || !fromPacs)
      return 1;
    fromPacs->click();
    Expect(ct.pacsBrowser()->isVisible(), "From PACS... opens the browser");
    Browser b(ct);
    Expect(b.Complete(), "the browser's fields, buttons, table and status line are named");
    if (!b.Complete())
      return 1;
    Expect(!b.Fetch->isEnabled(), "Fetch is disabled before anything is found");
    Expect(b.Folder->text().toStdString() == cache.string(),
           "the default folder is the per-user cache's pacs folder: " +
               b.Folder->text().toStdString());

    // DIMSE: found by a wildcard patient ID, fetched into the cache, then reused.
    FindTheSeries(b, dimse, "BM-PACS-*", "", "", "DIMSE");
    FetchTheSeries(b, "DIMSE");
    const fs::path cached = cache / uid;
    Expect(ct.ctFileName().toStdString() == cached.string(),
           "DIMSE: the CT path is the fetched folder: " + ct.ctFileName().toStdString());
    Expect(FileCount(cached) == kInstances, "DIMSE: the folder holds the series' " +
                                                std::to_string(kInstances) + " instances (" +
                                                std::to_string(FileCount(cached)) + ")");
    Expect(Has(b.Status->text(), "Fetched " + std::to_string(kInstances)) &&
               Has(b.Status->text(), dimse),
           "DIMSE: the status says what was fetched from where: " + b.Status->text().toStdString());
    ct.setCTFileName("");
    FetchTheSeries(b, "DIMSE again");
    Expect(b.Status->text().contains("reused") &&
               ct.ctFileName().toStdString() == cached.string() && FileCount(cached) == kInstances,
           "DIMSE: a folder that holds the series whole is reused: " +
               b.Status->text().toStdString());

    // DICOMweb: found by patient name and accession, fetched into another folder.
    if (dicomWeb) {
      b.Folder->setText(QString::fromStdString((dir / "web").string()));
      // (Orthanc's DICOMweb plugin 1.7 does not decode a percent-escaped '^' in a query.)
      FindTheSeries(b, orthanc.WebUrl + "/", "", "Pacs*", "BM-ACC-7", "DICOMweb");
      FetchTheSeries(b, "DICOMweb");
      const fs::path web = dir / "web" / uid;
      Expect(ct.ctFileName().toStdString() == web.string() && FileCount(web) == kInstances,
             "DICOMweb: the CT path is the fetched folder with " + std::to_string(kInstances) +
                 " instances: " + ct.ctFileName().toStdString() + " (" +
                 std::to_string(FileCount(web)) + ")");
    }

    // A server that is down: named, nothing listed.
    const std::string down = "ORTHANC@127.0.0.1:" + std::to_string(bmtest::FreeLoopbackPort());
    b.Server->setText(QString::fromStdString(down));
    b.PatientName->clear();
    b.Accession->clear();
    int before = b.Requests.Ended;
    b.Find->click();
    Expect(b.Requests.WaitFor(before + 1, 20000), "down: Find ends");
    Expect(b.Status->text().startsWith("Failed") && Has(b.Status->text(), down) &&
               b.Results->rowCount() == 0,
           "down: the status names the server and why, nothing listed: " +
               b.Status->text().toStdString());

    // A silent server: the request waits for its 2 s timeout off the GUI thread.
    {
      int port = 0;
      const int fd = bmtest::LoopbackSocket(port, true);
      const std::string silent = "ORTHANC@127.0.0.1:" + std::to_string(port);
      ct.pacsBrowser()->setTimeoutS(2);
      b.Server->setText(QString::fromStdString(silent));
      int ticks = 0;
      int ticksWhileBusy = 0;
      QTimer ticker;
      QObject::connect(&ticker, &QTimer::timeout, [&]() {
        ++ticks;
        if (ct.pacsBrowser()->isBusy() && !b.Find->isEnabled())
          ++ticksWhileBusy;
      });
      ticker.start(20);
      before = b.Requests.Ended;
      b.Find->click();
      Expect(ct.pacsBrowser()->isBusy() && Has(b.Status->text(), silent),
             "silent: the request runs and the status names the server: " +
                 b.Status->text().toStdString());
      Expect(b.Requests.WaitFor(before + 1, 20000), "silent: Find ends at the timeout");
      ticker.stop();
      Expect(ticksWhileBusy >= 5, "silent: the GUI thread turned while the request waited (" +
                                      std::to_string(ticksWhileBusy) + " ticks while busy, " +
                                      std::to_string(ticks) + " in all)");
      Expect(b.Status->text().startsWith("Failed") && Has(b.Status->text(), silent),
             "silent: the status names the server and why: " + b.Status->text().toStdString());

      // A CT section destroyed while its request waits: the destructor waits for the request.
      auto* closing = new qBMCTWidget;
      closing->pacsBrowser()->setServer(QString::fromStdString(silent));
      closing->pacsBrowser()->setTimeoutS(1);
      closing->pacsBrowser()->find();
      Expect(closing->pacsBrowser()->isBusy(), "closing: a request runs");
      delete closing;
      QCoreApplication::processEvents();
      Expect(true, "closing: a CT section destroyed during a request does not crash");
      ::close(fd);
    }

    // A server that stops after Find: Fetch names it and leaves no folder.
    const fs::path stopped = dir / "stopped";
    b.Folder->setText(QString::fromStdString(stopped.string()));
    ct.pacsBrowser()->setTimeoutS(5);
    FindTheSeries(b, dimse, "BM-PACS-1", "", "", "stopped");
    orthanc.Stop();
    const QString ctBefore = ct.ctFileName();
    if (b.Results->rowCount() == 1) {
      FetchTheSeries(b, "stopped");
      Expect(b.Status->text().startsWith("Failed") && Has(b.Status->text(), dimse),
             "stopped: the status names the server and why: " + b.Status->text().toStdString());
      Expect(!fs::exists(stopped / uid) && ct.ctFileName() == ctBefore,
             "stopped: no folder is left and the CT path is unchanged");
    }
  } catch (const std::exception& e) {
    Expect(false, std::string("unexpected error: ") + e.what());
  }
  fs::remove_all(dir);
  std::printf("%d failure(s), %.1f s\n", failures,
              std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count());
  return failures == 0 ? 0 : 1;
}
