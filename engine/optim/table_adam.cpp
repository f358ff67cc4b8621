#include "engine/optim/table_adam.h"

#include <cmath>

#include "engine/base/error.h"
#include "engine/base/shared_math.h"

namespace refrax::f32 {
#include "adam_update.glsl"
}  // namespace refrax::f32

namespace refrax {

TableAdam createTableAdam(uint32_t rowWidth, std::vector<AdamColumns> groups, size_t rows) {
  if (rowWidth == 0) fail("Adam table: a row must hold at least one float");
  for (const AdamColumns& g : groups)
    if (g.width == 0 || g.first + g.width > rowWidth) fail("Adam table: group '" + g.name + "' lies outside the row");
  TableAdam adam;
  adam.rowWidth = rowWidth;
  adam.groups = std::move(groups);
  adam.m.assign(rows * rowWidth, 0.0f);
  adam.v.assign(rows * rowWidth, 0.0f);
  return adam;
}

void tableAdamStep(TableAdam& adam, std::vector<float>& params, const std::vector<float>& grads, const AdamSettings& s) {
  const size_t w = adam.rowWidth, rows = params.size() / w;
  if (grads.size() != params.size() || adam.m.size() != params.size() || params.size() % w != 0) fail("Adam table: table sizes differ");
  const float b1 = float(s.beta1), b2 = float(s.beta2), eps = float(s.epsilon);
  for (auto& g : adam.groups) {
    g.step++;
    const float stepSize = float(g.lr.at(g.step) / (1.0 - std::pow(s.beta1, g.step)));
    const float invSqrtBc2 = float(1.0 / std::sqrt(1.0 - std::pow(s.beta2, g.step)));
    for (size_t i = 0; i < rows; i++)
      for (uint32_t c = 0; c < g.width; c++) {
        const size_t k = i * w + g.first + c;
        f32::adamUpdate(params[k], adam.m[k], adam.v[k], std::isfinite(grads[k]) ? grads[k] : 0.0f, b1, b2, eps, stepSize, invSqrtBc2);
      }
  }
}

double groupLearningRate(const TableAdam& adam, const std::string& name) {
  for (const auto& g : adam.groups)
    if (g.name == name) return g.lr.at(g.step);
  fail("Adam table: no group '" + name + "'");
}

void resetAdamColumns(TableAdam& adam, const std::string& name) {
  const size_t w = adam.rowWidth;
  for (auto& g : adam.groups) {
    if (g.name != name) continue;
    for (size_t i = 0; i < adam.m.size() / w; i++)
      for (uint32_t c = 0; c < g.width; c++) adam.m[i * w + g.first + c] = adam.v[i * w + g.first + c] = 0.0f;
    g.step = 0;
    return;
  }
  fail("Adam table: no group '" + name + "'");
}

void remapTableAdamRows(TableAdam& adam, const std::vector<uint32_t>& sourceRow) {
  const size_t w = adam.rowWidth, old = adam.m.size() / w;
  std::vector<float> m(sourceRow.size() * w, 0.0f), v(m.size(), 0.0f);
  for (size_t i = 0; i < sourceRow.size(); i++) {
    if (sourceRow[i] == kNewRow) continue;
    if (sourceRow[i] >= old) fail("Adam table: source row out of range");
    for (size_t c = 0; c < w; c++) {
      m[i * w + c] = adam.m[sourceRow[i] * w + c];
      v[i * w + c] = adam.v[sourceRow[i] * w + c];
    }
  }
  adam.m.swap(m);
  adam.v.swap(v);
}

}  // namespace refrax
