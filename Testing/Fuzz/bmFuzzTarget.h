// bmFuzzTarget.h - the entry point every fuzz target defines (libFuzzer's): one input, refused or
// accepted, never a crash, a hang or a sanitizer report. Built with libFuzzer (clang, BM_FUZZ=ON)
// or with bmFuzzDriver.cxx's deterministic mutation driver.
#pragma once

#include <cstddef>
#include <cstdint>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);
