// The host Adam for tables (engine/optim/table_adam.h), on the Gaussians' table, against the double
// reference (engine/reference/adam_ref.h): every column group with its own learning rate and
// bias correction, a group reset midway, non-finite gradients taken as zero; and the row
// remapping densification needs.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "engine/base/error.h"
#include "engine/reference/adam_ref.h"
#include "engine/gaussian/gaussians.h"
#include "engine/gaussian/gaussian_adam.h"
#include "tests/gpu_test.h"

using namespace refrax;

TEST_CASE("Gaussian Adam matches the double reference per column group, through a group reset") {
  std::mt19937 rng(7);
  std::normal_distribution<float> N(0.0f, 1.0f);
  const size_t count = 5;
  const int lrSteps = 6;  // short, so the decaying groups change rate every step
  GaussianSet set;
  set.params.resize(count * kGaussianFloats);
  for (float& p : set.params) p = N(rng);
  TableAdam adam = createGaussianAdam(2.0, lrSteps, count);
  REQUIRE(adam.groups.size() == 6);

  // The reference: one Adam state per group, over the group's columns of every row.
  struct RefGroup {
    std::vector<double> p, m, v;
    int step = 0;
  };
  std::vector<RefGroup> ref(adam.groups.size());
  auto columns = [&](const AdamColumns& g, const std::vector<float>& table) {
    std::vector<double> out;
    for (size_t i = 0; i < count; i++)
      for (uint32_t c = 0; c < g.width; c++) out.push_back(table[i * kGaussianFloats + g.first + c]);
    return out;
  };
  for (size_t k = 0; k < ref.size(); k++) {
    ref[k].p = columns(adam.groups[k], set.params);
    ref[k].m.assign(ref[k].p.size(), 0.0);
    ref[k].v.assign(ref[k].p.size(), 0.0);
  }

  for (int step = 1; step <= 5; step++) {
    std::vector<float> grads(set.params.size());
    for (float& g : grads) g = N(rng) * (step % 2 ? 1e-3f : 10.0f);  // gradients of very different size
    grads[3] = NAN;                                                    // a bad ray's gradient: counts as 0
    grads[kGaussianFloats + 1] = INFINITY;
    tableAdamStep(adam, set.params, grads);
    std::vector<float> clean = grads;
    for (float& g : clean) g = std::isfinite(g) ? g : 0.0f;
    for (size_t k = 0; k < ref.size(); k++) {
      RefGroup& r = ref[k];
      r.step++;
      ref::adamStep(r.p, r.m, r.v, columns(adam.groups[k], clean), adam.groups[k].lr.at(r.step), r.step);
      CHECK(adam.groups[k].step == r.step);
      std::vector<double> got = columns(adam.groups[k], set.params);
      double worst = 0;
      for (size_t i = 0; i < got.size(); i++) {
        double e = std::abs(got[i] - r.p[i]) / std::max(1.0, std::abs(r.p[i]));
        if (!(e <= worst)) worst = e;  // a NaN propagates (std::max would drop it)
      }
      INFO("group " << adam.groups[k].name << " step " << step);
      CHECK(worst < 1e-5);  // float arithmetic against double
    }
    if (step == 2) {
      // 3DGS's density reset: that group's moments and bias correction start over.
      resetAdamColumns(adam, "density");
      for (size_t k = 0; k < ref.size(); k++)
        if (adam.groups[k].name == "density") {
          ref[k].m.assign(ref[k].m.size(), 0.0);
          ref[k].v.assign(ref[k].v.size(), 0.0);
          ref[k].step = 0;
        }
    }
  }
  CHECK_THROWS_AS(resetAdamColumns(adam, "opacity"), Error);
  CHECK_THROWS_AS(tableAdamStep(adam, set.params, std::vector<float>(3)), Error);
}

TEST_CASE("Table Adam: the flat water's one height (one row, one column) follows the double reference") {
  AdamColumns height;
  height.name = "water_height";
  height.width = 1;
  height.lr = LearningRateSchedule{0.02, 0.0002, 4};  // decays over the steps taken here
  TableAdam adam = createTableAdam(1, {height}, 1);
  std::vector<float> p{0.3f};
  std::vector<double> rp{0.3}, rm{0.0}, rv{0.0};
  const double grads[] = {0.5, -2.0, 1e-4, 3.0, -0.25};
  for (int step = 1; step <= 5; step++) {
    tableAdamStep(adam, p, {float(grads[step - 1])});
    ref::adamStep(rp, rm, rv, {grads[step - 1]}, height.lr.at(step), step);
    INFO("step " << step);
    CHECK(p[0] == doctest::Approx(rp[0]).epsilon(1e-6));
    CHECK(adam.groups[0].step == step);
  }
  AdamColumns outside;
  outside.name = "outside";
  outside.first = 1;
  outside.width = 1;
  CHECK_THROWS_AS(createTableAdam(1, {outside}, 1), Error);
}

TEST_CASE("Table Adam: remapping rows carries moments along, zeroes new rows, refuses bad rows") {
  std::mt19937 rng(test::freshSeed());
  const size_t rows = 300;
  TableAdam adam = createGaussianAdam(1.0, 100, rows);
  const size_t width = adam.rowWidth;
  std::normal_distribution<float> N(0.0f, 1.0f);
  for (auto& x : adam.m) x = N(rng);
  for (auto& x : adam.v) x = std::abs(N(rng));
  for (auto& g : adam.groups) g.step = 7;
  const std::vector<float> m = adam.m, v = adam.v;
  // prune every third row, clone some, split one into two new rows
  std::vector<uint32_t> source;
  for (uint32_t r = 0; r < rows; r++)
    if (r % 3) source.push_back(r);
  source.push_back(5);
  source.push_back(kNewRow);
  source.push_back(kNewRow);
  std::shuffle(source.begin(), source.end(), rng);
  remapTableAdamRows(adam, source);
  REQUIRE(adam.m.size() == source.size() * width);
  REQUIRE(adam.v.size() == source.size() * width);
  for (const auto& g : adam.groups) CHECK(g.step == 7);  // torch keeps a tensor's step count across 3DGS's replacements
  size_t bad = 0;
  for (size_t i = 0; i < source.size(); i++)
    for (size_t k = 0; k < width; k++) {
      float em = source[i] == kNewRow ? 0.0f : m[source[i] * width + k];
      float ev = source[i] == kNewRow ? 0.0f : v[source[i] * width + k];
      if (adam.m[i * width + k] != em || adam.v[i * width + k] != ev) bad++;
    }
  CHECK(bad == 0);
  const std::vector<float> kept = adam.m;
  CHECK_THROWS_AS(remapTableAdamRows(adam, {0, uint32_t(source.size())}), Error);
  CHECK(adam.m == kept);  // unchanged after the refusal
  remapTableAdamRows(adam, {});
  CHECK(adam.m.empty());
}
