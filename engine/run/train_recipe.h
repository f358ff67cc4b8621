#pragma once
// What `refrax train DATA -o RUN` does with no method flags (issue 45): the recipe fills every
// setting the command line left open, for the run's model and device, before the data sizes
// the model (engine/train/model_sizing.h) and the schedule is scaled to the steps.
//
//   method     (the default) the settings that recover the water on scenes nobody tuned for
//              (docs/training.md "The defaults"; the studies behind them are
//              docs/experiments/2026-12-04-defaults.md and 2026-12-07-cpu-water.md): whole
//              images on a GPU, 64 px patches on a CPU; a fast surface on three coarse octaves,
//              its level held (anchor, level prior), stepping once per pass over the views on
//              a GPU and every step on a CPU; the Gaussians drawn at a plane sweep's depth and
//              drawn afresh through the water learned so far (twice on a GPU, three times on
//              a CPU).
//   reference  the paper's schedule as the reference code runs it (15,000 whole-image steps,
//              the surface at 5e-4 every step, SH degree 3, density resets): for studies.
//
// A flag given on the command line always wins; config.json records the recipe and every value
// it chose, so --resume, render and eval rebuild the same run.
#include <functional>
#include <string>
#include <vector>

#include "engine/run/train_config.h"

namespace refrax {

// The device the recipe sizes the run for.
struct RecipeDevice {
  bool cpu = false;  // a CPU implementation (lavapipe): patches and fewer steps
};

// The recipe's choices, each with why, for the log and config.json.
struct RecipeChoice {
  std::string key;    // config.json key
  std::string value;  // as the command line would give it
};

// Fills the settings `given` leaves open with `config.recipe`'s values for `config.model` on
// `device`, the training images being `imageWidth` x `imageHeight` at the smallest. Returns
// what it chose (empty for the reference recipe).
std::vector<RecipeChoice> applyRecipe(TrainConfig& config, const std::function<bool(const std::string& key)>& given,
                                      const RecipeDevice& device, int imageWidth, int imageHeight);

}  // namespace refrax
