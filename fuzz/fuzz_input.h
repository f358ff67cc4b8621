#pragma once
// Shared by the fuzz targets (fuzz/README.md): the loaders read files, so each input is written
// to a file of this process's scratch folder first, and the one outcome besides success that
// a loader may have is refrax::Error (one clear message). Any other exception is a finding:
// it would reach the user as an unexplained failure; so are crashes and sanitizer reports.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>

#include "engine/base/error.h"

namespace refrax::fuzz {

// A folder of this process's own (several fuzzing jobs may run at once).
inline const std::string& scratch() {
  static const std::string dir = [] {
    auto d = std::filesystem::temp_directory_path() / ("refrax-fuzz-" + std::to_string(getpid()));
    std::filesystem::create_directories(d);
    return d.string();
  }();
  return dir;
}

inline std::string writeInput(const std::string& name, const uint8_t* data, size_t size) {
  std::string path = scratch() + "/" + name;
  std::ofstream(path, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(data), std::streamsize(size));
  return path;
}

template <class F>
int expectCleanError(F&& load) {
  try {
    load();
  } catch (const Error&) {
    // the loader's one clear error: fine
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fuzz: an exception other than refrax::Error escaped the loader: %s\n", e.what());
    std::abort();
  }
  return 0;
}

}  // namespace refrax::fuzz
