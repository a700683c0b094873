// bmsim devices - the OpenCL devices `--backend opencl --cl-device D` can choose from.
#include <iostream>

#include "bmOpenCLDevice.h"
#include "bmsimArgs.h"
#include "bmsimCommand.h"

namespace {

void DevicesOptions(bm::cli::ParsedArgs& p) {
  p.Footer("Lists the OpenCL devices (number, type, name, platform, version, compute units, "
           "memory) and whether the OpenCL backend can use each (it needs double precision, "
           "cl_khr_fp64). --cl-device D (bmsim run, bench) takes the number or a part of the name; "
           "without it a usable GPU is preferred.");
}

int DevicesCommand(const bm::cli::ParsedArgs&) {
  const auto devices = bm::ListOpenCLDevices();
  if (devices.empty()) {
    std::cout << "no OpenCL device found (no OpenCL platform: install an ICD such as "
                 "pocl-opencl-icd or a GPU driver); --backend opencl falls back to the CPU "
                 "backend\n";
    return 0;
  }
  std::string preferred;
  try {
    bm::OpenCLDeviceInfo info;
    bm::ChooseOpenCLDevice("", &info);
    preferred = std::to_string(info.index);
  } catch (const std::exception&) {
  }
  for (const auto& d : devices) {
    std::cout << d.index << (std::to_string(d.index) == preferred ? " *" : "  ") << " [" << d.type
              << "] " << d.name << "\n      platform " << d.platform << ", " << d.version << ", "
              << d.computeUnits << " compute units, " << d.globalMemoryBytes / (1024 * 1024)
              << " MiB, " << (d.fp64 ? "fp64" : "NO fp64 (unusable)")
              << (d.int64Atomics ? ", int64 atomics" : "") << "\n";
  }
  if (!preferred.empty())
    std::cout << "* the default device\n";
  return 0;
}

} // namespace

BM_REGISTER_COMMAND(devices, "list the OpenCL devices the opencl backend can use", DevicesOptions,
                    DevicesCommand);
