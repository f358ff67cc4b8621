#pragma once
// One training run's state on the device and the host, and one optimisation step
// (docs/method.md §1.6, paper §3-4):
//   camera rays (a whole training image or a random patch of it)
//   -> water surface forward (refracted rays; skipped for --no-refraction)
//   -> Gaussian forward -> 0.8 L1 + 0.2 (1 - SSIM) + 0.007 mean(density^2)
//   -> Gaussian backward (per-Gaussian gradients, per-ray dL/d(origin, direction))
//   -> surface backward -> dL/dheight at the lattice points, summed over the surface batch
//   -> at each surface step (every --surface-batch steps): the priors' gradient
//      (--surface-smoothness, --level-prior) added, dL/dheight -> dL/d(height parameters)
//      once over the batch's points, Adam on the MLP (device Adam, engine/optim/adam.h) or the one
//      height of --flat-water, the surface lifted again
//   -> Adam on the Gaussian table's six groups (engine/optim/table_adam.h).
// The camera rays, the Gaussians, the loss and the backward share one submission with the
// surface trace's last (profile: `refrax train --profile`, engine/vk/vk_profile.h).
#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "engine/optim/adam.h"
#include "engine/height/analytic_height.h"
#include "engine/camera/camera_rays.h"
#include "engine/dataset/dataset.h"
#include "engine/gaussian/densify.h"
#include "engine/gaussian/densify_device.h"
#include "engine/gaussian/mcmc.h"
#include "engine/gaussian/gaussian_trace.h"
#include "engine/height/height_field.h"
#include "engine/loss/image_loss.h"
#include "engine/gaussian/gaussian_adam.h"
#include "engine/gaussian/gaussian_device_step.h"
#include "engine/train/plane_sweep.h"
#include "engine/run/train_config.h"
#include "engine/vk/vk_commands.h"
#include "engine/vk/vk_profile.h"
#include "engine/surface/surface_watch.h"
#include "engine/surface/water_surface.h"
#include "engine/model/model.h"

