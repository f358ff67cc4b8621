#include "engine/io/json_io.h"

#include <cmath>

#include "engine/base/error.h"
#include "engine/io/atomic_file.h"

namespace refrax {

nlohmann::json readJson(const std::string& path) {
  std::string text = readFile(path);
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    fail("malformed JSON in " + path + " (byte " + std::to_string(e.byte) + ")");
  } catch (const nlohmann::json::exception& e) {  // e.g. a number out of range such as 1e999
    fail("malformed JSON in " + path + ": " + e.what());
  }
}

void writeJson(const std::string& path, const nlohmann::json& value, int indent) {
  writeTextAtomic(path, value.dump(indent) + "\n");
}

const nlohmann::json& requireField(const nlohmann::json& object, const std::string& key, const std::string& where) {
  if (!object.is_object()) fail(where + ": expected a JSON object");
  auto it = object.find(key);
  if (it == object.end()) fail(where + ": missing '" + key + "'");
  return *it;
}

double requireNumber(const nlohmann::json& object, const std::string& key, const std::string& where) {
  const nlohmann::json& v = requireField(object, key, where);
  if (!v.is_number()) fail(where + ": '" + key + "' must be a number");
  double d = v.get<double>();
  if (!std::isfinite(d)) fail(where + ": '" + key + "' is not finite");
  return d;
}

}  // namespace refrax
