#pragma once
// The training options as one table: command-line flag, config.json key, default, accepted
// range and help text, one row each. The `refrax train` parser, --help, config.json written
// and read back (trainConfigToJson / trainConfigFromJson) and validateTrainConfig all come
// from it, so an option is added, renamed or re-ranged in one place.
//
// Every value passes through JSON: the command line's text is parsed into a JSON value
// (parse), and set() checks that value against the row's range, naming the flag or key it
// came from, before it narrows it into TrainConfig. Defaults are TrainConfig's initialisers.
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/run/train_config.h"

namespace refrax {

struct TrainOption {
  std::string flag;          // command-line name without "--"; empty: config.json only
  std::string key;           // config.json key ("schedule/NAME": inside "schedule"); empty: command line only
  std::string metavar;       // empty: a switch (takes no value)
  std::string help;
  std::string shownDefault;  // the default --help shows; empty: TrainConfig{}'s value
  bool required = false;     // every config.json ever written holds it (others default when absent)
  bool resumable = false;    // may be given with --resume (how far the run goes and how it reports)
  std::string group;         // switches of one group exclude each other
  // The config's value as JSON.
  std::function<nlohmann::json(const TrainConfig&)> get;
  // Checks `value` (error naming `name`) and stores it.
  std::function<void(TrainConfig&, const nlohmann::json& value, const std::string& name)> set;
  // The command line's text as the JSON value set() takes (error naming `name`).
  std::function<nlohmann::json(const std::string& text, const std::string& name)> parse;
};

// Every option, in --help's order.
const std::vector<TrainOption>& trainOptionTable();
// The row for a flag, or null.
const TrainOption* findTrainOption(const std::string& flag);
// --help's default for a row.
std::string shownDefault(const TrainOption& option);

}  // namespace refrax