namespace refrax {

struct Context;

struct StepResult {
  double loss = 0;        // image loss + density regulariser
  double imageLoss = 0;
  double psnr = 0;        // of the rendered batch against its target, at the progress line's steps (NaN at the others)
  uint32_t gaussians = 0;
  uint32_t missed = 0;    // rays that missed the surface domain
  bool restarted = false; // the Gaussians were drawn afresh after this step (--restart-gaussians)
  bool refitStarted = false;  // ... or before it, as the refit began (--refit)
  // Submitted and not waited for (TrainSession::deferSteps): the losses above are NaN until
  // readStepLosses reads them once the step has run.
  bool pending = false;
};

// The optimisers' state and the batch order: with the model's parameters, what a checkpoint
// saves and restores (checkpointContents, engine/train/checkpoint.h), so that a resumed run
// continues exactly. The water's optimiser is in WaterLearning (its moments live on the device).
struct TrainingState {
  TableAdam gaussianAdam;            // the Gaussians' optimiser (host table)
  std::vector<float> densifyStats;   // per Gaussian since the last clone/split: the gradient statistic, the rays (engine/gaussian/densify.h)
  std::mt19937 rng;
  std::vector<uint32_t> viewOrder;   // a shuffled pass over the training views
  uint32_t viewCursor = 0;
};

// The water's learning: its optimiser (the MLP's device Adam, or the plane's height as a table
// of one row and one column), the gradient summed since the last surface step, and the priors'
// cache. Part of the gradient sits in the surface until pushWaterGradient takes it into
// heightGrad or planeGrad; the surface refuses to be lifted or re-created while it does.
struct WaterLearning {
  AdamPipelines adamPipelines;
  AdamGroup heightAdam;   // checkpointed
  Buffer heightGrad;      // checkpointed: dL/d(MLP parameters) summed since the last surface step
  TableAdam planeAdam;    // checkpointed
  double planeGrad = 0;   // checkpointed: dL/d(plane height) summed since the last plane step (--surface-batch)
  // The priors (--surface-smoothness, --level-prior) of the current heights: dE/dheight at the
  // coarse grid's vertices (surface_prior.h) and E; fresh until the surface is lifted again.
  std::vector<float> priorGrad;
  double priorEnergy = 0;
  uint64_t priorHeightsVersion = 0;  // the surface's heightsVersion they were computed at
  // --anchor-mean-height, --level-prior and the divergence check: each coarse grid slot's
  // weight (viewWeights over the training views, computed on first use per surface grid).
  std::vector<double> viewWeights;
  // The coarse grid's heights as the surface step's own submissions lift them, copied in those
  // submissions to where the host reads them after its wait: the anchor, the priors and the
  // divergence check read them there, with no download of their own (issue 48).
  Buffer liftedHeights;                // MemoryUse::Readback, the surface's gridPointCount floats
  uint64_t liftedHeightsVersion = 0;   // the surface's heightsVersion they hold (0: none)
  // --sweep-loss: the last plane sweep's depths, with the colours the views agreed on at the
  // last application (engine/train/sweep_loss.h), and the applications so far in this process.
  DepthMap sweepMap;
  int sweepApplications = 0;
  // The sweep views at the loss's resolution (downscaledCamera, boxDownscaled): made once.
  std::vector<Camera> sweepLossCameras;
  std::vector<Image> sweepLossImages;
  // --sweep-watch: the flat water's plane sweep (made at the first check, on its own grid, the
  // grid later sweeps share: watchGrid), and the learned water the views agreed on best at a
  // check (its cost over the flat water's, weights and initial height; no weights: the flat
  // start, at 1). Not checkpointed: a resumed run's watch starts again from its next check.
  DepthMap watchFlat;
  PlaneSweepConfig watchGrid;
  double watchBest = 1.0;
  std::vector<float> watchBestWeights;
  float watchBestInitialHeight = 0;
};

// The step's device buffers for up to `capacity` rays (the model's own ray buffers:
// Model::capacity) and the pipelines that only training uses.
struct StepBuffers {
  uint32_t capacity = 0;
  LossPipelines lossPipelines;
  ComputePipeline copyPipeline;  // layouts handed between stages (engine/vk/strided_copy.h)
  ImageLossScratch lossScratch;
  Buffer pixels, rendered, target, lossGrad, lossResult, dLoss, grads, stats, rayGrads;
  Buffer pixelWeights;    // the batch's mask (1: the pixel counts), for masked views
  RecordedUploads uploads;  // the batch's target, mask and pixel list, copied in its first submission
  Buffer densityPartials, densityResult;  // the density regulariser's partial sums and value (engine/loss/image_loss.h)
  // The step's scalars where the host reads them after its wait with no submission of their
  // own (a discrete GPU's download is one): [0] the image loss, [1] the density regulariser.
  Buffer stepScalars;
  HitRecords hitRecords;  // the forward's blended hits, read by the backward (config.hitRecordsPerRay)
  // The Gaussians' optimiser on the device (engine/gaussian/gaussian_device_step.h), when the
  // run steps them there (gaussianStepsOnDevice); its moments and statistic sums are the device's
  // copies of TrainingState's.
  std::optional<GaussianDeviceOptimiser> gaussianOptimiser;
  // Densification on the device (engine/gaussian/densify_device.h), where the run orders its
  // proxies there too (a GPU: GaussianTracer::orderOnDevice) and steps the Gaussians there.
  std::optional<DeviceDensifyPipelines> densifyPipelines;
  // Which copy of the Gaussians (model.gaussians, model.device) and of their optimiser's state
  // is current: the device steps them, the host changes them (densification, a restart, a
  // loaded checkpoint); pullGaussians and pushGaussians make the other copy the same.
  enum class Copies { Same, DeviceNewer, HostNewer } gaussianCopies = Copies::HostNewer;
  // Steps not waited for (TrainSession::deferSteps): two slots, each with its own command
  // buffer, fence, uploads' area and profiling timer, so that one step is recorded while the
  // last runs; every step's image and density losses copied to lossLog's row step % rows.
  struct StepSlot {
    SubmitSlot submit;
    RecordedUploads uploads;
    GpuTimer timer;
    Buffer liftedHeights;         // a water step's lifted coarse heights, read once it has run
    std::function<void()> finish;  // the host's part of the step, once it has run (a water step's checks)
  };
  std::array<StepSlot, 2> slots;
  Buffer lossLog;
};
constexpr uint32_t kLossLogRows = 256;

// --water-sign-check at a restart of this process: the step, the mirror's agreement against
// the learned water's, and whether the mirror was kept.
struct WaterSignCheck {
  int step = 0;
  SweepAgreement agreement;  // the mirror image (cost) against the learned water (reference)
  SweepAgreement flat;       // the learned water (cost) against flat water (reference), before any mirroring
  bool mirrored = false;
};

// --water-scale-search at a restart of this process: the plane-sweep cost through the learned
// relief scaled by each of kWaterScales, over the cost at scale 1, and the scale kept.
struct WaterScaleSearch {
  int step = 0;
  std::vector<double> ratios;  // per kWaterScales, cost / the learned water's cost (1 at scale 1)
  size_t cells = 0;            // the fewest cells a comparison had
  double chosen = 1;
};

// --surface-gate at a restart of this process: the learned water's plane-sweep agreement
// against flat water's, and whether the water started again from flat.
struct SurfaceGateCheck {
  int step = 0;
  SweepAgreement agreement;  // the learned water (cost) against flat water (reference)
  bool reset = false;
};

// --restart-gate at a restart step: the learned water's plane-sweep agreement against flat
// water's, and whether the Gaussians were drawn afresh.
struct RestartGateCheck {
  int step = 0;
  SweepAgreement agreement;  // the learned water (cost) against flat water (reference)
  bool restarted = false;
};
// Whether --restart-gate X draws the Gaussians afresh for this agreement: the learned water's
// sweep cost below X times flat water's (a comparison with no cells restarts, as without it).
bool restartGatePasses(const SweepAgreement& a, double gate);

// --sweep-watch at a check: the learned water's plane-sweep agreement against flat water's,
// whether the water went back to the best state so far, and the water's learning rate after.
struct SweepWatchCheck {
  int step = 0;
  SweepAgreement agreement;  // the learned water (cost) against flat water (reference)
  bool best = false;         // the best agreement so far: the state a later rollback returns to
  bool rolledBack = false;
  double learningRateScale = 1;  // the water's learning rate over the configured one, after the check
};

// What --sweep-watch does with a check's ratio (the learned water's sweep cost over flat
// water's) given the best ratio so far (1 before any: flat water): keep it as the new best,
// keep the water as it is (within the tolerance over flat water), or roll it back.
enum class SweepWatchVerdict { Best, Keep, RollBack };
SweepWatchVerdict sweepWatchVerdict(double ratio, double best);

// What the run reports of this process (refrax report, the end-of-run checks, --profile);
// nothing here steers training.
struct RunLog {
  int deferredSteps = 0;  // steps trainToEnd did not wait for (TrainSession::deferSteps)
  DensifyStats lastDensify;
  McmcStats lastMcmc;
  std::vector<WaterSignCheck> signChecks;
  std::vector<WaterScaleSearch> scaleSearches;
  // --sweep-loss: at each application, the step, the loss per ray that landed, and those rays.
  struct SweepLossPoint {
    int step = 0;
    double perRay = 0;
    size_t rays = 0;
  };
  std::vector<SweepLossPoint> sweepLosses;
  std::vector<SurfaceGateCheck> gateChecks;
  std::vector<SweepWatchCheck> watchChecks;
  std::vector<RestartGateCheck> restartGateChecks;
  size_t gaussiansAtPoints = 0;  // --init-points: how many of the last drawn Gaussians sit at sparse points
  double sweptCellFraction = 0;  // --init-depth sweep: the last sweep's cells with a depth
  // The learned water's shape over the seen water as of its last surface step (measured by the
  // divergence check, which reads the heights anyway), and the run's series of it with the
  // mean training loss (engine/surface/surface_watch.h; trainToEnd samples it).
  SurfaceShape surfaceShape;
  bool surfaceShapeMeasured = false;
  std::vector<SurfaceWatchSample> surfaceWatch;
  GpuProfiler profiler;  // the steps of this process, stage by stage (engine/vk/vk_profile.h)
};

// A model in training: the model (engine/model/model.h: Gaussians, water, ray buffers; what a
// run's reader loads) and, by lifetime, the dataset, the checkpointed training state, the
// water's learning, the step's buffers, the densification rules derived from the config, and
// the run's log. Not movable (the model is not): it lives in a unique_ptr.
struct TrainSession {
  Model model;
  Dataset dataset;
  TrainingState state;
  WaterLearning water;
  StepBuffers buffers;
  // Densification (engine/gaussian/densify.h: 3DGS's clone/split/prune, or mcmc.h), derived
  // from config.schedule at creation.
  DensifyConfig densifyConfig;
  McmcConfig mcmcConfig;
  RunLog log;
  // The water's surface step recorded into its batch's submission where it can be (trainStep):
  // one submission a step. False: a submission of its own after the batch's, as before (tests
  // compare the two).
  bool surfaceStepInBatch = true;
  // Steps submitted without waiting where nothing the host does next needs their results
  // (deferredStepAt): the host records step t + 1 while the device runs step t, and waits for
  // step t only once step t + 1 is queued (issue 48). Their losses are read later
  // (readStepLosses). Every step at a multiple of syncEvery is waited for. trainToEnd sets it
  // (REFRAX_STEP_SYNC=1: off); off, every step waits for itself.
  bool deferSteps = false;
  int syncEvery = 100;
  int deferredSlot = -1;                      // the slot of the step being recorded, when deferred
  uint32_t lastBatchWidth = 0, lastBatchHeight = 0;  // of the last step: a new size reallocates its buffers

