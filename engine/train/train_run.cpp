#include "engine/train/train_run.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cmath>
#include <filesystem>

#include "engine/dataset/ground_truth.h"
#include "engine/dataset/scene_bounds.h"
#include "engine/base/error.h"
#include "engine/io/atomic_file.h"
#include "engine/io/json_io.h"
#include "engine/io/npy.h"
#include "engine/gaussian/ply_gaussians.h"
#include "engine/train/checkpoint.h"
#include "engine/train/init_gaussians.h"
#include "engine/train/model_sizing.h"
#include "engine/train/plane_sweep.h"
#include "engine/model/render_model.h"
#include "engine/run/train_views.h"
#include "engine/vk/vk_commands.h"
#include "engine/vk/vk_context.h"
#include "engine/vk/vk_profile.h"

namespace refrax {

void resolveSceneConfig(TrainConfig& c, const Dataset& d) {
  const auto& train = d.split("train");
  d.split("test");  // an evaluation needs test views: refrax::Error when absent
  std::vector<Camera> cams;
  for (const auto& v : train) cams.push_back(v.camera);
  if (!d.water.height)
    fail("the water height is unknown: give it in " + d.root + "/water.json ('height') or with --water-height");
  c.ior = d.water.ior;
  c.waterHeight = *d.water.height;
  c.domain = d.water.domain ? *d.water.domain : surfaceDomainFromCameras(cams, c.waterHeight);
  c.depth = d.water.depth ? *d.water.depth : estimateWaterDepth(train, c.waterHeight, c.ior);
  Box b = gaussianBoxFromRefractedFrusta(cams, c.waterHeight, c.ior, c.depth);
  for (int a = 0; a < 3; a++) {
    c.boxMin[a] = b.min[a];
    c.boxMax[a] = b.max[a];
  }
  if (c.initPoints && d.points.empty())
    fail("--init-points: " + d.root + " has no sparse points under the water: it has no sparse points at all (only COLMAP models carry "
         "them, in points3D)");
  char heightText[32];
  std::snprintf(heightText, sizeof heightText, "%.4g", c.waterHeight);
  if (c.initPoints &&
      std::none_of(d.points.begin(), d.points.end(), [&](const SparsePoint& p) { return underWater(p, c.waterHeight); }))
    fail("--init-points: " + d.root + " has no sparse points under the water: all " + std::to_string(d.points.size()) +
         " of its sparse points lie at or above the water height " + std::string(heightText) +
         " (check --water-height or water.json's \"height\" against `refrax inspect`)");
  c.extent = sceneExtent(cams);
  applyModelSizing(c, cams);  // after the domain: the sizing reads what the views see of it
  if (c.gaussiansFixed && c.gaussiansFrom.empty()) fail("--gaussians-fixed needs --gaussians-from PLY: fixed random Gaussians learn nothing");
  if (!c.gaussiansFrom.empty()) {
    if (c.initPoints || c.initDepth != InitDepth::Box) fail("--gaussians-from replaces the drawn Gaussians: it takes no --init-points or --init-depth");
    const size_t count = readGaussiansPly(c.gaussiansFrom).count();  // refrax::Error naming the file
    if (count == 0) fail("--gaussians-from " + c.gaussiansFrom + " holds no Gaussians");
    c.initialGaussians = uint32_t(count);
    c.maxGaussians = std::max(c.maxGaussians, c.initialGaussians);
  }
  for (const Camera& cam : cams)
    if (c.patch > 0 && (int(c.patch) > cam.width || int(c.patch) > cam.height))
      fail("--patch " + std::to_string(c.patch) + " is larger than the " + std::to_string(cam.width) + " x " + std::to_string(cam.height) +
           " training images (0 trains on whole images)");
  resolveSchedule(c);
  validateTrainConfig(c);
  if (c.model == WaterModel::KnownWater) loadKnownWater(d);  // refused before any device work
}

namespace {

std::string evaluationsPath(const std::string& runDir) { return (std::filesystem::path(runDir) / "evaluations.json").string(); }
std::string surfaceWatchPath(const std::string& runDir) { return (std::filesystem::path(runDir) / "surface_watch.json").string(); }

// The learned water is watched for roughening (engine/surface/surface_watch.h) once it learns.
bool watchesSurface(const TrainSession& s) { return s.model.config.model == WaterModel::Refraction && s.model.height && s.model.surface; }

// About a hundred samples a run, whatever its progress lines.
int surfaceWatchInterval(const TrainConfig& c) { return std::max(1, c.steps / 100); }  // the water's run, not a refit

// Above this ratio of plane-sweep costs (learned water over flat) the run warns that its surface
// may be further from the truth than the flat start. Why 1.02 and not 1: on 24 tiny-preset runs
// (docs/experiments/2026-11-27-surface-checks.md) every run above 1.02 had ended worse than the
// flat start (6 of 14 such runs), and no better one read above 1.016; on 15 more, held out,
// both warnings were right (and 11 worse runs read below).
constexpr double kAgreementWarning = 1.02;

std::string surfaceAgreementLine(const nlohmann::json& a) {
  const double ratio = a["ratio"].get<double>();
  char text[480];
  if (ratio > kAgreementWarning)
    std::snprintf(text, sizeof text,
                  "warning: the training views agree less through the learned water than through the flat start (plane-sweep colour "
                  "variance %.3gx the flat water's over %zu cells): the surface may be further from the truth than the flat start "
                  "(docs/training.md, \"Is the learned water right?\")",
                  ratio, a["cells"].get<size_t>());
  else
    std::snprintf(text, sizeof text,
                  "the training views' plane-sweep colour variance through the learned water is %.3gx the flat start's (over %zu cells; "
                  "the run warns above %.3gx)",
                  ratio, a["cells"].get<size_t>(), kAgreementWarning);
  return text;
}

std::string mirrorWarningLine(double mirrorRatio) {
  char text[400];
  std::snprintf(text, sizeof text,
                "warning: the training views agree more through the learned water's mirror image about the water height (plane-sweep "
                "colour variance %.3gx the learned water's): the waves may be learned upside down; --water-sign-check with "
                "--restart-gaussians checks this during training (docs/training.md)",
                mirrorRatio);
  return text;
}

// The line after a restart step's --water-sign-check.
std::string signCheckLine(const WaterSignCheck& c) {
  char text[480];
  std::snprintf(text, sizeof text,
                "step %d: the training views' plane-sweep colour variance through the learned water is %.3gx flat water's, "
                "through its mirror image %.3gx the learned water's: %s",
                c.step, c.flat.reference > 0 ? c.flat.cost / c.flat.reference : 0.0,
                c.agreement.reference > 0 ? c.agreement.cost / c.agreement.reference : 0.0,
                c.mirrored ? "the mirror image kept" : "the learned water kept");
  return text;
}

// The line after a restart step's --water-scale-search.
std::string scaleSearchLine(const WaterScaleSearch& c) {
  std::string ratios;
  for (size_t k = 0; k < c.ratios.size(); k++) {
    char one[48];
    std::snprintf(one, sizeof one, "%s%gx: %.3g", k ? ", " : "", kWaterScales[k], c.ratios[k]);
    ratios += one;
  }
  char text[400];
  std::snprintf(text, sizeof text, "step %d: plane-sweep colour variance through the learned water's relief scaled (%s of the learned's): %gx kept",
                c.step, ratios.c_str(), c.chosen);
  return text;
}

// The line after a restart step's --surface-gate.
std::string gateLine(const SurfaceGateCheck& c) {
  char text[400];
  const double ratio = c.agreement.reference > 0 ? c.agreement.cost / c.agreement.reference : 0.0;
  std::snprintf(text, sizeof text, "step %d: the training views' plane-sweep colour variance through the learned water is %.3gx flat water's: %s",
                c.step, ratio,
                c.reset ? "they agree less through it than through flat water, so the water starts again from flat (--surface-gate)"
                        : "the learned water kept");
  return text;
}

// The line after a restart step that --restart-gate passed by.
std::string restartGateLine(const RestartGateCheck& c) {
  char text[400];
  const double ratio = c.agreement.reference > 0 ? c.agreement.cost / c.agreement.reference : 0.0;
  std::snprintf(text, sizeof text,
                "step %d: the training views agree no more through the learned water than through flat water (plane-sweep colour "
                "variance %.3gx flat water's): the Gaussians keep fitting, not drawn afresh (--restart-gate)",
                c.step, ratio);
  return text;
}

// The line after a --sweep-watch check that rolled the water back.
std::string watchLine(const SweepWatchCheck& c) {
  char text[400];
  const double ratio = c.agreement.reference > 0 ? c.agreement.cost / c.agreement.reference : 0.0;
  std::snprintf(text, sizeof text,
                "step %d: the training views agree less through the learned water than through flat water (plane-sweep colour "
                "variance %.3gx), so it goes back to the water they agreed on best and its learning rate is %.3gx the configured "
                "(--sweep-watch)",
                c.step, ratio, c.learningRateScale);
  return text;
}

// A resumed run's samples up to its checkpoint (kept on disk as they grow, like evaluations).
std::vector<SurfaceWatchSample> readSurfaceWatch(const std::string& runDir, int upToStep) {
  std::vector<SurfaceWatchSample> kept;
  const std::string path = surfaceWatchPath(runDir);
  if (!fileExists(path)) return kept;
  for (const SurfaceWatchSample& w : surfaceWatchFromJson(readJson(path), path))
    if (w.step <= upToStep) kept.push_back(w);
  return kept;
}

// One point of the accuracy-against-time curve: the metrics after `step`, and the wall time
// spent in training steps up to it (evaluations themselves are not counted).
nlohmann::json evaluationPoint(const TrainSession& s, const nlohmann::json& m) {
  nlohmann::json e = {{"step", s.model.step}, {"seconds", s.model.trainingSeconds}, {"psnr", m["psnr"]}, {"ssim", m["ssim"]}};
  if (m.contains("surface_rmse")) e["surface_rmse"] = m["surface_rmse"];
  return e;
}

}  // namespace

nlohmann::json readEvaluations(const std::string& runDir, int upToStep) {
  nlohmann::json kept = nlohmann::json::array();
  std::string path = evaluationsPath(runDir);
  if (!fileExists(path)) return kept;
  nlohmann::json all = readJson(path);
  if (!all.is_array()) fail(path + ": not an array of evaluations");
  for (const auto& e : all)
    if (e.is_object() && e.contains("step") && e["step"].is_number_integer() && e["step"].get<int>() <= upToStep) kept.push_back(e);
  return kept;
}

namespace {

// A JSON array of one object per item.
template <class T, class Row>
nlohmann::json jsonRows(const std::vector<T>& items, const Row& row) {
  nlohmann::json rows = nlohmann::json::array();
  for (const T& item : items) rows.push_back(row(item));
  return rows;
}

}  // namespace

nlohmann::json writeRunOutputs(TrainSession& s, const std::string& runDir) {
  namespace fs = std::filesystem;
  fs::path dir(runDir);
  fs::create_directories(dir / "renders");
  pullGaussians(s);
  writeGaussiansPly((dir / "point_cloud.ply").string(), s.model.gaussians);
  if (s.model.config.model != WaterModel::NoRefraction) {
    uint32_t n = s.model.config.gridCells + 1;
    NpyArray a;
    a.shape = {n, n};
    a.data = sampleWaterHeights(s.model, n, n);
    writeNpy((dir / "water_height.npy").string(), a);
  }
  if (s.model.height) saveHeightField((dir / "height_field.bin").string(), *s.model.ctx, *s.model.height);
  nlohmann::json m = evaluateModel(s.model, s.dataset, (dir / "renders").string());
  m["water_height_domain"] = {s.model.config.domain.xMin, s.model.config.domain.yMin, s.model.config.domain.xMax, s.model.config.domain.yMax};
  if (s.model.config.model == WaterModel::FlatWater) m["flat_water_height"] = s.model.planeHeight;
  nlohmann::json evaluations = readEvaluations(runDir, s.model.step - 1);
  evaluations.push_back(evaluationPoint(s, m));
  m["evaluations"] = evaluations;
  // The oracle's water is checked too: how much better the views agree through the true water
  // than through flat water is how well this capture determines its water at all.
  if (watchesSurface(s) || s.model.config.model == WaterModel::KnownWater) {
    const SweepAgreement a = agreementWithFlatWater(s);
    if (a.cells == 0 || !(a.reference > 0)) {
      // Fewer than the sweep's minimum of views see any cell (two training views, or views that
      // barely overlap), or the views agree exactly through the flat water: the check has
      // nothing to compare, and a run that stayed quiet would read as a surface that passed.
      m["surface_unchecked"] = a.cells == 0 ? "no water cell is seen by " + std::to_string(PlaneSweepConfig{}.minViews) +
                                                  " of the training views, the plane sweep's minimum"
                                            : std::string("the training views agree exactly through the flat water");
    } else {
      const double ratio = a.cost / a.reference;
      m["surface_agreement"] = {{"sweep_cost", a.cost}, {"flat_sweep_cost", a.reference}, {"ratio", ratio}, {"cells", a.cells},
                                {"warned", ratio > kAgreementWarning}};
      m["surface_sweep_ratio"] = ratio;  // the report's column
    }
    if (s.model.height) {
      const SweepAgreement mirror = agreementOfMirror(s);
      if (mirror.cells > 0 && mirror.reference > 0 && m.contains("surface_agreement")) {
        m["surface_agreement"]["mirror_ratio"] = mirror.cost / mirror.reference;
        m["surface_agreement"]["mirror_better"] = mirror.cost < kMirrorBetter * mirror.reference;
      }
    }
  }
  // the restarts' checks of this process (a resumed run's start at its checkpoint)
  auto ratio = [](const SweepAgreement& a) { return a.reference > 0 ? a.cost / a.reference : 0.0; };
  if (!s.log.signChecks.empty())
    m["water_sign_checks"] = jsonRows(s.log.signChecks, [&](const WaterSignCheck& c) -> nlohmann::json {
      return {{"step", c.step}, {"learned_sweep_cost", c.agreement.reference}, {"mirror_sweep_cost", c.agreement.cost},
              {"cells", c.agreement.cells}, {"flat_ratio", ratio(c.flat)}, {"mirrored", c.mirrored}};
    });
  if (!s.log.sweepLosses.empty())
    m["sweep_losses"] = jsonRows(s.log.sweepLosses, [&](const RunLog::SweepLossPoint& p) -> nlohmann::json {
      return {{"step", p.step}, {"per_ray", p.perRay}, {"rays", p.rays}};
    });
  if (!s.log.scaleSearches.empty())
    m["water_scale_searches"] = jsonRows(s.log.scaleSearches, [&](const WaterScaleSearch& c) -> nlohmann::json {
      return {{"step", c.step}, {"scales", std::vector<double>(std::begin(kWaterScales), std::end(kWaterScales))},
              {"sweep_ratios", c.ratios}, {"cells", c.cells}, {"chosen", c.chosen}};
    });
  if (!s.log.gateChecks.empty())
    m["surface_gate_checks"] = jsonRows(s.log.gateChecks, [&](const SurfaceGateCheck& c) -> nlohmann::json {
      return {{"step", c.step}, {"learned_sweep_cost", c.agreement.cost}, {"flat_sweep_cost", c.agreement.reference},
              {"cells", c.agreement.cells}, {"ratio", ratio(c.agreement)}, {"reset", c.reset}};
    });
  if (!s.log.restartGateChecks.empty())
    m["restart_gate_checks"] = jsonRows(s.log.restartGateChecks, [&](const RestartGateCheck& c) -> nlohmann::json {
      return {{"step", c.step}, {"learned_sweep_cost", c.agreement.cost}, {"flat_sweep_cost", c.agreement.reference},
              {"cells", c.agreement.cells}, {"ratio", ratio(c.agreement)}, {"restarted", c.restarted}};
    });
  if (!s.log.watchChecks.empty())
    m["sweep_watch_checks"] = jsonRows(s.log.watchChecks, [&](const SweepWatchCheck& c) -> nlohmann::json {
      return {{"step", c.step}, {"learned_sweep_cost", c.agreement.cost}, {"flat_sweep_cost", c.agreement.reference},
              {"cells", c.agreement.cells}, {"ratio", ratio(c.agreement)}, {"best", c.best}, {"rolled_back", c.rolledBack},
              {"learning_rate_scale", c.learningRateScale}};
    });
  if (!s.log.surfaceWatch.empty()) {
    m["surface_watch"] = surfaceWatchJson(s.log.surfaceWatch);
    const RougheningVerdict verdict = judgeRoughening(s.log.surfaceWatch, s.model.config.schedule.surfaceFreeze + 1);
    m["surface_roughening"] = rougheningJson(verdict);
    if (verdict.judged) m["surface_roughened"] = verdict.roughening;  // the report's column
  }
  if (s.log.profiler.steps > 0) {
    m["profile"] = profileJson(s.log.profiler);
    // Steps the host did not wait for before recording the next (TrainSession::deferSteps).
    m["profile"]["steps_not_waited_for"] = s.log.deferredSteps;
  }
  writeJson((dir / "metrics.json").string(), m);
  return m;
}

namespace {

// What a step that was waited for says about its events (a restart and its checks, a gate, a
// rollback).
void sayStepEvents(const TrainSession& s, const StepResult& r, const std::function<void(const std::string&)>& say) {
  const TrainConfig& c = s.model.config;
  if (r.restarted) {
    std::string how = c.initDepth == InitDepth::Sweep ? ", at the plane sweep's depth in " + std::to_string(int(std::lround(100 * s.log.sweptCellFraction))) + "% of the cells" : "";
    if (c.initPoints) how += ", " + std::to_string(s.log.gaussiansAtPoints) + " at sparse points";
    if (!s.log.gateChecks.empty() && s.log.gateChecks.back().step == s.model.step) say(gateLine(s.log.gateChecks.back()));
    if (!s.log.signChecks.empty() && s.log.signChecks.back().step == s.model.step) say(signCheckLine(s.log.signChecks.back()));
    if (!s.log.scaleSearches.empty() && s.log.scaleSearches.back().step == s.model.step) say(scaleSearchLine(s.log.scaleSearches.back()));
    say("step " + std::to_string(s.model.step) + ": the Gaussians drawn afresh (" + std::to_string(r.gaussians) + how + ")");
  }
  if (r.refitStarted)
    say("step " + std::to_string(s.model.step) + ": the refit: " + std::to_string(c.schedule.refitSteps) + " steps of Gaussians drawn afresh (" +
        std::to_string(r.gaussians) + ") under the water as learned, held fixed");
  if (!s.log.restartGateChecks.empty() && s.log.restartGateChecks.back().step == s.model.step && !s.log.restartGateChecks.back().restarted)
    say(restartGateLine(s.log.restartGateChecks.back()));
  if (!s.log.watchChecks.empty() && s.log.watchChecks.back().step == s.model.step && s.log.watchChecks.back().rolledBack)
    say(watchLine(s.log.watchChecks.back()));
}

}  // namespace

nlohmann::json trainToEnd(TrainSession& s, const std::string& runDir, const TrainProgress& progress) {
  const TrainConfig& c = s.model.config;
  auto start = std::chrono::steady_clock::now();
  int first = s.model.step;
  auto say = [&](const std::string& text) {
    if (progress.line) progress.line(text);
  };
  const double startSeconds = s.model.trainingSeconds;
  if (watchesSurface(s) && s.log.surfaceWatch.empty() && s.model.step > 0) s.log.surfaceWatch = readSurfaceWatch(runDir, s.model.step);
  double watchLoss = 0;  // image loss summed since the last surface sample
  int watchSteps = 0;
  // Steps not waited for (TrainSession::deferSteps): their losses are read once they have run,
  // at the next step that is waited for (every surface-watch sample's is), in step order.
  const char* sync = std::getenv("REFRAX_STEP_SYNC");
  s.deferSteps = !(sync && std::string(sync) == "1");
  s.syncEvery = surfaceWatchInterval(c);
  std::vector<int> pendingSteps;
  auto settlePending = [&] {
    for (int k : pendingSteps) {
      const StepLosses l = readStepLosses(s, k);
      if (!std::isfinite(l.image + l.density)) fail("training diverged at step " + std::to_string(k) + ": the loss is not finite");
      watchLoss += l.image;
      watchSteps++;
    }
    pendingSteps.clear();
  };
  const int last = totalSteps(c);
  while (s.model.step < last) {
    if (progress.timeLimitSeconds > 0 && s.model.trainingSeconds - startSeconds >= progress.timeLimitSeconds) {
      say("stopping at step " + std::to_string(s.model.step) + " of " + std::to_string(last) + ": the time limit (" +
          std::to_string(int(progress.timeLimitSeconds)) + " s of training) is reached; --resume continues");
      break;
    }
    auto stepStart = std::chrono::steady_clock::now();
    attachProfiler(*s.model.ctx, s.log.profiler);
    StepResult r = trainStep(s);
    detachProfiler(*s.model.ctx);
    profileStepEnd(s.log.profiler, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - stepStart).count());
    if (r.pending) {  // no event at this step, nothing to say: its loss is read later
      s.log.deferredSteps++;
      pendingSteps.push_back(s.model.step);
      if (pendingSteps.size() >= kLossLogRows / 2) settlePending();  // before the log's rows come round again
    } else {
      settlePending();
      sayStepEvents(s, r, say);
      watchLoss += r.imageLoss;
      watchSteps++;
    }
    // The watch samples the water's run, not the refit's (the water held, its Gaussians fresh).
    const int watchEnd = c.steps;
    if ((s.model.step % surfaceWatchInterval(c) == 0 || s.model.step == watchEnd) && s.model.step <= watchEnd && watchesSurface(s) &&
        s.log.surfaceShapeMeasured) {
      s.log.surfaceWatch.push_back({s.model.step, watchLoss / watchSteps, s.log.surfaceShape});
      watchLoss = 0;
      watchSteps = 0;
    }
    if (s.model.step % c.progressEvery == 0 || s.model.step == last) {
      double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      double rate = (s.model.step - first) / std::max(elapsed, 1e-9);
      char line[256];
      std::snprintf(line, sizeof line, "step %6d/%d  loss %.5f  psnr %6.2f  gaussians %u  %.2f steps/s  eta %.0f s", s.model.step, last, r.loss,
                    r.psnr, r.gaussians, rate, (last - s.model.step) / std::max(rate, 1e-9));
      say(std::string(line) + (progress.profile ? "  | " + profileTop(s.log.profiler, 3) : ""));
    }
    // An evaluation traces the water and a checkpoint saves the gradient summed so far.
    const bool evaluate = c.evalEvery > 0 && s.model.step % c.evalEvery == 0 && s.model.step < last;
    const bool checkpoint = c.checkpointEvery > 0 && s.model.step % c.checkpointEvery == 0;
    if (evaluate || checkpoint) pushWaterGradient(s);
    if (evaluate) {
      nlohmann::json m = evaluateModel(s.model, s.dataset, "");
      // Kept on disk as it grows, so a resumed run's curve still starts at step 0.
      nlohmann::json evaluations = readEvaluations(runDir, s.model.step - 1);
      evaluations.push_back(evaluationPoint(s, m));
      writeJson(evaluationsPath(runDir), evaluations);
      char line[160];
      std::snprintf(line, sizeof line, "eval step %d: test psnr %.3f ssim %.4f", s.model.step, m["psnr"].get<double>(), m["ssim"].get<double>());
      say(line);
    }
    if (checkpoint) saveCheckpoint(s, runDir);
    if (checkpoint && !s.log.surfaceWatch.empty()) writeJson(surfaceWatchPath(runDir), surfaceWatchJson(s.log.surfaceWatch));
  }
  settlePending();
  s.deferSteps = false;
  pushWaterGradient(s);
  if (latestCheckpoint(runDir) != checkpointPath(runDir, s.model.step)) saveCheckpoint(s, runDir);
  if (!s.log.surfaceWatch.empty()) writeJson(surfaceWatchPath(runDir), surfaceWatchJson(s.log.surfaceWatch));
  nlohmann::json m = writeRunOutputs(s, runDir);
  if (m.contains("surface_roughening") && m["surface_roughening"]["judged"].get<bool>())
    say(std::string(m["surface_roughening"]["roughening"].get<bool>() ? "warning: " : "") + m["surface_roughening"]["text"].get<std::string>());
  if (m.contains("surface_unchecked"))
    say("warning: the run cannot check its learned water (" + m["surface_unchecked"].get<std::string>() +
        "): a surface further from the truth than the flat start would go unsaid (docs/training.md, \"Is the learned water right?\")");
  if (m.contains("surface_agreement")) {
    say(surfaceAgreementLine(m["surface_agreement"]));
    if (m["surface_agreement"].value("mirror_better", false))
      say(mirrorWarningLine(m["surface_agreement"]["mirror_ratio"].get<double>()));
  }
  return m;
}

std::unique_ptr<TrainSession> openRun(Context& ctx, const std::string& runDir, bool requireCheckpoint) {
  TrainConfig c = readRunConfig(runDir);
  std::string ckpt = latestCheckpoint(runDir);
  if (ckpt.empty() && requireCheckpoint) fail(runDir + " has no checkpoint yet");
  auto s = createTrainSession(ctx, c, loadRunDataset(c));
  if (!ckpt.empty()) loadCheckpoint(*s, ckpt);
  return s;
}

}  // namespace refrax
