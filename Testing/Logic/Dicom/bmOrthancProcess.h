// bmOrthancProcess.h - a real PACS for the tests: Debian's Orthanc (/usr/sbin/Orthanc, installed
// by Utilities/setup-debian.sh) started on loopback with a configuration the test writes (its own
// storage folder, a free DICOM port, our calling AET registered; the HTTP server off, or on a free
// port with the DICOMweb plugin of Debian's orthanc-dicomweb), stopped (SIGTERM, then waited for)
// when the object goes.
#pragma once

#include <fcntl.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <thread>

namespace bmtest {

/// A TCP socket bound to a free port on 127.0.0.1 (the kernel's choice), listening when `listen`
/// (connections complete, nothing answers: a silent server). Returns the socket; `port` is set.
inline int LoopbackSocket(int& port, bool listen) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  a.sin_port = 0;
  socklen_t n = sizeof a;
  if (fd < 0 || ::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0 ||
      (listen && ::listen(fd, 4) != 0) ||
      ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &n) != 0) {
    if (fd >= 0)
      ::close(fd);
    throw std::runtime_error("no free loopback port");
  }
  port = ntohs(a.sin_port);
  return fd;
}

/// A TCP port on 127.0.0.1 nothing listens on now.
inline int FreeLoopbackPort() {
  int port = 0;
  ::close(LoopbackSocket(port, false));
  return port;
}

/// Whether something accepts TCP connections on 127.0.0.1:port.
inline bool Listening(int port) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  a.sin_port = htons(uint16_t(port));
  const bool ok = fd >= 0 && ::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0;
  if (fd >= 0)
    ::close(fd);
  return ok;
}

class OrthancProcess {
public:
  static constexpr const char* kExecutable = "/usr/sbin/Orthanc";
  static constexpr const char* kDicomWebPlugin = "/usr/share/orthanc/plugins/libOrthancDicomWeb.so";
  /// Starts Orthanc with AET `aet` in `folder` (created), knowing `callingAet` as a modality
  /// allowed to query and retrieve; with `dicomWeb`, also its DICOMweb service at WebUrl. Throws
  /// std::runtime_error when Orthanc (or the plugin) is not installed or does not listen within
  /// 30 s (its log is in folder/orthanc.log).
  explicit OrthancProcess(const std::filesystem::path& folder, bool dicomWeb = false,
                          const std::string& aet = "ORTHANC",
                          const std::string& callingAet = "BMSIM")
      : Folder(folder), Aet(aet) {
    if (::access(kExecutable, X_OK) != 0)
      throw std::runtime_error(std::string(kExecutable) +
                               " is not installed: Debian's orthanc package "
                               "(Utilities/setup-debian.sh installs it)");
    if (dicomWeb && ::access(kDicomWebPlugin, R_OK) != 0)
      throw std::runtime_error(std::string(kDicomWebPlugin) +
                               " is not installed: Debian's orthanc-dicomweb package "
                               "(Utilities/setup-debian.sh installs it)");
    std::filesystem::remove_all(folder);
    std::filesystem::create_directories(folder / "storage");
    Port = FreeLoopbackPort();
    const std::string config = (folder / "orthanc.json").string();
    {
      std::ofstream f(config);
      f << "{\"Name\": \"BMTEST\", \"StorageDirectory\": \"" << (folder / "storage").string()
        << "\", \"IndexDirectory\": \"" << (folder / "storage").string() << "\", \"DicomAet\": \""
        << aet << "\", \"DicomPort\": " << Port
        << ", \"RemoteAccessAllowed\": false, \"AuthenticationEnabled\": false,"
           " \"DicomCheckCalledAet\": true, \"ConcurrentJobs\": 1,"
           " \"DicomModalities\": {\"bm\": [\""
        << callingAet << "\", \"127.0.0.1\", " << FreeLoopbackPort() << "]}, ";
      if (dicomWeb) {
        HttpPort = FreeLoopbackPort();
        f << "\"HttpServerEnabled\": true, \"HttpPort\": " << HttpPort << ", \"Plugins\": [\""
          << kDicomWebPlugin
          << "\"], \"DicomWeb\": {\"Enable\": true, \"Root\": \"/dicom-web/\"}}\n";
        WebUrl = "http://127.0.0.1:" + std::to_string(HttpPort) + "/dicom-web";
      } else {
        f << "\"HttpServerEnabled\": false, \"Plugins\": []}\n";
      }
    }
    const std::string log = (folder / "orthanc.log").string();
    Pid = ::fork();
    if (Pid == 0) {
      const int out = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      if (out >= 0) {
        ::dup2(out, 1);
        ::dup2(out, 2);
      }
      ::execl(kExecutable, kExecutable, config.c_str(), static_cast<char*>(nullptr));
      ::_exit(127);
    }
    const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    while (!Listening(Port) || (dicomWeb && !Listening(HttpPort))) {
      int status = 0;
      if (Pid < 0 || ::waitpid(Pid, &status, WNOHANG) == Pid) {
        Pid = -1;
        throw std::runtime_error("Orthanc did not start (see " + log + ")");
      }
      if (std::chrono::steady_clock::now() > end) {
        Stop();
        throw std::runtime_error("Orthanc did not listen on port " + std::to_string(Port) +
                                 " within 30 s (see " + log + ")");
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
  }
  ~OrthancProcess() { Stop(); }
  OrthancProcess(const OrthancProcess&) = delete;
  OrthancProcess& operator=(const OrthancProcess&) = delete;

  void Stop() {
    if (Pid > 0) {
      ::kill(Pid, SIGTERM);
      int status = 0;
      ::waitpid(Pid, &status, 0);
      Pid = -1;
    }
  }

  std::filesystem::path Folder;
  std::string Aet;
  int Port = 0;       ///< DICOM
  int HttpPort = 0;   ///< with DICOMweb
  std::string WebUrl; ///< the DICOMweb root, with DICOMweb

private:
  pid_t Pid = -1;
};

} // namespace bmtest
