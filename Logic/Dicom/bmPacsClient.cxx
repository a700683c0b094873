#include "bmPacsClient.h"

#include "bmDicomWriting.h" // QuietDicomLog
#include "bmFetchedSeries.h"

#include <dcmtk/config/osconfig.h>

#include <dcmtk/dcmdata/dcdeftag.h>
#include <dcmtk/dcmdata/dcfilefo.h>
#include <dcmtk/dcmdata/dcuid.h>
#include <dcmtk/dcmnet/diutil.h>
#include <dcmtk/dcmnet/scu.h>
#include <dcmtk/oflog/oflog.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <memory>
#include <set>
#include <sstream>
#include <stdexcept>
#include <system_error>

namespace fs = std::filesystem;

namespace bm {

namespace {

/// DCMTK's network log off below fatal: every failure reaches the caller as an exception naming
/// the server and the step, and its own "E:" lines would only repeat it.
void QuietNetworkLog() {
  QuietDicomLog();
  static const bool once = [] {
    OFLog::getLogger("dcmtk.dcmnet").setLogLevel(OFLogger::FATAL_LOG_LEVEL);
    return true;
  }();
  (void)once;
}

std::string Where(const PacsServer& s) {
  return s.calledAet + "@" + s.host + ":" + std::to_string(s.port);
}

void CheckServer(const PacsServer& s) {
  const auto aet = [](const std::string& a) { return !a.empty() && a.size() <= 16; };
  if (s.host.empty() || s.port < 1 || s.port > 65535 || !aet(s.calledAet) || !aet(s.callingAet) ||
      s.timeoutS < 1 || s.timeoutS > 3600)
    throw std::invalid_argument("PACS server '" + Where(s) + "' (calling AET '" + s.callingAet +
                                "', timeout " + std::to_string(s.timeoutS) +
                                " s): a host, a port in [1, 65535], application entity titles of "
                                "1-16 characters and a timeout in [1, 3600] s are needed");
}

/// The storage SOP classes a fetched CT series or our results may hold.
const char* const kStorageClasses[] = {
    UID_CTImageStorage,         UID_EnhancedCTImageStorage,       UID_SegmentationStorage,
    UID_ComprehensiveSRStorage, UID_SecondaryCaptureImageStorage, UID_EncapsulatedPDFStorage};

OFList<OFString> TransferSyntaxes() {
  OFList<OFString> ts;
  ts.push_back(UID_LittleEndianExplicitTransferSyntax);
  ts.push_back(UID_LittleEndianImplicitTransferSyntax);
  return ts;
}

/// A DcmSCU whose C-GET stores each incoming instance in one folder and counts them.
class Scu : public DcmSCU {
public:
  explicit Scu(const PacsServer& s) : Server(s) {
    CheckServer(s);
    setAETitle(s.callingAet.c_str());
    setPeerHostName(s.host.c_str());
    setPeerPort(Uint16(s.port));
    setPeerAETitle(s.calledAet.c_str());
    setConnectionTimeout(Sint32(s.timeoutS));
    setACSETimeout(Uint32(s.timeoutS));
    setDIMSETimeout(Uint32(s.timeoutS));
    setDIMSEBlockingMode(DIMSE_BLOCKING);
    setMaxReceivePDULength(ASC_DEFAULTMAXPDU);
  }
  ~Scu() override {
    if (isConnected())
      abortAssociation();
  }

  /// Connects, negotiates the contexts added before and checks that `needed` was accepted.
  T_ASC_PresentationContextID Open(const char* needed, const char* what) {
    OFCondition c = initNetwork();
    if (c.bad())
      throw std::runtime_error("PACS " + Where(Server) + ": cannot set up the network (" +
                               c.text() + ")");
    c = negotiateAssociation();
    if (c.bad())
      throw std::runtime_error("PACS " + Where(Server) + ": no association for " + what + " (" +
                               c.text() +
                               "): is the server running there, and does it know the calling "
                               "AET '" +
                               Server.callingAet + "'?");
    const T_ASC_PresentationContextID id = findPresentationContextID(needed, "");
    if (id == 0)
      throw std::runtime_error("PACS " + Where(Server) + " does not accept " + what);
    return id;
  }

  void Close() {
    if (isConnected())
      releaseAssociation();
  }

