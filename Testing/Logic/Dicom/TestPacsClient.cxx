// A PACS in the loop (bmPacsClient.h) against a real Orthanc started on loopback by the test
// (bmOrthancProcess.h): a small CT series stored (C-STORE), found by patient, study and series
// (C-FIND), fetched back whole into a new folder (C-GET) with every instance and voxel; the bone's
// Segmentation stored back beside it, found in the CT's study and fetched with its reference to
// the CT's series. Failures name the server and why, and leave nothing: a server that is down,
// one that never answers (a timeout), a wrong called AET, a calling AET the PACS does not know,
// an unknown series, a target folder that exists, a file that is not DICOM.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <dcmtk/config/osconfig.h>

#include <dcmtk/dcmdata/dcdeftag.h>
#include <dcmtk/dcmdata/dcfilefo.h>
#include <dcmtk/dcmdata/dcuid.h>

#include "bmCTImage.h"
#include "bmDicomSegmentation.h"
#include "bmDicomSeriesWriter.h"
#include "bmDicomSource.h"
#include "bmDicomWebClient.h"
#include "bmOrthancProcess.h"
#include "bmPacsClient.h"
#include "bmPacsConnection.h"
#include "bmSeriesFolder.h"

namespace fs = std::filesystem;

namespace {

fs::path Scratch(const std::string& name) {
  const fs::path d = fs::path(testing::TempDir()) / ("bm-pacs-" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

// 20 x 16 x 12 voxels of 1 mm, the voxels numbered so that a fetched series is checked voxel by
// voxel.
bm::CTImage SmallCT() {
  bm::CTImage ct;
  ct.hu = bm::HUImage::New();
  bm::HUImage::RegionType region;
  region.SetSize({{20, 16, 12}});
  ct.hu->SetRegions(region);
  bm::HUImage::SpacingType spacing;
  spacing.Fill(1.0);
  ct.hu->SetSpacing(spacing);
  bm::HUImage::PointType origin;
  origin[0] = -10;
  origin[1] = -8;
  origin[2] = 2;
  ct.hu->SetOrigin(origin);
  ct.hu->Allocate();
  float* v = ct.hu->GetBufferPointer();
  for (size_t i = 0; i < 20 * 16 * 12; ++i)
    v[i] = float(int(i % 1500) - 500);
  return ct;
}

std::string Text(DcmItem& d, const DcmTagKey& tag) {
  OFString v;
  d.findAndGetOFStringArray(tag, v);
  return v.c_str();
}

std::set<std::string> SopInstances(const fs::path& folder) {
  std::set<std::string> uids;
  for (const auto& e : fs::directory_iterator(folder)) {
    DcmFileFormat f;
    if (f.loadFile(e.path().string().c_str()).good())
      uids.insert(Text(*f.getDataset(), DCM_SOPInstanceUID));
  }
  return uids;
}

std::vector<std::string> Files(const fs::path& folder) {
  std::vector<std::string> files;
  for (const auto& e : fs::directory_iterator(folder))
    if (e.path().extension() == ".dcm")
      files.push_back(e.path().string());
  std::sort(files.begin(), files.end());
  return files;
}

template <class F> std::string Failure(F&& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

} // namespace

TEST(PacsClient, SeriesStoredFoundFetchedAndResultsStoredBeside) {
  const fs::path dir = Scratch("roundtrip");
  bmtest::OrthancProcess orthanc(dir / "orthanc");
  bm::PacsServer server;
  server.port = orthanc.Port;

  bm::DicomWriteOptions wo;
  wo.patientID = "BM-PACS-1";
  wo.patientName = "Pacs^Test";
  const bm::CTImage ct = SmallCT();
  const std::string seriesUid = bm::WriteDicomSeries(ct, (dir / "ct").string(), wo);
  const bm::DicomSource src = bm::ReadDicomSource((dir / "ct").string());
  ASSERT_EQ(src.images.size(), 12u);
  bm::StoreFiles(server, Files(dir / "ct"));

  // Found by patient, by study and by series; not by another patient.
  bm::PacsQuery byPatient;
  byPatient.patientId = "BM-PACS-1";
  const std::vector<bm::PacsSeries> found = bm::FindSeries(server, byPatient);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].seriesInstanceUid, seriesUid);
  EXPECT_EQ(found[0].studyInstanceUid, src.studyUID);
  EXPECT_EQ(found[0].modality, "CT");
  EXPECT_EQ(found[0].instances, 12);
  EXPECT_EQ(found[0].patientName, "Pacs^Test");
  bm::PacsQuery byStudy;
  byStudy.studyInstanceUid = src.studyUID;
  EXPECT_EQ(bm::FindSeries(server, byStudy).size(), 1u);
  bm::PacsQuery wildcard;
  wildcard.patientId = "BM-PACS-*";
  EXPECT_EQ(bm::FindSeries(server, wildcard).size(), 1u);
  bm::PacsQuery other;
  other.patientId = "SOMEONE-ELSE";
  EXPECT_TRUE(bm::FindSeries(server, other).empty());

  // Fetched whole: every instance, every voxel (read back as the CT reader reads a folder).
  const fs::path got = dir / "fetched";
  EXPECT_EQ(bm::GetSeries(server, "", seriesUid, got.string()), 12);
  std::set<std::string> sent;
  for (const auto& image : src.images)
    sent.insert(image.sopInstanceUID);
  EXPECT_EQ(SopInstances(got), sent);
  const bm::DicomSource back = bm::ReadDicomSource(got.string());
  EXPECT_EQ(back.seriesUID, seriesUid);
  EXPECT_EQ(back.frameOfReferenceUID, src.frameOfReferenceUID);
  for (const auto& e : fs::directory_iterator(dir)) // nothing left beside it
    EXPECT_NE(e.path().filename().string().rfind(".fetched", 0), 0u) << e.path();

  // The bone's Segmentation (a hole in a block) stored back: in the CT's study, found by its
  // modality, fetched with its reference to the CT's series.
  bm::Voxmap before({20, 16, 12}, 1.0, {-9.5, -7.5, 2.0}), after(before);
  for (int k = 2; k < 10; ++k)
    for (int j = 2; j < 14; ++j)
      for (int i = 2; i < 18; ++i) {
        before.SetFill(before.Index(i, j, k), bm::Voxmap::kFull);
        after.SetFill(after.Index(i, j, k), (i >= 8 && i < 12) ? 0 : bm::Voxmap::kFull);
      }
  const std::string seg = (dir / "reamed-bone.seg.dcm").string();
  bm::WriteReamingSegmentation(seg, src, before, after);
  bm::StoreFiles(server, {seg});
  bm::PacsQuery segs;
  segs.studyInstanceUid = src.studyUID;
  segs.modality = "SEG";
  const std::vector<bm::PacsSeries> segFound = bm::FindSeries(server, segs);
  ASSERT_EQ(segFound.size(), 1u);
  EXPECT_EQ(segFound[0].instances, 1);
  const fs::path segBack = dir / "seg-fetched";
  EXPECT_EQ(bm::GetSeries(server, src.studyUID, segFound[0].seriesInstanceUid, segBack.string()),
            1);
  DcmFileFormat f;
  ASSERT_TRUE(f.loadFile(Files(segBack).at(0).c_str()).good());
  DcmDataset& d = *f.getDataset();
  EXPECT_EQ(Text(d, DCM_SOPClassUID), UID_SegmentationStorage);
  EXPECT_EQ(Text(d, DCM_StudyInstanceUID), src.studyUID);
  EXPECT_EQ(Text(d, DCM_FrameOfReferenceUID), src.frameOfReferenceUID);
  DcmItem* reference = nullptr;
  ASSERT_TRUE(d.findAndGetSequenceItem(DCM_ReferencedSeriesSequence, reference, 0).good());
  EXPECT_EQ(Text(*reference, DCM_SeriesInstanceUID), seriesUid);
  // Both series in the study now.
  bm::PacsQuery any = byStudy;
  any.modality.clear();
  EXPECT_EQ(bm::FindSeries(server, any).size(), 2u);
}

TEST(PacsClient, FailuresNameTheServerAndWhyAndLeaveNothing) {
  const fs::path dir = Scratch("failures");
  bmtest::OrthancProcess orthanc(dir / "orthanc");
  bm::PacsServer server;
  server.port = orthanc.Port;
  server.timeoutS = 2;
  bm::WriteDicomSeries(SmallCT(), (dir / "ct").string());

  // Down: nothing listens on the port.
  bm::PacsServer down = server;
  down.port = bmtest::FreeLoopbackPort();
  std::string why = Failure([&] { bm::FindSeries(down, {}); });
  EXPECT_NE(why.find("127.0.0.1:" + std::to_string(down.port)), std::string::npos) << why;
  EXPECT_NE(why.find("no association"), std::string::npos) << why;
  // Slow: a socket that accepts connections and never answers: the 2 s timeout ends it.
  {
    bm::PacsServer silent = server;
    const int fd = bmtest::LoopbackSocket(silent.port, true);
    const auto t0 = std::chrono::steady_clock::now();
    why = Failure([&] { bm::FindSeries(silent, {}); });
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    ::close(fd);
    EXPECT_NE(why.find("no association"), std::string::npos) << why;
    EXPECT_LT(s, 10.0) << "the timeout did not end the wait";
  }
  // Another called AET: the association is rejected.
  bm::PacsServer wrongAet = server;
  wrongAet.calledAet = "NOT-ORTHANC";
  why = Failure([&] { bm::FindSeries(wrongAet, {}); });
  EXPECT_NE(why.find("NOT-ORTHANC@127.0.0.1"), std::string::npos) << why;
  EXPECT_NE(why.find("Rejected"), std::string::npos) << why;
  // A calling AET the PACS does not know: it refuses the query.
  bm::PacsServer stranger = server;
  stranger.callingAet = "STRANGER";
  why = Failure([&] { bm::FindSeries(stranger, {}); });
  EXPECT_NE(why.find("STRANGER"), std::string::npos) << why;

  // An unknown series, and a target folder that exists: refused, nothing written.
  why = Failure([&] { bm::GetSeries(server, "", "1.2.3.4.5", (dir / "none").string()); });
  EXPECT_NE(why.find("no series 1.2.3.4.5"), std::string::npos) << why;
  EXPECT_FALSE(fs::exists(dir / "none"));
  fs::create_directories(dir / "taken");
  why = Failure([&] { bm::GetSeries(server, "", "1.2.3.4.5", (dir / "taken").string()); });
  EXPECT_NE(why.find("exists"), std::string::npos) << why;
  // A file that is not DICOM: named, before anything is sent.
  const std::string text = (dir / "notes.dcm").string();
  std::ofstream(text) << "not DICOM\n";
  const std::vector<std::string> files = {Files(dir / "ct").at(0), text};
  why = Failure([&] { bm::StoreFiles(server, files); });
  EXPECT_NE(why.find("notes.dcm"), std::string::npos) << why;
  EXPECT_TRUE(bm::FindSeries(server, {}).empty()) << "a refused store sent files";
  // Bad addresses are refused by the parser, naming the text.
  EXPECT_THROW(bm::ParsePacsServer("localhost"), std::invalid_argument);
  EXPECT_THROW(bm::ParsePacsServer("A@h:99999"), std::invalid_argument);
  EXPECT_THROW(bm::ParsePacsServer("AN-AET-LONGER-THAN-16@h:104"), std::invalid_argument);
  const bm::PacsServer parsed = bm::ParsePacsServer("PACS1@pacs.example:11112");
  EXPECT_EQ(parsed.calledAet, "PACS1");
  EXPECT_EQ(parsed.host, "pacs.example");
  EXPECT_EQ(parsed.port, 11112);
  const bm::PacsSeriesUrl url =
      bm::ParsePacsUrl("pacs://PACS1@pacs.example:11112/1.2.840.5?aet=WS7");
  EXPECT_EQ(url.server.calledAet, "PACS1");
  EXPECT_EQ(url.server.callingAet, "WS7");
  EXPECT_EQ(url.server.port, 11112);
  EXPECT_EQ(url.seriesInstanceUid, "1.2.840.5");
  for (const char* bad : {"http://h:1/1.2", "pacs://h:1", "pacs://h:1/", "pacs://h:1/1.2/../x",
                          "pacs://h:1/1.2?user=x", "pacs://h/1.2"})
    EXPECT_THROW(bm::ParsePacsUrl(bad), std::invalid_argument) << bad;
}

TEST(PacsClient, DicomWebFindsFetchesAndStoresAsDimseDoes) {
  // The same PACS through its DICOMweb service (Orthanc's plugin): STOW-RS, QIDO-RS, WADO-RS.
  const fs::path dir = Scratch("dicomweb");
  bmtest::OrthancProcess orthanc(dir / "orthanc", true);
  bm::DicomWebServer server;
  server.url = orthanc.WebUrl;
  server.timeoutS = 10;
  EXPECT_TRUE(bm::IsDicomWebUrl(server.url));
  EXPECT_FALSE(bm::IsDicomWebUrl("ORTHANC@127.0.0.1:4242"));

  bm::DicomWriteOptions wo;
  wo.patientID = "BM-WEB-1";
  const std::string seriesUid = bm::WriteDicomSeries(SmallCT(), (dir / "ct").string(), wo);
  const bm::DicomSource src = bm::ReadDicomSource((dir / "ct").string());
  bm::StoreFilesWeb(server, Files(dir / "ct"));

  bm::PacsQuery q;
  q.patientId = "BM-WEB-*";
  const std::vector<bm::PacsSeries> found = bm::FindSeriesWeb(server, q);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].seriesInstanceUid, seriesUid);
  EXPECT_EQ(found[0].studyInstanceUid, src.studyUID);
  EXPECT_EQ(found[0].patientId, "BM-WEB-1");
  EXPECT_EQ(found[0].instances, 12);
  q.patientId = "SOMEONE-ELSE";
  EXPECT_TRUE(bm::FindSeriesWeb(server, q).empty());

  const fs::path got = dir / "fetched";
  EXPECT_EQ(bm::GetSeriesWeb(server, "", seriesUid, got.string()), 12);
  std::set<std::string> sent;
  for (const auto& image : src.images)
    sent.insert(image.sopInstanceUID);
  EXPECT_EQ(SopInstances(got), sent);
  EXPECT_EQ(bm::ReadDicomSource(got.string()).seriesUID, seriesUid);
  // The same series through DIMSE: the two faces of one PACS agree.
  bm::PacsServer dimse;
  dimse.port = orthanc.Port;
  bm::PacsQuery byPatient;
  byPatient.patientId = "BM-WEB-1";
  ASSERT_EQ(bm::FindSeries(dimse, byPatient).size(), 1u);
  EXPECT_EQ(bm::FindSeries(dimse, byPatient)[0].seriesInstanceUid, seriesUid);

  // Failures: named, nothing left.
  std::string why =
      Failure([&] { bm::GetSeriesWeb(server, "", "1.2.3.4.5", (dir / "x").string()); });
  EXPECT_NE(why.find("no series 1.2.3.4.5"), std::string::npos) << why;
  EXPECT_FALSE(fs::exists(dir / "x"));
  bm::DicomWebServer down = server;
  down.url = "http://127.0.0.1:" + std::to_string(bmtest::FreeLoopbackPort()) + "/dicom-web";
  why = Failure([&] { bm::FindSeriesWeb(down, {}); });
  EXPECT_NE(why.find(down.url), std::string::npos) << why;
  bm::DicomWebServer wrongRoot = server;
  wrongRoot.url = "http://127.0.0.1:" + std::to_string(orthanc.HttpPort) + "/not-dicom-web";
  why = Failure([&] { bm::FindSeriesWeb(wrongRoot, {}); });
  EXPECT_NE(why.find("HTTP 404"), std::string::npos) << why;
  const std::string text = (dir / "notes.dcm").string();
  std::ofstream(text) << "not DICOM\n";
  why = Failure([&] { bm::StoreFilesWeb(server, {text}); });
  EXPECT_NE(why.find("notes.dcm"), std::string::npos) << why;
  EXPECT_THROW(bm::FindSeriesWeb(bm::DicomWebServer{"ftp://h/x", 10}, {}), std::invalid_argument);
}

