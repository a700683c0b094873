// bmsim pacs - a PACS over DICOM's network protocol (bmPacsClient.h) or DICOMweb
// (bmDicomWebClient.h), whichever --server names (bmPacsConnection.h): find a patient's series,
// fetch one into a folder (which bmsim plan and import read), store files back (a plan's SEG and
// SR from bmsim run --dicom).
#include <iomanip>
#include <iostream>

#include "bmPacsConnection.h"
#include "bmsimArgs.h"
#include "bmsimCommand.h"

namespace {

void PacsOptions(bm::cli::ParsedArgs& p) {
  p.Words("ACTION [ARGS]", "find | get | store FILE...");
  p.Value("server", "[AET@]HOST:PORT|URL",
          "the PACS (required): its DICOM address, e.g. ORTHANC@127.0.0.1:4242 (DIMSE), or its "
          "DICOMweb root, e.g. http://127.0.0.1:8042/dicom-web (QIDO-RS, WADO-RS, STOW-RS)");
  p.Value("aet", "AET", "our application entity title, as the PACS knows us (default BMSIM)");
  p.Int("timeout", 1, 3600, "connection and message timeout, s (default 30)");
  p.Value("patient-id", "ID", "find: the patient's ID (wildcards * ?)");
  p.Value("patient-name", "NAME", "find: the patient's name (wildcards * ?)");
  p.Value("accession", "NUMBER", "find: the study's accession number");
  p.Value("study", "UID", "find, get: the Study Instance UID");
  p.Value("series", "UID", "find, get: the Series Instance UID (get: required)");
  p.Value("modality", "CT", "find: the series' modality (default CT; 'any' for every modality)");
  p.Value("out", "DIR", "get: a new folder for the series' files (required)");
  p.Footer("find lists the matching series (C-FIND, Study Root, series level; or QIDO-RS): "
           "patient, study date, accession, modality, instances, Study and Series Instance UIDs. "
           "get fetches one series (C-GET; or WADO-RS) into a new folder, written whole or not "
           "at all. store sends DICOM files (C-STORE; or STOW-RS), e.g. the Segmentation and "
           "Structured Report of bmsim run --dicom. Exit status 1 when the PACS cannot be "
           "reached, refuses or fails, naming why.");
}

/// The PACS named by --server: DIMSE (AET@host:port) or DICOMweb (an http(s) root), parsed by
/// bm::PacsConnection.
bm::PacsConnection Server(const bm::cli::ParsedArgs& p) {
  const auto address = p.Get("server");
  if (!address)
    throw bm::cli::UsageError("--server [AET@]HOST:PORT or --server URL is required");
  if (bm::IsDicomWebUrl(*address) && p.Has("aet"))
    throw bm::cli::UsageError("--aet applies to a DICOM address, not a DICOMweb URL");
  bm::PacsServer base;
  base.callingAet = p.Get("aet", base.callingAet);
  if (const auto t = p.GetInt("timeout", 1, 3600))
    base.timeoutS = int(*t);
  try {
    return bm::PacsConnection(*address, base);
  } catch (const std::invalid_argument& e) {
    throw bm::cli::UsageError(e.what());
  }
}

int PacsCommand(const bm::cli::ParsedArgs& p) {
  const auto& words = p.Positional();
  if (words.empty())
    throw bm::cli::UsageError("pacs needs an action: find, get or store");
  const std::string action = words[0];
  const bm::PacsConnection server = Server(p);
  if (action == "find") {
    if (words.size() != 1)
      throw bm::cli::UsageError("pacs find takes no file");
    bm::PacsQuery q;
    q.patientId = p.Get("patient-id", "");
    q.patientName = p.Get("patient-name", "");
    q.accessionNumber = p.Get("accession", "");
    q.studyInstanceUid = p.Get("study", "");
    q.seriesInstanceUid = p.Get("series", "");
    q.modality = p.Get("modality", "CT");
    if (q.modality == "any")
      q.modality.clear();
    const auto found = server.FindSeries(q);
    std::cout << found.size() << " series\n";
    for (const auto& s : found)
      std::cout << s.patientId << " | " << s.patientName << " | " << s.studyDate << " | "
                << s.accessionNumber << " | " << s.modality << " | "
                << (s.instances >= 0 ? std::to_string(s.instances) : "?") << " instances | "
                << s.seriesDescription << " | study " << s.studyInstanceUid << " | series "
                << s.seriesInstanceUid << "\n";
    if (found.empty())
      std::cout << "nothing matched\n";
    return 0;
  }
  if (action == "get") {
    if (words.size() != 1)
      throw bm::cli::UsageError("pacs get takes no file: --series UID --out DIR");
    const auto series = p.Get("series");
    const auto out = p.Get("out");
    if (!series || !out)
      throw bm::cli::UsageError("pacs get needs --series UID and --out DIR");
    const int n = server.GetSeries(p.Get("study", ""), *series, *out);
    std::cout << "fetched " << n << " instance" << (n == 1 ? "" : "s") << " of series " << *series
              << " into " << *out << "\n";
    return 0;
  }
  if (action == "store") {
    const std::vector<std::string> files(words.begin() + 1, words.end());
    if (files.empty())
      throw bm::cli::UsageError("pacs store needs one or more DICOM files");
    server.StoreFiles(files);
    std::cout << "stored " << files.size() << " file" << (files.size() == 1 ? "" : "s") << "\n";
    return 0;
  }
  throw bm::cli::UsageError("unknown pacs action '" + action + "': find, get or store");
}

} // namespace

BM_REGISTER_COMMAND(pacs,
                    "find, fetch and store DICOM series on a PACS (DIMSE C-FIND, C-GET, C-STORE, "
                    "or DICOMweb)",
                    PacsOptions, PacsCommand);