  // C-GET's incoming instances.
  const FetchedSeries* Into = nullptr;
  std::set<std::string> Received;
  std::string StoreError;

  OFCondition handleSTORERequest(const T_ASC_PresentationContextID, DcmDataset* incomingObject,
                                 OFBool& continueCGETSession, Uint16& cStoreReturnStatus) override {
    std::unique_ptr<DcmDataset> data(incomingObject);
    continueCGETSession = OFTrue;
    OFString sop;
    if (!Into || !data || data->findAndGetOFString(DCM_SOPInstanceUID, sop).bad() || sop.empty()) {
      StoreError = "an instance without a SOP Instance UID";
      cStoreReturnStatus = STATUS_STORE_Error_CannotUnderstand;
      return EC_Normal;
    }
    const std::string name(sop.c_str());
    DcmFileFormat file(data.get());
    const OFCondition c =
        file.saveFile(Into->InstancePath(name).string().c_str(), EXS_LittleEndianExplicit);
    if (c.bad()) {
      StoreError = "cannot write instance " + name + ": " + c.text();
      cStoreReturnStatus = STATUS_STORE_Refused_OutOfResources;
      return EC_Normal;
    }
    Received.insert(name);
    cStoreReturnStatus = STATUS_Success;
    return EC_Normal;
  }

private:
  PacsServer Server;
};

std::string Text(DcmItem* item, const DcmTagKey& tag) {
  OFString v;
  if (item && item->findAndGetOFStringArray(tag, v).good())
    return v.c_str();
  return "";
}

/// A server that aborts the association at a request (Orthanc, for a calling AET it does not
/// know) has usually refused who we are.
std::string RefusedHint(const OFCondition& c, const PacsServer& s) {
  return c == DUL_PEERABORTEDASSOCIATION
             ? ": the server aborted it; does it allow queries and retrievals from the calling "
               "AET '" +
                   s.callingAet + "'?"
             : "";
}

std::string StatusText(Uint16 status) {
  std::ostringstream s;
  s << "status 0x" << std::hex << status;
  return s.str();
}

} // namespace

PacsServer ParsePacsServer(const std::string& text, const PacsServer& base) {
  PacsServer s = base;
  std::string rest = text;
  if (const auto at = rest.find('@'); at != std::string::npos) {
    s.calledAet = rest.substr(0, at);
    rest = rest.substr(at + 1);
  }
  const auto colon = rest.rfind(':');
  const auto bad = [&]() {
    return std::invalid_argument("PACS server '" + text + "': expected [AET@]host:port");
  };
  if (colon == std::string::npos || colon == 0 || colon + 1 == rest.size())
    throw bad();
  s.host = rest.substr(0, colon);
  const std::string port = rest.substr(colon + 1);
  if (port.size() > 5 || !std::all_of(port.begin(), port.end(), [](char c) {
        return std::isdigit(static_cast<unsigned char>(c));
      }))
    throw bad();
  s.port = std::stoi(port);
  CheckServer(s);
  return s;
}

PacsSeriesUrl ParsePacsUrl(const std::string& url, const PacsServer& base) {
  const std::string scheme = "pacs://";
  const auto bad = [&]() {
    return std::invalid_argument(
        "'" + url + "': a PACS series is pacs://[AET@]HOST:PORT/SERIES-UID[?aet=OURS]");
  };
  if (url.rfind(scheme, 0) != 0)
    throw bad();
  std::string rest = url.substr(scheme.size());
  PacsServer ours = base;
  if (const auto q = rest.find('?'); q != std::string::npos) {
    const std::string query = rest.substr(q + 1);
    rest = rest.substr(0, q);
    if (query.rfind("aet=", 0) != 0 || query.size() == 4)
      throw bad();
    ours.callingAet = query.substr(4);
  }
  const auto slash = rest.find('/');
  if (slash == std::string::npos || slash + 1 == rest.size())
    throw bad();
  PacsSeriesUrl u;
  u.seriesInstanceUid = rest.substr(slash + 1);
  if (!std::all_of(
          u.seriesInstanceUid.begin(), u.seriesInstanceUid.end(),
          [](char c) { return std::isdigit(static_cast<unsigned char>(c)) || c == '.'; }) ||
      u.seriesInstanceUid.size() > 64)
    throw bad();
  u.server = ParsePacsServer(rest.substr(0, slash), ours);
  return u;
}

std::vector<PacsSeries> FindSeries(const PacsServer& server, const PacsQuery& q) {
  QuietNetworkLog();
  Scu scu(server);
  scu.addPresentationContext(UID_FINDStudyRootQueryRetrieveInformationModel, TransferSyntaxes());
  const T_ASC_PresentationContextID id =
      scu.Open(UID_FINDStudyRootQueryRetrieveInformationModel, "queries (C-FIND, Study Root)");
  DcmDataset keys;
  keys.putAndInsertOFStringArray(DCM_QueryRetrieveLevel, "SERIES");
  keys.putAndInsertOFStringArray(DCM_PatientID, q.patientId.c_str());
  keys.putAndInsertOFStringArray(DCM_PatientName, q.patientName.c_str());
  keys.putAndInsertOFStringArray(DCM_AccessionNumber, q.accessionNumber.c_str());
  keys.putAndInsertOFStringArray(DCM_StudyInstanceUID, q.studyInstanceUid.c_str());
  keys.putAndInsertOFStringArray(DCM_StudyDate, "");
  keys.putAndInsertOFStringArray(DCM_SeriesInstanceUID, q.seriesInstanceUid.c_str());
  keys.putAndInsertOFStringArray(DCM_Modality, q.modality.c_str());
  keys.putAndInsertOFStringArray(DCM_SeriesDescription, "");
  keys.putAndInsertOFStringArray(DCM_NumberOfSeriesRelatedInstances, "");
  OFList<QRResponse*> responses;
  const OFCondition c = scu.sendFINDRequest(id, &keys, &responses);
  std::vector<PacsSeries> found;
  std::string failure;
  for (QRResponse* r : responses) {
    if (r->m_status == STATUS_Pending ||
        r->m_status == STATUS_FIND_Pending_WarningUnsupportedOptionalKeys) {
      DcmDataset* d = r->m_dataset;
      PacsSeries s;
      s.patientId = Text(d, DCM_PatientID);
      s.patientName = Text(d, DCM_PatientName);
      s.studyInstanceUid = Text(d, DCM_StudyInstanceUID);
      s.studyDate = Text(d, DCM_StudyDate);
      s.accessionNumber = Text(d, DCM_AccessionNumber);
      s.seriesInstanceUid = Text(d, DCM_SeriesInstanceUID);
      s.modality = Text(d, DCM_Modality);
      s.seriesDescription = Text(d, DCM_SeriesDescription);
      const std::string n = Text(d, DCM_NumberOfSeriesRelatedInstances);
      s.instances = n.empty() ? -1 : std::atoi(n.c_str());
      found.push_back(s);
    } else if (r->m_status != STATUS_Success) {
      failure = StatusText(r->m_status);
    }
    delete r;
  }
  if (c.bad())
    throw std::runtime_error("PACS " + Where(server) + ": the query failed (" + c.text() + ")" +
                             RefusedHint(c, server));
  if (!failure.empty())
    throw std::runtime_error("PACS " + Where(server) + " refused the query (" + failure + ")");
  scu.Close();
  return found;
}

int GetSeries(const PacsServer& server, const std::string& studyInstanceUid,
              const std::string& seriesInstanceUid, const std::string& folder) {
  QuietNetworkLog();
  if (seriesInstanceUid.empty())
    throw std::invalid_argument("fetching a series needs its Series Instance UID");
  FetchedSeries fetched(folder); // refuses a folder that exists
  // The study, when not given, from a query (C-GET at series level needs it).
  std::string study = studyInstanceUid;
  int expected = -1;
  {
    PacsQuery q;
    q.seriesInstanceUid = seriesInstanceUid;
    q.studyInstanceUid = studyInstanceUid;
    q.modality.clear();
    const std::vector<PacsSeries> found = FindSeries(server, q);
    if (found.empty())
      throw std::runtime_error("PACS " + Where(server) + " holds no series " + seriesInstanceUid);
    study = found.front().studyInstanceUid;
    expected = found.front().instances;
  }
  Scu scu(server);
  scu.addPresentationContext(UID_GETStudyRootQueryRetrieveInformationModel, TransferSyntaxes());
  for (const char* sop : kStorageClasses) // the server sends the instances back on these
    scu.addPresentationContext(sop, TransferSyntaxes(), ASC_SC_ROLE_SCP);
  const T_ASC_PresentationContextID id =
      scu.Open(UID_GETStudyRootQueryRetrieveInformationModel, "retrieval (C-GET, Study Root)");
  scu.Into = &fetched;
  DcmDataset keys;
  keys.putAndInsertOFStringArray(DCM_QueryRetrieveLevel, "SERIES");
  keys.putAndInsertOFStringArray(DCM_StudyInstanceUID, study.c_str());
  keys.putAndInsertOFStringArray(DCM_SeriesInstanceUID, seriesInstanceUid.c_str());
  OFList<RetrieveResponse*> responses;
  const OFCondition c = scu.sendCGETRequest(id, &keys, &responses);
  Uint16 finalStatus = STATUS_Success;
  int failed = 0;
  for (RetrieveResponse* r : responses) {
    if (r->m_status != STATUS_Pending) {
      finalStatus = r->m_status;
      failed = r->m_numberOfFailedSubops;
    }
    delete r;
  }
  if (c.bad())
    throw std::runtime_error("PACS " + Where(server) + ": the retrieval failed (" + c.text() + ")" +
                             RefusedHint(c, server));
  if (!scu.StoreError.empty())
    throw std::runtime_error("PACS " + Where(server) + ": " + scu.StoreError);
  if (finalStatus != STATUS_Success || failed > 0)
    throw std::runtime_error("PACS " + Where(server) + ": the retrieval ended with " +
                             StatusText(finalStatus) + ", " + std::to_string(failed) +
                             " instance(s) failed");
  scu.Close();
  return fetched.Commit("PACS " + Where(server), seriesInstanceUid, int(scu.Received.size()),
                        expected);
}

void StoreFiles(const PacsServer& server, const std::vector<std::string>& files) {
  QuietNetworkLog();
  if (files.empty())
    throw std::invalid_argument("no DICOM file to store");
  // Each file's SOP class and transfer syntax, read first: an unreadable file stops before any
  // association.
  struct Item {
    std::string path, sopClass, transferSyntax;
  };
  std::vector<Item> items;
  for (const std::string& path : files) {
    DcmFileFormat f;
    const OFCondition c = f.loadFile(path.c_str(), EXS_Unknown, EGL_noChange, 4096);
    OFString sop, ts;
    if (c.bad() || f.getMetaInfo()->findAndGetOFString(DCM_MediaStorageSOPClassUID, sop).bad() ||
        f.getMetaInfo()->findAndGetOFString(DCM_TransferSyntaxUID, ts).bad())
      throw std::runtime_error("'" + path + "' is not a DICOM file with a SOP class (" +
                               std::string(c.bad() ? c.text() : "no meta header") + ")");
    items.push_back({path, sop.c_str(), ts.c_str()});
  }
  Scu scu(server);
  std::set<std::pair<std::string, std::string>> contexts;
  for (const Item& i : items)
    if (contexts.insert({i.sopClass, i.transferSyntax}).second) {
      OFList<OFString> ts;
      ts.push_back(i.transferSyntax.c_str());
      scu.addPresentationContext(i.sopClass.c_str(), ts);
    }
  scu.Open(items.front().sopClass.c_str(), "storage (C-STORE)");
  for (const Item& i : items) {
    const T_ASC_PresentationContextID id =
        scu.findPresentationContextID(i.sopClass.c_str(), i.transferSyntax.c_str());
    if (id == 0)
      throw std::runtime_error("PACS " + Where(server) + " does not accept '" + i.path +
                               "' (SOP class " + i.sopClass + ")");
    Uint16 status = 0;
    const OFCondition c = scu.sendSTORERequest(id, i.path.c_str(), nullptr, status);
    if (c.bad())
      throw std::runtime_error("PACS " + Where(server) + ": storing '" + i.path + "' failed (" +
                               c.text() + ")");
    if (status != STATUS_Success)
      throw std::runtime_error("PACS " + Where(server) + " refused '" + i.path + "' (" +
                               StatusText(status) + ")");
  }
  scu.Close();
}

} // namespace bm
