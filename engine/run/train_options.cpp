#include "engine/run/train_options.h"

#include <algorithm>
#include <filesystem>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <utility>

#include "engine/base/error.h"
#include "engine/gaussian/gaussian_trace.h"
#include "engine/surface/surface_prior.h"

namespace refrax {
namespace {

using json = nlohmann::json;
template <class T>
using Ref = std::function<T&(TrainConfig&)>;

template <class T>
Ref<T> field(T TrainConfig::*m) {
  return [m](TrainConfig& c) -> T& { return c.*m; };
}
Ref<int> scheduleField(int ScheduleSteps::*m) {
  return [m](TrainConfig& c) -> int& { return c.schedule.*m; };
}

std::string number(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

// ---- the command line's text as JSON

json parseInteger(const std::string& text, const std::string& name) {
  char* end = nullptr;
  errno = 0;
  long long v = std::strtoll(text.c_str(), &end, 10);
  if (end == text.c_str() || *end) fail(name + " expects an integer, got '" + text + "'");
  if (errno == ERANGE) fail(name + " is out of range: '" + text + "'");
  return json(v);
}

json parseReal(const std::string& text, const std::string& name) {
  char* end = nullptr;
  double v = std::strtod(text.c_str(), &end);
  if (end == text.c_str() || *end) fail(name + " expects a number, got '" + text + "'");
  return json(v);
}

json parseText(const std::string& text, const std::string&) { return json(text); }

// ---- JSON values, checked

long long integerOf(const json& v, const std::string& name) {
  if (!v.is_number_integer()) fail(name + " must be an integer, got " + v.dump());
  if (v.is_number_unsigned()) return (long long)std::min<uint64_t>(v.get<uint64_t>(), uint64_t(LLONG_MAX));
  return v.get<long long>();
}

double realOf(const json& v, const std::string& name) {
  if (!v.is_number()) fail(name + " must be a number, got " + v.dump());
  return v.get<double>();
}

// ---- rows

TrainOption row(const std::string& flag, const std::string& key, const std::string& metavar, const std::string& help) {
  TrainOption o;
  o.flag = flag;
  o.key = key;
  o.metavar = metavar;
  o.help = help;
  return o;
}

template <class T>
TrainOption integer(const std::string& flag, const std::string& key, const std::string& metavar, const std::string& help, Ref<T> ref,
                    long long lo, long long hi) {
  TrainOption o = row(flag, key, metavar, help);
  o.get = [ref](const TrainConfig& c) { return json(ref(const_cast<TrainConfig&>(c))); };
  o.set = [ref, lo, hi](TrainConfig& c, const json& v, const std::string& name) {
    long long x = integerOf(v, name);
    if (x < lo || x > hi) fail(name + " must be between " + std::to_string(lo) + " and " + std::to_string(hi) + ", got " + std::to_string(x));
    ref(c) = T(x);
  };
  o.parse = parseInteger;
  return o;
}

// A real in the interval lo..hi, each end open or closed; hi = INFINITY: any finite value above lo.
TrainOption real(const std::string& flag, const std::string& key, const std::string& metavar, const std::string& help, Ref<double> ref,
                 double lo, bool loOpen, double hi, bool hiOpen) {
  std::string range = std::isinf(hi) ? std::string(loOpen ? "finite and > " : "finite and >= ") + number(lo)
                                     : std::string(loOpen ? "(" : "[") + number(lo) + ", " + number(hi) + (hiOpen ? ")" : "]");
  if (!std::isinf(hi)) range = "in " + range;
  TrainOption o = row(flag, key, metavar, help);
  o.get = [ref](const TrainConfig& c) { return json(ref(const_cast<TrainConfig&>(c))); };
  o.set = [ref, lo, loOpen, hi, hiOpen, range](TrainConfig& c, const json& v, const std::string& name) {
    double x = realOf(v, name);
    bool ok = std::isfinite(x) && (loOpen ? x > lo : x >= lo) && (hiOpen ? x < hi : x <= hi);
    if (!ok) fail(name + " must be " + range + ", got " + number(x));
    ref(c) = x;
  };
  o.parse = parseReal;
  return o;
}

// A switch: given on the command line, the field takes `whenGiven`.
TrainOption switchOption(const std::string& flag, const std::string& key, const std::string& help, Ref<bool> ref, bool whenGiven) {
  TrainOption o = row(flag, key, "", help);
  o.get = [ref](const TrainConfig& c) { return json(ref(const_cast<TrainConfig&>(c))); };
  o.set = [ref](TrainConfig& c, const json& v, const std::string& name) {
    if (!v.is_boolean()) fail(name + " must be true or false, got " + v.dump());
    ref(c) = v.get<bool>();
  };
  o.parse = [whenGiven](const std::string&, const std::string&) { return json(whenGiven); };
  return o;
}

// A file, stored as an absolute path (config.json then names it wherever the run is opened).
TrainOption filePath(const std::string& flag, const std::string& key, const std::string& metavar, const std::string& help,
                     Ref<std::string> ref) {
  TrainOption o = row(flag, key, metavar, help);
  o.get = [ref](const TrainConfig& c) { return json(ref(const_cast<TrainConfig&>(c))); };
  o.set = [ref](TrainConfig& c, const json& v, const std::string& name) {
    if (!v.is_string()) fail(name + " must be a file's path, got " + v.dump());
    ref(c) = v.get<std::string>();
  };
  o.parse = [](const std::string& text, const std::string& name) {
    if (text.empty()) fail(name + " needs a file");
    return json(std::filesystem::absolute(text).lexically_normal().string());
  };
  return o;
}

// One of named values; the field holds the name's enum. A value with no name (set in code)
// reads as its number, which set() then refuses naming the flag.
template <class E>
TrainOption choice(const std::string& flag, const std::string& key, const std::string& metavar, const std::string& help, Ref<E> ref,
                   std::vector<std::pair<std::string, E>> names) {
  TrainOption o = row(flag, key, metavar, help);
  o.get = [ref, names](const TrainConfig& c) {
    E e = ref(const_cast<TrainConfig&>(c));
    for (const auto& [name, value] : names)
      if (value == e) return json(name);
    return json(static_cast<long long>(e));
  };
  o.set = [ref, names](TrainConfig& c, const json& v, const std::string& name) {
    std::string list;  // "a, b or c"
    for (size_t i = 0; i < names.size(); i++) list += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + names[i].first;
    if (!v.is_string()) fail(name + " must be " + list + ", got " + v.dump());
    for (const auto& [text, value] : names)
      if (text == v.get<std::string>()) return void(ref(c) = value);
    fail(name + " must be " + list + ", got " + v.get<std::string>());
  };
  o.parse = parseText;
  return o;
}

// One of named strings, kept as text (the proxy, which proxyKindFor resolves against the device).
TrainOption textChoice(const std::string& flag, const std::string& key, const std::string& metavar, const std::string& help,
                       Ref<std::string> ref, std::vector<std::string> choices) {
  TrainOption o = row(flag, key, metavar, help);
  o.get = [ref](const TrainConfig& c) { return json(ref(const_cast<TrainConfig&>(c))); };
  o.set = [ref, choices](TrainConfig& c, const json& v, const std::string& name) {
    std::string list;  // "a, b or c"
    for (size_t i = 0; i < choices.size(); i++) list += (i == 0 ? "" : i + 1 == choices.size() ? " or " : ", ") + choices[i];
    if (!v.is_string()) fail(name + " must be " + list + ", got " + v.dump());
    std::string s = v.get<std::string>();
    if (std::find(choices.begin(), choices.end(), s) == choices.end()) fail(name + " must be " + list + ", got " + s);
    ref(c) = s;
  };
  o.parse = parseText;
  return o;
}

// A step of the schedule: -1 (unset: scaled from the reference by resolveSchedule) or a step.
TrainOption step(const std::string& flag, const std::string& name, const std::string& help, int ScheduleSteps::*m,
                 const std::string& shown) {
  TrainOption o = integer<int>(flag, "schedule/" + name, "N", help, scheduleField(m), -1, kMaxScheduleStep);
  o.required = true;
  o.shownDefault = shown;
  o.parse = [](const std::string& text, const std::string& n) {
    json v = parseInteger(text, n);
    if (v.get<long long>() < 0 || v.get<long long>() > kMaxScheduleStep) fail(n + " must be a step count >= 0");
    return v;
  };
  return o;
}

TrainOption required(TrainOption o) {
  o.required = true;
  return o;
}
TrainOption resumable(TrainOption o) {
  o.resumable = true;
  return o;
}
TrainOption shown(TrainOption o, const std::string& text) {
  o.shownDefault = text;
  return o;
}

TrainOption modelSwitch(const std::string& flag, const std::string& help, WaterModel model) {
  TrainOption o = row(flag, "", "", help);
  o.group = "model";
  o.get = [model](const TrainConfig& c) { return json(c.model == model); };
  o.set = [model](TrainConfig& c, const json& v, const std::string&) {
    if (v.is_boolean() && v.get<bool>()) c.model = model;
  };
  o.parse = [](const std::string&, const std::string&) { return json(true); };
  return o;
}

// Every refrax train flag, one row each (a declarative table: long by design, one row per option).
std::vector<TrainOption> makeTable() {
  const double inf = INFINITY;
  std::vector<TrainOption> t;
  t.push_back(modelSwitch("no-refraction", "comparison: plain 3DGRT, straight rays, no water surface", WaterModel::NoRefraction));
  t.push_back(modelSwitch("flat-water", "comparison: a flat water plane whose only parameter, its height, is learned (at the GPU's water settings on every device)", WaterModel::FlatWater));
  t.push_back(modelSwitch("known-water", "oracle: the dataset's ground-truth surface (water.json), fixed; only the Gaussians learn",
                          WaterModel::KnownWater));
  t.push_back(real("known-water-scale", "known_water_scale", "S",
                   "study: with --known-water, the true water's relief scaled about its level by S (0: flat at the true level); how "
                   "flat the valley between the flat start and the truth is (docs/experiments/2026-12-05-water-valley.md)",
                   field(&TrainConfig::knownWaterScale), 0, false, inf, false));
  {
    TrainOption m = row("", "model", "", "the water model (the switches above)");
    m.required = true;
    m.get = [](const TrainConfig& c) { return json(waterModelName(c.model)); };
    m.set = [](TrainConfig& c, const json& v, const std::string& name) {
      if (!v.is_string()) fail(name + " must be a water model's name, got " + v.dump());
      c.model = parseWaterModel(v.get<std::string>());
    };
    t.push_back(m);
  }
  {
    // Absent from runs written before recipes: the reference, which they trained with.
    TrainOption r = choice("recipe", "recipe", "NAME",
                           "what fills the settings not given: method (the defaults: sized from the data and the device, whole images on "
                           "a GPU, patches on a CPU; docs/training.md) or reference (the paper's schedule, for studies)",
                           field(&TrainConfig::recipe), {{"method", Recipe::Method}, {"reference", Recipe::Reference}});
    r.shownDefault = "method";
    t.push_back(r);
  }
  t.push_back(shown(required(resumable(integer<int>("steps", "steps", "N", "training steps (one training image or patch each)",
                                                      field(&TrainConfig::steps), 1, 10000000))),
                    "15000 on a GPU, 4000 on a CPU; with --time-limit, what fits it; reference 15000"));
  t.push_back(required(integer<uint64_t>("seed", "seed", "S", "random seed (initial Gaussians, height field, view order, patches)",
                                         field(&TrainConfig::seed), 0, LLONG_MAX)));
  t.push_back(shown(required(integer<uint32_t>("gaussians", "initial_gaussians", "N", "initial Gaussians, uniform in the box derived under the water",
                                               field(&TrainConfig::initialGaussians), 1, 50000000)),
                    "from the data: one per 8 pixels of a training image"));
  t.push_back(choice("init-depth", "init_depth", "KIND",
                     "the initial (and restarted) Gaussians' depth: box (uniform in the box, the reference) or sweep (a plane sweep of the "
                     "training views through the current water; docs/training.md)",
                     field(&TrainConfig::initDepth), {{"box", InitDepth::Box}, {"sweep", InitDepth::Sweep}}));
  t.back().shownDefault = "sweep; reference box";
  t.push_back(switchOption("init-points", "init_points",
                           "the initial (and restarted) Gaussians at the dataset's sparse points under the water (COLMAP's points3D, moved "
                           "down to their true depth through the flat water; points above it dropped), at most --gaussians of them; the "
                           "rest as --init-depth says",
                           field(&TrainConfig::initPoints), true));
  t.push_back(filePath("gaussians-from", "gaussians_from", "PLY",
                       "study: the initial (and restarted) Gaussians read from a 3DGS PLY (e.g. a --known-water run's point_cloud.ply) "
                       "instead of drawn; their count replaces --gaussians",
                       field(&TrainConfig::gaussiansFrom)));
  t.push_back(switchOption("gaussians-fixed", "gaussians_fixed",
                           "study: with --gaussians-from, the Gaussians stay as read (no Adam, no density schedule, no densification, "
                           "every SH degree from step 1): only the water learns (docs/training.md)",
                           field(&TrainConfig::gaussiansFixed), true));
  t.push_back(shown(required(integer<uint32_t>("max-gaussians", "max_gaussians", "N", "cap on the Gaussian count (enforced by densification)",
                                               field(&TrainConfig::maxGaussians), 1, 100000000)),
                    "from the data: the initial count (at least --gaussians)"));
  t.push_back(required(real("initial-density", "initial_density", "X", "initial Gaussian density", field(&TrainConfig::initialDensity), 0,
                            true, 1, true)));
  t.push_back(shown(required(integer<uint32_t>("sh-degree", "max_sh_degree", "D", "highest SH degree (reached one degree per --sh-interval steps)",
                                               field(&TrainConfig::maxShDegree), 0, 3)),
                    "0; reference 3"));
  t.push_back(required(integer<uint32_t>("k-buffer", "k_buffer", "K", "tracer k-buffer size", field(&TrainConfig::kBuffer), 1, 64)));
  t.push_back(integer<uint32_t>("hit-records", "hit_records", "N",
                                "hits per ray the forward records so the backward need not re-trace (8 bytes each; 0: re-trace)",
                                field(&TrainConfig::hitRecordsPerRay), 0, 1024));
  t.push_back(required(textChoice("proxy", "proxy", "KIND", "Gaussian proxies: aabb, instanced or auto", field(&TrainConfig::proxy),
                              {"aabb", "instanced", "auto"})));
  t.push_back(required(integer<uint32_t>("mlp-width", "mlp_width", "W", "height-field MLP width", field(&TrainConfig::mlpWidth), 1, 256)));
  t.push_back(required(integer<uint32_t>("mlp-layers", "mlp_hidden_layers", "L", "height-field MLP hidden layers",
                                         field(&TrainConfig::mlpHiddenLayers), 1, 8)));
  t.push_back(shown(required(integer<uint32_t>("mlp-octaves", "mlp_octaves", "O", "height-field frequency-encoding octaves",
                                         field(&TrainConfig::mlpOctaves), 0, 16)), "from the data: the finest period about 22 pixels on the water"));
  t.push_back(shown(integer<uint32_t>("mlp-coarse-octaves", "mlp_coarse_octaves", "C",
                                      "coarse-to-fine: octaves open while the surface is frozen, the rest open gradually until "
                                      "--octaves-open-until (>= O: all from the start)",
                                      field(&TrainConfig::mlpCoarseOctaves), 0, 16),
                    "3; reference O"));
  t.push_back(required(real("mlp-init-range", "mlp_init_range", "X", "height-field last layer initialised in +-X (reference 0.1)",
                            field(&TrainConfig::mlpInitRange), 0, false, inf, false)));
  t.push_back(shown(real("surface-lr", "surface_lr", "X",
                         "surface learning rate at step 0 (MLP weights, or the flat height), decaying to X/100 (reference 5e-4)",
                         field(&TrainConfig::surfaceLearningRate), 0, true, 1, true),
                    "1e-3 on a GPU, 3e-3 on a CPU; reference 5e-4"));
  t.push_back(shown(required(integer<uint32_t>("grid-cells", "grid_cells", "N", "water-surface proxy mesh cells per side",
                                         field(&TrainConfig::gridCells), 1, 4096)), "from the data: 2^octaves"));
  t.push_back(shown(required(integer<uint32_t>("subdivision", "subdivision_levels", "K", "recursive subdivision levels of the surface trace",
                                         field(&TrainConfig::subdivisionLevels), 0, 6)), "from the data: finest triangles about 2 pixels on the water"));
  {
    TrainOption v = integer<uint32_t>("train-views", "train_views", "N",
                                      "train on N of the training views, spread evenly in file order (first and last included); the test "
                                      "views are unchanged",
                                      field(&TrainConfig::trainViews), 0, 1000000000);
    v.shownDefault = "all";
    v.parse = [](const std::string& text, const std::string& name) {
      json n = parseInteger(text, name);
      if (n.get<long long>() < 1) fail(name + " must be at least 1, got " + text);
      return json(std::min<long long>(n.get<long long>(), 1000000000));
    };
    t.push_back(v);
  }
  t.push_back(shown(required(integer<uint32_t>("patch", "patch", "P",
                                               "train on one random P x P patch per step (0: whole images); ~P^2/(w h) of the time per step",
                                               field(&TrainConfig::patch), 0, 16384)),
                    "0 on a GPU, 64 on a CPU (images over 64 px); reference 0"));
  t.push_back(required(real("density-decay", "density_decay", "X", "density multiplier every --density-decay-every steps",
                            field(&TrainConfig::densityDecay), 0, true, 1, false)));
  t.push_back(real("density-loss", "density_loss", "X",
                   "weight of the density loss X mean(density^2) over all Gaussians (0: off, the paper's ablation)",
                   field(&TrainConfig::densityLossWeight), 0, false, 1000, false));
  {
    TrainOption b = integer<int>("surface-batch", "surface_batch", "N|views",
                                 "one surface Adam step every N steps, on the gradient summed over their N views (1: every step, the "
                                 "reference; views: the training view count, one step per pass over the views, which the shuffled order "
                                 "visits once each when the surface starts learning at a pass's start)",
                                 field(&TrainConfig::surfaceBatch), 1, 100000);
    auto setCount = b.set;
    // "views" is 0 in TrainConfig (resolved to the training view count by the session)
    b.get = [](const TrainConfig& c) { return c.surfaceBatch == 0 ? json("views") : json(c.surfaceBatch); };
    b.set = [setCount](TrainConfig& c, const json& v, const std::string& name) {
      if (v == "views") c.surfaceBatch = 0;
      else if (v.is_string()) fail(name + " must be views or a step count, got " + v.get<std::string>());
      else setCount(c, v, name);
    };
    b.parse = [](const std::string& text, const std::string& name) { return text == "views" ? json("views") : parseInteger(text, name); };
    b.shownDefault = "views on a GPU, 1 on a CPU; reference 1";
    t.push_back(b);
  }
  t.push_back(step("surface-freeze", "surface_freeze", "surface frozen for the first N steps", &ScheduleSteps::surfaceFreeze,
                   "2 x steps/15 on a GPU, steps/10 on a CPU; reference 1000 x steps/15000"));
  {
    // Not scaled with --steps, and absent from runs written before it: 0, the reference.
    TrainOption o = step("surface-until", "surface_until",
                         "surface (and flat height) frozen again after its last step at or before step N; the Gaussians train "
                         "on through it (0: learns to the end; docs/training.md)",
                         &ScheduleSteps::surfaceUntil, "0");
    o.required = false;
    t.push_back(o);
  }
  {
    // Not scaled with --steps, and absent from runs written before it: 0, none.
    TrainOption o = step("refit", "refit_steps",
                         "after --steps, N more steps of Gaussians drawn afresh under the water as learned (then held fixed), their "
                         "densification, density and SH schedule counted again from the refit's start: Gaussians fitted while the water "
                         "moved keep its history in their colours (docs/training.md) (0: none)",
                         &ScheduleSteps::refitSteps, "0");
    o.required = false;
    t.push_back(o);
  }
  t.push_back(step("face-normals-until", "face_normals_until", "flat face normals until step N, then interpolated",
                   &ScheduleSteps::faceNormalsUntil, "7500 x steps/15000"));
  t.push_back(real("surface-smoothness", "surface_smoothness", "X",
                   "weight of a slope prior on the water, X mean((h_a - h_b) / spacing)^2 over the coarse grid's edges: damps a fast "
                   "surface's runaway (0.1 left 2 of 9 tiny presets running away, 4 without; docs/training.md)",
                   field(&TrainConfig::surfaceSmoothness), 0, false, inf, false));
  t.back().shownDefault = "0.1; reference 0";
  t.push_back(real("level-prior", "level_prior", "X",
                   "weight of a prior holding the seen water level: X times the mean square of its tilt and bowl (the {x, y, x^2, xy, "
                   "y^2} part of a least-squares fit, each vertex weighted by the training views that see it): straight-down views "
                   "barely see them (docs/training.md)",
                   field(&TrainConfig::levelPrior), 0, false, inf, false));
  t.back().shownDefault = "10000; reference 0";
  t.push_back(switchOption("level-prior-tilt-only", "level_prior_tilt_only",
                           "the level prior on the seen water's tilt alone ({x, y}), not its bowl: a wave longer than the seen water is "
                           "partly a bowl, which the full prior holds flat (docs/training.md)",
                           field(&TrainConfig::levelPriorTiltOnly), true));
  t.push_back(integer<int>("level-prior-degree", "level_prior_degree", "D",
                           "the level prior's highest degree: every x^a y^b of a + b <= D past the constant (2: tilt and bowl; 3 "
                           "and 4: the smooth warps past the bowl, which the Gaussians also absorb; docs/training.md)",
                           field(&TrainConfig::levelPriorDegree), 1, kMaxLevelPriorDegree));
  t.push_back(real("level-prior-warp", "level_prior_warp", "S",
                   "study: the level prior's terms past the bowl (degree 3 and up, --level-prior-degree) weighted S times "
                   "--level-prior: a long true wave is partly such a warp (docs/experiments/2026-12-07-level-degree.md)",
                   field(&TrainConfig::levelPriorWarpShare), 0, false, 1, false));
  t.push_back(switchOption("anchor-mean-height", "anchor_mean_height",
                           "keep the learned water's mean height (each vertex weighted by the training views that see it) at the given "
                           "water height: straight-down views barely see a uniform shift (on with the method's recipe, the default)",
                           field(&TrainConfig::anchorMeanHeight), true));
  t.push_back(switchOption("water-sign-check", "water_sign_check",
                           "at each --restart-gaussians step, keep the learned water's mirror image about the water height when the "
                           "views agree clearly more through it (a plane sweep of each): waves learned upside down fit the views "
                           "nearly as well (docs/training.md)",
                           field(&TrainConfig::waterSignCheck), true));
  t.push_back(real("sweep-loss", "sweep_loss", "W",
                   "study: weight of a loss on the water that does not pass through the Gaussians: the training views' rays, "
                   "refracted by the learned water, against the colour the views agree on where they land (a plane sweep's mean "
                   "colour at its depth, held fixed) (docs/experiments/2026-12-05-water-valley.md) (0: none)",
                   field(&TrainConfig::sweepLoss), 0, false, inf, false));
  t.push_back(integer<int>("sweep-loss-every", "sweep_loss_every", "N", "study: --sweep-loss at every N-th surface step",
                           field(&TrainConfig::sweepLossEvery), 1, 1000000));
  t.push_back(switchOption("sweep-loss-only", "sweep_loss_only",
                           "study: with --sweep-loss, the water learns from the sweep loss alone; the images' gradient reaches the "
                           "Gaussians, not the water (docs/experiments/2026-12-05-water-valley.md)",
                           field(&TrainConfig::sweepLossOnly), true));
  t.push_back(switchOption("water-scale-search", "water_scale_search",
                           "study: at each --restart-gaussians step, the learned water's relief scaled about the water height by the "
                           "factor among 0, 0.5, 1, 1.5, 2 through which the views agree best (a plane sweep of each; not 1 only when "
                           "clearly better): the Gaussians absorb a water learned at part of its height, the sweep does not "
                           "(docs/experiments/2026-12-05-water-valley.md)",
                           field(&TrainConfig::waterScaleSearch), true));
  t.push_back(real("surface-agreement", "surface_agreement", "P",
                   "the height field's Adam steps scaled by (|m| / sqrt(v))^P, bias-corrected: how consistently its gradients have "
                   "pointed one way; a gradient of noise about zero (views that disagree, Gaussians that absorbed the waves) then "
                   "hardly moves the water, where plain Adam walks it about the learning rate per step (docs/training.md) (0: plain Adam)",
                   field(&TrainConfig::surfaceAgreement), 0, false, 16, false));
  t.push_back(real("surface-gate", "surface_gate", "X",
                   "at each --restart-gaussians step, the learned water starts again from flat when the training views' colours agree "
                   "less through it than through flat water (a plane sweep of each: its cost above X times the flat water's); the "
                   "Gaussians cannot make such a sweep agree (docs/training.md) (0: off)",
                   field(&TrainConfig::surfaceGate), 0, false, inf, false));
  t.push_back(real("restart-gate", "restart_gate", "X",
                   "study: at each --restart-gaussians step the Gaussians are drawn afresh only when the training views agree more "
                   "through the learned water than through flat water (a plane sweep of each: its cost below X times the flat water's); "
                   "otherwise they keep fitting (0: every restart)",
                   field(&TrainConfig::restartGate), 0, false, inf, false));
  t.push_back(integer<int>("sweep-watch", "sweep_watch", "N",
                           "study: every N steps while the water learns, and at its last, the training views swept through the learned "
                           "water and through flat water; when they agree less through the learned water, it goes back to the water they "
                           "agreed on best at a check (flat water if none) and its learning rate halves "
                           "(docs/experiments/2026-12-05-water-valley.md) (0: off)",
                           field(&TrainConfig::sweepWatch), 0, 1000000));
  {
    TrainOption o = step("octaves-open-until", "octaves_open_until",
                         "every encoding octave open from step N (the window opens linearly from --surface-freeze)",
                         &ScheduleSteps::octavesOpenUntil, "never (the coarse octaves only); reference 7500 x steps/15000");
    o.required = false;  // runs written before the option: 0 (every octave open)
    t.push_back(o);
  }
  t.push_back(step("sh-interval", "sh_degree_interval", "SH degree +1 every N steps", &ScheduleSteps::shDegreeInterval, "1000 x steps/15000"));
  t.push_back(step("density-reset-every", "density_reset_interval",
                   "density reset to <= 0.01 every N steps (part of densification: only when it runs)",
                   &ScheduleSteps::densityResetInterval, "0 (never); reference max(1000, 3000 x steps/15000)"));
  t.push_back(step("density-reset-until", "density_reset_until", "no density reset from step N", &ScheduleSteps::densityResetUntil,
                   "12000 x steps/15000"));
  t.push_back(step("density-decay-every", "density_decay_interval", "density decay every N steps", &ScheduleSteps::densityDecayInterval, "50"));
  t.push_back(step("densify-from", "densify_from", "densification from step N", &ScheduleSteps::densifyFrom, "500 x steps/15000"));
  t.push_back(step("densify-every", "densify_interval", "densification every N steps", &ScheduleSteps::densifyInterval,
                   "max(100, 300 x steps/15000)"));
  t.push_back(step("densify-until", "densify_until", "densification until step N", &ScheduleSteps::densifyUntil, "12000 x steps/15000"));
  t.push_back(required(switchOption("no-densify", "densify", "no clone/split/prune (and no density reset)", field(&TrainConfig::densify), false)));
  t.push_back(shown(required(real("densify-grad", "densify_grad_threshold", "X", "clone/split threshold on the mean positional-gradient statistic",
                                  field(&TrainConfig::densifyGradThreshold), 0, false, inf, false)),
                    "3e-4"));
  t.push_back(choice("densify-strategy", "densify_strategy", "KIND",
                     "3dgs (clone, split, prune, density resets: the reference) or mcmc (3DGS-MCMC: Gaussians under 0.005 density "
                     "relocated onto live ones, the count grown 5% per densification up to --max-gaussians, noise on the nearly "
                     "transparent ones' positions; no prune, no density reset)",
                     field(&TrainConfig::densifyStrategy), {{"3dgs", DensifyStrategy::Reference3dgs}, {"mcmc", DensifyStrategy::Mcmc}}));
  t.push_back(step("prune-every", "prune_interval", "prune low-density Gaussians every N steps (densify-from..densify-until)",
                   &ScheduleSteps::pruneInterval, "100"));
  t.push_back(step("prune-large-from", "prune_large_from", "also prune Gaussians larger than 10% of the extent from step N",
                   &ScheduleSteps::pruneLargeFrom, "never without density resets; reference 3000 x steps/15000"));
  t.push_back(step("lr-steps", "lr_steps", "length of the decaying learning-rate schedules", &ScheduleSteps::lrSteps, "30000 x steps/15000"));
  {
    TrainOption r = row("restart-gaussians", "schedule/gaussian_restarts", "N[,N...]",
                        "draw the Gaussians afresh after each step N (as at step 0, with fresh Adam state and schedules), the surface "
                        "kept: the first Gaussians absorb the distortion of the still-flat water, and fresh ones let it grow toward the "
                        "true amplitude; with --init-depth sweep each restart looks through a better surface (docs/training.md) (0: never)");
    r.shownDefault = "where the water learns, 1/3 and 8/15 of the steps on a GPU, 1/4, 2/5 and 11/20 on a CPU; reference 0";
    r.get = [](const TrainConfig& c) { return json(c.schedule.gaussianRestarts); };
    r.set = [](TrainConfig& c, const json& v, const std::string& name) {
      if (!v.is_array()) fail(name + " must be a list of steps, got " + v.dump());
      std::vector<int> steps;
      for (const json& s : v) {
        long long x = s.is_number_integer() ? integerOf(s, name) : -1;
        if (x < 1 || x > kMaxScheduleStep) fail(name + " must be steps after the first, got " + s.dump());
        steps.push_back(int(x));
      }
      c.schedule.gaussianRestarts = steps;
    };
    r.parse = [](const std::string& text, const std::string& name) {
      // A comma-separated list of steps; 0 alone: never.
      json steps = json::array();
      std::stringstream in(text);
      std::string item;
      auto bad = [&] { fail(name + " expects steps separated by commas, got '" + text + "'"); };
      if (text.empty()) bad();
      while (std::getline(in, item, ',')) {
        char* end = nullptr;
        double v = std::strtod(item.c_str(), &end);
        if (item.empty() || end == item.c_str() || *end || v != std::floor(v) || v < 0 || v > kMaxScheduleStep) bad();
        if (v > 0) steps.push_back(int(v));
      }
      if (!text.empty() && text.back() == ',') bad();
      return steps;
    };
    t.push_back(r);
  }
  t.push_back(required(resumable(integer<int>("progress-every", "progress_every", "N", "progress line every N steps (stderr)",
                                              field(&TrainConfig::progressEvery), 1, 100000000))));
  t.push_back(required(resumable(integer<int>("eval-every", "eval_every", "N", "test-split evaluation every N steps (0: at the end only)",
                                              field(&TrainConfig::evalEvery), 0, 100000000))));
  t.push_back(required(resumable(integer<int>("checkpoint-every", "checkpoint_every", "N", "checkpoint every N steps (0: at the end only)",
                                              field(&TrainConfig::checkpointEvery), 0, 100000000))));
  t.push_back(required(real("", "density_reset_value", "", "density a reset lowers every Gaussian's to", field(&TrainConfig::densityResetValue),
                            0, false, 1, false)));
  return t;
}

}  // namespace

const std::vector<TrainOption>& trainOptionTable() {
  static const std::vector<TrainOption> table = makeTable();
  return table;
}

const TrainOption* findTrainOption(const std::string& flag) {
  for (const TrainOption& o : trainOptionTable())
    if (!flag.empty() && o.flag == flag) return &o;
  return nullptr;
}

std::string shownDefault(const TrainOption& option) {
  if (!option.shownDefault.empty()) return option.shownDefault;
  if (option.metavar.empty()) return "";  // a switch
  json v = option.get(TrainConfig{});
  if (v.is_string()) return v.get<std::string>();
  if (v.is_number_float()) return number(v.get<double>());
  return v.dump();
}

}  // namespace refrax
