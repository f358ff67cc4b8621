#pragma once
// Whole-file reads and crash-safe writes: every output is written to a temporary file in
// the same directory and renamed over the target, so no reader ever sees half a file.
#include <cstddef>
#include <string>

namespace refrax {

void writeFileAtomic(const std::string& path, const void* data, size_t bytes);
void writeTextAtomic(const std::string& path, const std::string& text);
// The file's bytes; refrax::Error naming the path when it cannot be read.
std::string readFile(const std::string& path);
bool fileExists(const std::string& path);

}  // namespace refrax
