#pragma once
// The `refrax` command line: each subcommand registers itself from its own file with
// REFRAX_COMMAND, and declares its options so `--help` and error messages come for free.
#include <atomic>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace refrax {
struct Context;
}

namespace refrax::cli {

struct Option {
  std::string name;      // without the leading "--"
  std::string metavar;   // empty: a flag without a value
  std::string help;
  std::string fallback;  // default shown in --help (empty: none)
};

struct Args {
  std::string command;
  std::vector<std::string> positional;
  std::map<std::string, std::string> values;  // options given (flags map to "1")

  bool has(const std::string& name) const { return values.count(name) != 0; }
  std::string get(const std::string& name, const std::string& fallback = "") const;
  double getDouble(const std::string& name, double fallback) const;
  long getInt(const std::string& name, long fallback) const;
  // getInt, and one clear error when the value lies outside [lo, hi]
  long getIntIn(const std::string& name, long fallback, long lo, long hi) const;
};

struct Command {
  std::string name;
  std::string summary;
  std::string usage;  // e.g. "refrax bench <suite> [options]"
  std::vector<Option> options;
  int (*run)(const Args&);
  // Options known only after every file has registered (bench suites); may be null.
  std::vector<Option> (*lateOptions)() = nullptr;
  std::vector<Option> allOptions() const;
};

void registerCommand(const Command& command);
const std::vector<Command>& commands();
// Parses argv for `command` (throws refrax::Error on unknown options or missing values).
Args parseArgs(const Command& command, int argc, char** argv, int first);
void printHelp(const Command& command);
// Options every device-using command accepts: --device, --validation.
std::vector<Option> deviceOptions();
// Creates the output folder `path` (for `flag`, e.g. "-o") before any device work, so a
// folder that cannot be made is one clear error; the returned guard removes it again, if this
// call made it and it is still empty, unless keep() is called (the command succeeded).
struct OutputFolder {
  std::string path;
  bool made = false, kept = false;
  int lockFd = -1;  // claimOutputFolder's lock on the folder, held for the guard's life
  OutputFolder() = default;
  OutputFolder(const OutputFolder&) = delete;
  OutputFolder& operator=(const OutputFolder&) = delete;
  ~OutputFolder();
  void keep() { kept = true; }
};
std::unique_ptr<OutputFolder> createOutputFolder(const std::string& path, const std::string& flag);
// Refuses `path` unless it is absent or an empty folder: "FLAG PATH is a file, not a folder",
// or "PATH already exists and is not empty (ADVICE)".
void checkNewOrEmptyFolder(const std::string& path, const std::string& flag, const std::string& advice);
// createOutputFolder for a process that writes into the folder while it runs (refrax train):
// the folder is also locked for the guard's life (flock on the folder itself, so nothing is
// written into it and a killed process leaves no stale lock) and checked empty under the
// lock. Of two processes given one folder at the same moment exactly one claims it; the other
// is refused naming it and leaves the folder to the first.
std::unique_ptr<OutputFolder> claimOutputFolder(const std::string& path, const std::string& flag, const std::string& advice);
// The same lock on an existing run folder (refrax train --resume); the returned guard holds it.
std::unique_ptr<OutputFolder> lockRunFolder(const std::string& path);
// From this call on, Ctrl-C and SIGTERM set the returned flag instead of ending the process,
// so a command writing a staged folder (engine/io/staged_folder.h) stops between files and
// removes it rather than leaving it behind.
const std::atomic<bool>& catchInterrupts();
// The Vulkan context chosen by --device / --validation (and their environment variables).
std::unique_ptr<Context> openContext(const Args& args, bool verbose = true);

struct Registrar {
  explicit Registrar(const Command& c) { registerCommand(c); }
};

}  // namespace refrax::cli

#define REFRAX_CLI_CONCAT2(a, b) a##b
#define REFRAX_CLI_CONCAT(a, b) REFRAX_CLI_CONCAT2(a, b)
#define REFRAX_COMMAND(...) static ::refrax::cli::Registrar REFRAX_CLI_CONCAT(refraxCommand_, __LINE__)(::refrax::cli::Command __VA_ARGS__)
