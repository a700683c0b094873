#include "bmDicomWebClient.h"

#include "bmDicomWriting.h" // QuietDicomLog
#include "bmFetchedSeries.h"

#include <dcmtk/config/osconfig.h>

#include <dcmtk/dcmdata/dcdeftag.h>
#include <dcmtk/dcmdata/dcfilefo.h>
#include <dcmtk/dcmdata/dcistrmb.h>
#include <dcmtk/dcmdata/dcmetinf.h>

#include <curl/curl.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <random>
#include <set>
#include <stdexcept>
#include <system_error>

namespace fs = std::filesystem;

namespace bm {

namespace {

struct Response {
  long status = 0;
  std::string contentType, body;
};

size_t Append(char* data, size_t size, size_t n, void* out) {
  static_cast<std::string*>(out)->append(data, size * n);
  return size * n;
}

size_t Header(char* data, size_t size, size_t n, void* out) {
  std::string line(data, size * n);
  std::string lower = line;
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  if (lower.rfind("content-type:", 0) == 0) {
    std::string v = line.substr(13);
    while (!v.empty() && std::isspace(static_cast<unsigned char>(v.front())))
      v.erase(v.begin());
    while (!v.empty() && std::isspace(static_cast<unsigned char>(v.back())))
      v.pop_back();
    static_cast<Response*>(out)->contentType = v;
  }
  return size * n;
}

void CheckServer(const DicomWebServer& s) {
  if (!IsDicomWebUrl(s.url) || s.timeoutS < 1 || s.timeoutS > 3600)
    throw std::invalid_argument("DICOMweb server '" + s.url + "' (timeout " +
                                std::to_string(s.timeoutS) +
                                " s): an http:// or https:// root and a timeout in [1, 3600] s "
                                "are needed");
}

/// One HTTP request; throws std::runtime_error naming the request when it cannot be made.
Response Request(const DicomWebServer& s, const std::string& method, const std::string& url,
                 const std::vector<std::string>& headers, const std::string& body = {}) {
  static const bool init = [] { return curl_global_init(CURL_GLOBAL_DEFAULT) == CURLE_OK; }();
  if (!init)
    throw std::runtime_error("libcurl could not be initialised");
  std::unique_ptr<CURL, decltype(&curl_easy_cleanup)> curl(curl_easy_init(), curl_easy_cleanup);
  if (!curl)
    throw std::runtime_error("libcurl could not make a request");
  curl_slist* list = nullptr;
  for (const auto& h : headers)
    list = curl_slist_append(list, h.c_str());
  std::unique_ptr<curl_slist, decltype(&curl_slist_free_all)> hold(list, curl_slist_free_all);
  Response r;
  CURL* c = curl.get();
  curl_easy_setopt(c, CURLOPT_URL, url.c_str());
  curl_easy_setopt(c, CURLOPT_PROTOCOLS_STR, "http,https");
  curl_easy_setopt(c, CURLOPT_NOSIGNAL, 1L);
  curl_easy_setopt(c, CURLOPT_CONNECTTIMEOUT, long(s.timeoutS));
  curl_easy_setopt(c, CURLOPT_TIMEOUT, long(s.timeoutS));
  curl_easy_setopt(c, CURLOPT_HTTPHEADER, list);
  curl_easy_setopt(c, CURLOPT_WRITEFUNCTION, Append);
  curl_easy_setopt(c, CURLOPT_WRITEDATA, &r.body);
  curl_easy_setopt(c, CURLOPT_HEADERFUNCTION, Header);
  curl_easy_setopt(c, CURLOPT_HEADERDATA, &r);
  if (method == "POST") {
    curl_easy_setopt(c, CURLOPT_POST, 1L);
    curl_easy_setopt(c, CURLOPT_POSTFIELDS, body.data());
    curl_easy_setopt(c, CURLOPT_POSTFIELDSIZE_LARGE, curl_off_t(body.size()));
  }
  const CURLcode code = curl_easy_perform(c);
  if (code != CURLE_OK)
    throw std::runtime_error("DICOMweb " + method + " " + url + ": " + curl_easy_strerror(code));
  curl_easy_getinfo(c, CURLINFO_RESPONSE_CODE, &r.status);
  return r;
}

/// A query value or path segment percent-encoded, but for the wildcard *, which is legal in a
/// URL's query and which a server (Orthanc's plugin) does not match when encoded.
std::string Escape(const std::string& v) {
  char* e = curl_escape(v.c_str(), int(v.size()));
  const std::string encoded = e ? e : "";
  curl_free(e);
  std::string out;
  for (size_t i = 0; i < encoded.size(); ++i)
    if (encoded.compare(i, 3, "%2A") == 0) {
      out.push_back('*');
      i += 2;
    } else {
      out.push_back(encoded[i]);
    }
  return out;
}

/// The first value of a tag in a DICOM JSON object ("" when absent): text, a person's
/// alphabetic name, or a number as text.
std::string Value(const nlohmann::json& o, const char* tag) {
  const auto t = o.find(tag);
  if (t == o.end() || !t->is_object())
    return "";
  const auto v = t->find("Value");
  if (v == t->end() || !v->is_array() || v->empty())
    return "";
  const nlohmann::json& x = v->front();
  if (x.is_string())
    return x.get<std::string>();
  if (x.is_number_integer())
    return std::to_string(x.get<long long>());
  if (x.is_object() && x.contains("Alphabetic") && x["Alphabetic"].is_string())
    return x["Alphabetic"].get<std::string>();
  return "";
}

std::string Refused(const std::string& what, const Response& r) {
  return "DICOMweb " + what + ": HTTP " + std::to_string(r.status) +
         (r.body.empty() ? "" : " (" + r.body.substr(0, 200) + ")");
}

/// The value of `param` in a Content-Type header (quoted or not), "" when absent.
std::string Parameter(const std::string& contentType, const std::string& param) {
  std::string lower = contentType;
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  const auto at = lower.find(param + "=");
  if (at == std::string::npos)
    return "";
  std::string v = contentType.substr(at + param.size() + 1);
  if (!v.empty() && v.front() == '"') {
    const auto end = v.find('"', 1);
    return end == std::string::npos ? "" : v.substr(1, end - 1);
  }
  return v.substr(0, v.find_first_of("; \t"));
}

/// The parts' bodies of a multipart/related body with `boundary`.
std::vector<std::string_view> Parts(const std::string& body, const std::string& boundary) {
  std::vector<std::string_view> parts;
  const std::string delimiter = "--" + boundary;
  size_t at = body.find(delimiter);
  while (at != std::string::npos) {
    size_t start = at + delimiter.size();
    if (body.compare(start, 2, "--") == 0)
      break; // the closing delimiter
    const size_t headersEnd = body.find("\r\n\r\n", start);
    if (headersEnd == std::string::npos)
      break;
    const size_t content = headersEnd + 4;
    const size_t next = body.find("\r\n" + delimiter, content);
    if (next == std::string::npos)
      throw std::runtime_error("a multipart part has no closing boundary");
    parts.emplace_back(body.data() + content, next - content);
    at = next + 2;
  }
  return parts;
}

} // namespace

bool IsDicomWebUrl(const std::string& text) {
  return text.rfind("http://", 0) == 0 || text.rfind("https://", 0) == 0;
}

std::vector<PacsSeries> FindSeriesWeb(const DicomWebServer& server, const PacsQuery& q) {
  CheckServer(server);
  std::string url = server.url + "/series?includefield=00201209&includefield=0008103E"
                                 "&includefield=00080020&includefield=00100010"
                                 "&includefield=00100020&includefield=00080050";
  const std::pair<const char*, const std::string*> keys[] = {
      {"PatientID", &q.patientId},
      {"PatientName", &q.patientName},
      {"AccessionNumber", &q.accessionNumber},
      {"StudyInstanceUID", &q.studyInstanceUid},
      {"SeriesInstanceUID", &q.seriesInstanceUid},
      {"Modality", &q.modality}};
  for (const auto& [key, value] : keys)
    if (!value->empty())
      url += std::string("&") + key + "=" + Escape(*value);
  const Response r = Request(server, "GET", url, {"Accept: application/dicom+json"});
  if (r.status == 204)
    return {};
  if (r.status != 200)
    throw std::runtime_error(Refused("query " + url, r));
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(r.body);
  } catch (const std::exception& e) {
    throw std::runtime_error("DICOMweb query " + url + ": the answer is not JSON (" + e.what() +
                             ")");
  }
  if (!j.is_array())
    throw std::runtime_error("DICOMweb query " + url + ": the answer is not a JSON array");
  std::vector<PacsSeries> found;
  for (const auto& o : j) {
    if (!o.is_object())
      continue;
    PacsSeries s;
    s.patientId = Value(o, "00100020");
    s.patientName = Value(o, "00100010");
    s.studyInstanceUid = Value(o, "0020000D");
    s.studyDate = Value(o, "00080020");
    s.accessionNumber = Value(o, "00080050");
    s.seriesInstanceUid = Value(o, "0020000E");
    s.modality = Value(o, "00080060");
    s.seriesDescription = Value(o, "0008103E");
    const std::string n = Value(o, "00201209");
    s.instances = n.empty() ? -1 : std::atoi(n.c_str());
    found.push_back(s);
  }
  return found;
}

