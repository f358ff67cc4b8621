// What a checkpoint saves (CheckpointContents) round-trips field by field: a session's
// contents, saved, loaded into a fresh session of the same config and read again, are equal
// in every field, for the learned MLP water and the learned flat plane (each field is
// exercised by at least one of them: the test also asserts none of them is left at its default).
#include <doctest/doctest.h>

#include <tuple>
#include <utility>

#include "engine/run/checkpoint_format.h"
#include "engine/train/checkpoint.h"
#include "tests/gpu_test.h"
#include "tests/train_test_util.h"

namespace refrax {
namespace {

// Every field of CheckpointContents, in order. The structured binding names exactly as many
// fields as the struct has: adding or removing one stops this file compiling, so a new field
// cannot slip past the comparison below.
auto fieldsOf(const CheckpointContents& c) {
  const auto& [model, step, trainingSeconds, rng, viewOrder, viewCursor, gaussians, params, adamM, adamV, groupSteps, densifyStats,
               heightCount, heightWeights, heightM, heightV, heightGrad, heightStep, planeHeight, planeM, planeV, planeGrad, planeStep] = c;
  return std::tie(model, step, trainingSeconds, rng, viewOrder, viewCursor, gaussians, params, adamM, adamV, groupSteps, densifyStats,
                  heightCount, heightWeights, heightM, heightV, heightGrad, heightStep, planeHeight, planeM, planeV, planeGrad, planeStep);
}
constexpr const char* kFieldNames[] = {"model",        "step",        "trainingSeconds", "rng",         "viewOrder",    "viewCursor",
                                       "gaussians",    "params",      "adamM",           "adamV",       "groupSteps",   "densifyStats",
                                       "heightCount",  "heightWeights", "heightM",       "heightV",     "heightGrad",   "heightStep",
                                       "planeHeight",  "planeM",      "planeV",          "planeGrad",   "planeStep"};
constexpr size_t kFields = std::tuple_size_v<decltype(fieldsOf(std::declval<const CheckpointContents&>()))>;
static_assert(std::size(kFieldNames) == kFields, "a name per field");

// Calls f(name, a's field, b's field) for every field.
template <class F, size_t... I>
void forEachFieldPair(const CheckpointContents& a, const CheckpointContents& b, F&& f, std::index_sequence<I...>) {
  const auto fa = fieldsOf(a), fb = fieldsOf(b);
  (f(kFieldNames[I], std::get<I>(fa), std::get<I>(fb)), ...);
}
template <class F>
void forEachFieldPair(const CheckpointContents& a, const CheckpointContents& b, F&& f) {
  forEachFieldPair(a, b, f, std::make_index_sequence<kFields>{});
}

void requireSameContents(const CheckpointContents& saved, const CheckpointContents& restored) {
  forEachFieldPair(saved, restored, [](const char* name, const auto& x, const auto& y) { CHECK_MESSAGE(x == y, "field " << std::string(name)); });
}

// The fields of `c` that hold something other than a default-constructed CheckpointContents'.
std::vector<std::string> setFields(const CheckpointContents& c) {
  std::vector<std::string> set;
  forEachFieldPair(c, CheckpointContents{}, [&](const char* name, const auto& x, const auto& blank) {
    if (!(x == blank)) set.push_back(name);
  });
  return set;
}

// A session trained into the middle of a surface batch (so the water's gradient sum is not
// zero), its contents; saved, loaded into a fresh session, and that session's contents.
std::pair<CheckpointContents, CheckpointContents> roundTrip(Context& ctx, bool flatWater, uint64_t seed) {
  test::TrainTempDir dir;
  Dataset d;
  TrainConfig c = test::sessionConfig(test::tinyDataset("nerfrac-primary-sine"), 10, 200, 16, seed, d);
  c.mlpWidth = 16;
  c.mlpHiddenLayers = 1;
  c.schedule.surfaceFreeze = 0;
  c.surfaceLearningRate = 1e-2;
  c.surfaceBatch = 4;
  if (flatWater) c.model = WaterModel::FlatWater;
  auto first = createTrainSession(ctx, c, d);
  while (first->model.step < 7) trainStep(*first);  // 3 steps into the second surface batch; 7 of the 8 views
  const CheckpointContents saved = checkpointContents(*first);
  saveCheckpoint(*first, dir / "run");
  first.reset();
  auto second = createTrainSession(ctx, c, d);
  loadCheckpoint(*second, latestCheckpoint(dir / "run"));
  return {saved, checkpointContents(*second)};
}

}  // namespace

GPU_TEST_CASE("checkpoint: every field of the saved state round-trips through a file into a fresh session" *
              doctest::test_suite("one-backend")) {
  const auto [mlpSaved, mlpRestored] = roundTrip(ctx, false, rng());
  requireSameContents(mlpSaved, mlpRestored);
  const auto [flatSaved, flatRestored] = roundTrip(ctx, true, rng());
  requireSameContents(flatSaved, flatRestored);

  // Between them the two sessions set every field, so no comparison above was of two defaults.
  std::vector<std::string> set = setFields(mlpSaved);
  for (const std::string& f : setFields(flatSaved)) set.push_back(f);
  for (const char* name : kFieldNames) CHECK_MESSAGE(std::find(set.begin(), set.end(), name) != set.end(), "field " << std::string(name) << " never set");
}

}  // namespace refrax