// One text names either face (bmPacsConnection.h), and a series' folder is reused when it holds
// the series whole, refused when it holds anything else (bmSeriesFolder.h); no PACS needed.
TEST(PacsConnection, OneTextNamesEitherFaceAndAWholeSeriesFolderIsReused) {
  bm::PacsServer base;
  base.callingAet = "OURS";
  base.timeoutS = 7;
  const bm::PacsConnection dimse("PACS@10.0.0.2:104", base);
  EXPECT_FALSE(dimse.IsDicomWeb());
  EXPECT_EQ(dimse.Name(), "PACS@10.0.0.2:104");
  EXPECT_EQ(dimse.Dimse().callingAet, "OURS");
  EXPECT_EQ(dimse.Dimse().timeoutS, 7);
  EXPECT_EQ(bm::PacsConnection("10.0.0.2:104").Name(), "ORTHANC@10.0.0.2:104");
  const bm::PacsConnection web("https://pacs.example.org/dicom-web//", base);
  EXPECT_TRUE(web.IsDicomWeb());
  EXPECT_EQ(web.Name(), "https://pacs.example.org/dicom-web");
  EXPECT_EQ(web.DicomWeb().timeoutS, 7);
  for (const char* bad : {"", "pacs", "PACS@host", "PACS@host:99999", "PACS@host:x"}) {
    const std::string why = Failure([&] { bm::PacsConnection{bad}; });
    EXPECT_NE(why.find(std::string("'") + bad + "'"), std::string::npos) << bad << ": " << why;
  }

  const fs::path dir = Scratch("series-folder");
  EXPECT_EQ(bm::SeriesFolder((dir / "cache").string(), "1.2.3/../4"),
            (dir / "cache" / "1.2.3_.._4").string());
  EXPECT_THROW(bm::SeriesFolder(dir.string(), ""), std::invalid_argument);
  bm::DicomWriteOptions wo;
  const std::string uid = bm::WriteDicomSeries(SmallCT(), (dir / "held").string(), wo);
  EXPECT_EQ(bm::HeldSeriesInstances((dir / "held").string(), uid), 12);
  EXPECT_EQ(bm::HeldSeriesInstances((dir / "held").string(), "1.2.3"), 0);
  EXPECT_EQ(bm::HeldSeriesInstances((dir / "none").string(), uid), -1);

  // Held whole: reused without asking the PACS (nothing listens on its port).
  const bm::PacsConnection down("ORTHANC@127.0.0.1:" + std::to_string(bmtest::FreeLoopbackPort()));
  bm::PacsSeries series;
  series.seriesInstanceUid = uid;
  series.instances = 12;
  const bm::SeriesFetch reused = bm::FetchSeriesInto(down, series, (dir / "held").string());
  EXPECT_TRUE(reused.reused);
  EXPECT_EQ(reused.instances, 12);
  // Not whole (the PACS lists more), or something else in it: refused, left as it was.
  series.instances = 13;
  std::string why = Failure([&] { bm::FetchSeriesInto(down, series, (dir / "held").string()); });
  EXPECT_NE(why.find("12 of its 13"), std::string::npos) << why;
  series.instances = 12;
  std::ofstream((dir / "held" / "notes.txt").string()) << "not DICOM\n";
  why = Failure([&] { bm::FetchSeriesInto(down, series, (dir / "held").string()); });
  EXPECT_NE(why.find("does not hold series"), std::string::npos) << why;
  EXPECT_EQ(Files(dir / "held").size(), 12u);
  // Not there: fetched, and a server that is down is named, leaving no folder.
  why = Failure([&] { bm::FetchSeriesInto(down, series, (dir / "fetched").string()); });
  EXPECT_NE(why.find(down.Name()), std::string::npos) << why;
  EXPECT_FALSE(fs::exists(dir / "fetched"));
}