int GetSeriesWeb(const DicomWebServer& server, const std::string& studyInstanceUid,
                 const std::string& seriesInstanceUid, const std::string& folder) {
  CheckServer(server);
  QuietDicomLog();
  if (seriesInstanceUid.empty())
    throw std::invalid_argument("fetching a series needs its Series Instance UID");
  FetchedSeries fetched(folder); // refuses a folder that exists
  PacsQuery q;
  q.studyInstanceUid = studyInstanceUid;
  q.seriesInstanceUid = seriesInstanceUid;
  q.modality.clear();
  const std::vector<PacsSeries> found = FindSeriesWeb(server, q);
  if (found.empty())
    throw std::runtime_error("DICOMweb " + server.url + " holds no series " + seriesInstanceUid);
  const std::string url = server.url + "/studies/" + Escape(found.front().studyInstanceUid) +
                          "/series/" + Escape(seriesInstanceUid);
  const Response r =
      Request(server, "GET", url, {"Accept: multipart/related; type=\"application/dicom\""});
  if (r.status != 200)
    throw std::runtime_error(Refused("retrieval " + url, r));
  const std::string boundary = Parameter(r.contentType, "boundary");
  if (r.contentType.rfind("multipart/related", 0) != 0 || boundary.empty())
    throw std::runtime_error("DICOMweb retrieval " + url + ": the answer is '" + r.contentType +
                             "', not multipart/related with a boundary");
  std::set<std::string> written;
  for (const std::string_view part : Parts(r.body, boundary)) {
    DcmInputBufferStream in;
    in.setBuffer(part.data(), offile_off_t(part.size()));
    in.setEos();
    DcmFileFormat f;
    f.transferInit();
    const OFCondition c = f.read(in);
    f.transferEnd();
    OFString sop;
    if (c.bad() || f.getDataset()->findAndGetOFString(DCM_SOPInstanceUID, sop).bad() || sop.empty())
      throw std::runtime_error("DICOMweb retrieval " + url + ": a part is not a DICOM instance" +
                               (c.bad() ? std::string(" (") + c.text() + ")" : ""));
    const fs::path file = fetched.InstancePath(sop.c_str());
    std::ofstream out(file, std::ios::binary);
    out.write(part.data(), std::streamsize(part.size()));
    if (!out)
      throw std::runtime_error("cannot write instance " + file.string());
    written.insert(sop.c_str());
  }
  return fetched.Commit("DICOMweb " + server.url, seriesInstanceUid, int(written.size()),
                        found.front().instances);
}