  TrainSession() = default;
  TrainSession(const TrainSession&) = delete;
  TrainSession& operator=(const TrainSession&) = delete;
  ~TrainSession();  // waits for the steps in flight before their buffers go
};

// The image and density losses of a step that ran (its row of StepBuffers::lossLog; waits for
// the steps in flight first). Good for the kLossLogRows steps before the latest.
struct StepLosses {
  double image = 0, density = 0;
};
StepLosses readStepLosses(TrainSession& session, int step);

// Loads nothing: `dataset` and `config` (resolved) are given. Initialises the Gaussians,
// the height field and the surface from config.seed.
std::unique_ptr<TrainSession> createTrainSession(Context& ctx, const TrainConfig& config, Dataset dataset);

// Steps per surface Adam step: config.surfaceBatch, or with 0 (--surface-batch views) the
// training view count.
int surfaceBatchSteps(const TrainSession& session);

// One optimisation step (advances session.step).
StepResult trainStep(TrainSession& session);

// The water's gradient summed since the last surface step sits partly in the surface, as
// dL/dheight at its lattice points (engine/surface/water_surface.h): this takes it into the
// parameters' gradient (water.heightGrad for the MLP, or water.planeGrad). Needed before anything that
// lifts the surface again, re-creates it or saves the session; a no-op when nothing is pending.
// A missed push is an error, not a lost gradient: the surface refuses to be lifted or
// re-created, and its point cache to overflow, while a gradient is pending (water_surface.h).
// `then` (the water's Adam step) is recorded after the push, in its last submission (alone where
// nothing is pending).
void pushWaterGradient(TrainSession& session, const std::function<void(VkCommandBuffer)>& then = {});

// The parts of a step, for trainStep and for checks that differentiate a fixed batch
// (engine/train/gradient_check.h).
// One step's batch: a training view and the rectangle of its pixels traced (the whole image,
// or with config.patch a random patch of it).
struct StepBatch {
  uint32_t view = 0;  // index into the train split
  uint32_t x0 = 0, y0 = 0, width = 0, height = 0;
  bool patch = false;
  uint32_t rays() const { return width * height; }
};
// The next view of the shuffled pass and, with config.patch, its patch (advances the rng).
StepBatch nextStepBatch(TrainSession& session);
// The trace options of step t (background, SH degree, hit records) for this batch; also sets
// the surface's face-normal switch for step t.
TraceOptions stepTraceOptions(TrainSession& session, const StepBatch& batch, int t);
// What a batch's forward hands its backward (as tiny-cuda-nn's forward returns the context its
// backward takes): the batch, its trace options, and the device buffers the forward wrote,
// named, so no stage reads "the last forward" from hidden state. The buffers are the
// session's; a context is good until the session's next forward.
struct BatchContext {
  StepBatch batch;
  TraceOptions options;
  const Buffer* cameraRays = nullptr;      // the camera rays (into the water, or straight on)
  const Buffer* tracedRays = nullptr;      // the rays the Gaussians saw: refracted, or the camera rays
  const Buffer* results = nullptr;         // the Gaussian forward's per-ray results
  const Buffer* dLoss = nullptr;           // dL/d(rgb, opacity) per ray
  const Buffer* surfaceRecords = nullptr;  // the surface trace's per-ray records; null without water
  uint32_t rays() const { return batch.rays(); }
};
struct BatchForward {
  double imageLoss = 0;  // 0.8 L1 + 0.2 (1 - SSIM) of the batch
  std::vector<float> rendered, target;  // rgb per ray (times the mask for a masked view); rendered only when asked
  std::vector<float> weight;            // per ray: the view's mask (1: counts); empty: every ray counts
  BatchContext context;                 // what cmdBackwardBatch takes
};
// Camera rays -> water (unless --no-refraction) -> Gaussians -> image loss, at the session's
// current parameters. `then` records more work (the backward, given the batch's context) into
// the same submission, after the loss. readRendered: the rendered batch read back (a ray's rgb,
// 12 bytes a ray: 5.5 MB for a whole 392 px image) for the progress line's PSNR.
BatchForward forwardBatch(TrainSession& session, const StepBatch& batch, const TraceOptions& options,
                          const std::function<void(VkCommandBuffer, const BatchContext&)>& then = {}, bool readRendered = false);
// Records the backward of the forward that returned `context`: per-Gaussian gradients into
// session.buffers.grads (and statistics), per-ray dL/d(ray) and, when the surface learns, dL/d(height)
// at the surface's lattice points (pushed into the parameters by pushWaterGradient).
// session.buffers.grads and .stats must have been cleared.
void cmdBackwardBatch(VkCommandBuffer cb, TrainSession& session, const BatchContext& context, bool surfaceLearns);

// After the host table changed (Adam, decay, reset, densification): upload it and refresh
// the proxies (same count: rebuild in place; new count: new proxies); after a device step,
// refresh the proxies only.
void syncGaussians(TrainSession& session, bool countChanged);

// Whether the run steps its Gaussians on the device (Adam, the density schedule and the
// statistic's sums in the step's command buffer): every run but --gaussians-fixed and MCMC
// (whose position noise draws from the host's generator every step).
bool gaussianStepsOnDevice(const TrainConfig& config);
// The host's copies of the Gaussians (model.gaussians), their Adam moments and statistic sums
// (state) made current after device steps, and checked; a no-op when they are. What reads
// them between steps calls it first: densification, a checkpoint, the run's files, a test.
void pullGaussians(TrainSession& session);
// The device's copies made current after the host changed them.
void pushGaussians(TrainSession& session);

// Gradient and statistics buffers for the current Gaussian count.
void allocateGaussianBuffers(TrainSession& session);

// Makes room for `rays` rays per pass, in the model's and the batch's buffers (a whole image
// for the plane sweep); the surface's pending gradient is pushed first.
void ensureRayCapacity(TrainSession& session, uint32_t rays);

// How well the training views agree through the learned water against the flat water at the
// water height (plane sweeps over the Gaussians' box, engine/train/plane_sweep.h): a
// ground-truth-free check that the surface explains the views better than its flat start.
// The surface is lifted back from the session's height source.
SweepAgreement agreementWithFlatWater(TrainSession& session);

// The learned water (a height field) against its mirror image about the water height
// (mirrorHeightField), by the same plane-sweep agreement: `cost` the mirror's, `reference` the
// learned water's. The height field and the surface are left as they were.
SweepAgreement agreementOfMirror(TrainSession& session);
// A mirror whose cost is under this fraction of the learned water's is the better water: a
// nearly flat water reads within about 1% of its mirror, and the full-size waves learned
// upside down 0.32-0.34x (their mirrors, right way up, 2.9-3.1x the other way).
constexpr double kMirrorBetter = 0.95;
// --water-scale-search's candidates, and how much better than the learned water's a scale's
// sweep cost must be to be kept (as a mirror must be, kMirrorBetter).
constexpr double kWaterScales[] = {0.0, 0.5, 1.0, 1.5, 2.0};
constexpr double kWaterScaleBetter = kMirrorBetter;

// anchorMeanHeight (engine/model/model.h) over the training views.
void anchorMeanHeight(TrainSession& session);

}  // namespace refrax
