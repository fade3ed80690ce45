// libFuzzer target: the scene reader (see fuzz_entry.h). Only InputError may escape.
#include "core/error.h"
#include "fuzz_entry.h"

#include <iostream>

// Warnings of the mesh validator go to std::cerr; silence them (sanitizer reports and
// libFuzzer write to file descriptor 2 directly).
extern "C" int LLVMFuzzerInitialize(int*, char***) {
  std::cerr.rdbuf(nullptr);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    tissu::fuzz::scene_input(data, size);
  } catch (const tissu::InputError&) {
  }
  return 0;
}
