#pragma once
// JSON through nlohmann::json, with errors that name the file and what is wrong.
#include <nlohmann/json.hpp>
#include <string>

namespace refrax {

nlohmann::json readJson(const std::string& path);              // clear error on missing file or parse error
void writeJson(const std::string& path, const nlohmann::json& value, int indent = 2);  // atomic

// Typed field access with errors naming the file and field ("transforms.json: 'frames' must be an array").
const nlohmann::json& requireField(const nlohmann::json& object, const std::string& key, const std::string& where);
double requireNumber(const nlohmann::json& object, const std::string& key, const std::string& where);

}  // namespace refrax