void StoreFilesWeb(const DicomWebServer& server, const std::vector<std::string>& files) {
  CheckServer(server);
  QuietDicomLog();
  if (files.empty())
    throw std::invalid_argument("no DICOM file to store");
  std::mt19937_64 rng(std::random_device{}());
  const std::string boundary = "bm-" + std::to_string(rng()) + "-" + std::to_string(rng());
  std::string body;
  for (const std::string& path : files) {
    DcmFileFormat f;
    if (f.loadFile(path.c_str(), EXS_Unknown, EGL_noChange, 4096).bad() ||
        !f.getMetaInfo()->tagExists(DCM_MediaStorageSOPClassUID))
      throw std::runtime_error("'" + path + "' is not a DICOM file with a meta header");
    std::ifstream in(path, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (!in && !in.eof())
      throw std::runtime_error("cannot read '" + path + "'");
    body += "--" + boundary + "\r\nContent-Type: application/dicom\r\n\r\n" + bytes + "\r\n";
  }
  body += "--" + boundary + "--\r\n";
  const std::string url = server.url + "/studies";
  const Response r =
      Request(server, "POST", url,
              {"Content-Type: multipart/related; type=\"application/dicom\"; boundary=" + boundary,
               "Accept: application/dicom+json"},
              body);
  if (r.status != 200)
    throw std::runtime_error(Refused("storage " + url, r));
  // A 200 may still list failed instances (Failed SOP Sequence).
  try {
    const nlohmann::json j = nlohmann::json::parse(r.body);
    if (j.is_object() && j.contains("00081198") && j["00081198"].contains("Value") &&
        !j["00081198"]["Value"].empty())
      throw std::runtime_error("DICOMweb storage " + url + ": the server failed " +
                               std::to_string(j["00081198"]["Value"].size()) + " instance(s)");
  } catch (const nlohmann::json::exception&) {
    // Not JSON: the status said it was stored.
  }
}

} // namespace bm
