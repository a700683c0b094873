// bmOpenCLBackend.h - the "opencl" backend of bmEngineFactory.h.
#pragma once

namespace bm {

/// Registers the backend "opencl": the method of the context's force model picks
/// bm::OpenCLEngine (lazar) or bm::OpenCLZhengEngine (zheng); EngineContext::device picks the
/// device (ChooseOpenCLDevice). Making an engine throws std::runtime_error when OpenCL is missing
/// or the device unusable. Safe to call more than once.
void RegisterOpenCLBackend();

} // namespace bm
