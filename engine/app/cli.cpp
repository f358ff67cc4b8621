#include "engine/app/cli.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <sys/file.h>
#include <unistd.h>

#include "engine/base/error.h"
#include "engine/vk/vk_context.h"

namespace refrax::cli {

namespace {
std::vector<Command>& registry() {
  static std::vector<Command> r;
  return r;
}
}  // namespace

void registerCommand(const Command& command) {
  registry().push_back(command);
  std::sort(registry().begin(), registry().end(), [](const Command& a, const Command& b) { return a.name < b.name; });
}

const std::vector<Command>& commands() { return registry(); }

std::vector<Option> Command::allOptions() const {
  std::vector<Option> all = options;
  if (lateOptions)
    for (auto& o : lateOptions()) all.push_back(o);
  return all;
}

std::string Args::get(const std::string& name, const std::string& fallback) const {
  auto it = values.find(name);
  return it == values.end() ? fallback : it->second;
}

double Args::getDouble(const std::string& name, double fallback) const {
  auto it = values.find(name);
  if (it == values.end()) return fallback;
  char* end = nullptr;
  double v = std::strtod(it->second.c_str(), &end);
  if (end == it->second.c_str() || *end) fail("--" + name + " expects a number, got '" + it->second + "'");
  return v;
}

long Args::getInt(const std::string& name, long fallback) const {
  auto it = values.find(name);
  if (it == values.end()) return fallback;
  char* end = nullptr;
  long v = std::strtol(it->second.c_str(), &end, 10);
  if (end == it->second.c_str() || *end) fail("--" + name + " expects an integer, got '" + it->second + "'");
  return v;
}

long Args::getIntIn(const std::string& name, long fallback, long lo, long hi) const {
  long v = getInt(name, fallback);
  if (v < lo || v > hi) fail("--" + name + " must be between " + std::to_string(lo) + " and " + std::to_string(hi));
  return v;
}

std::vector<Option> deviceOptions() {
  return {{"device", "NAME|INDEX", "Vulkan device to use (also REFRAX_DEVICE); default: the best qualifying one", ""},
          {"trace", "KIND", "how rays find the water and the Gaussians: rayquery (VK_KHR_ray_query), compute (compute shaders only, "
                            "any Vulkan 1.2 GPU) or auto (ray queries where the device has them; also REFRAX_TRACE)", "auto"},
          {"validation", "", "enable the Khronos validation layer (also REFRAX_VALIDATION=1)", ""}};
}

OutputFolder::~OutputFolder() {
  std::error_code ec;
  if (made && !kept && std::filesystem::is_empty(path, ec)) std::filesystem::remove(path, ec);
  if (lockFd >= 0) ::close(lockFd);
}

void checkNewOrEmptyFolder(const std::string& path, const std::string& flag, const std::string& advice) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return;
  if (!std::filesystem::is_directory(path, ec)) fail(flag + " " + path + " is a file, not a folder");
  if (!std::filesystem::is_empty(path, ec)) fail(path + " already exists and is not empty (" + advice + ")");
}

namespace {
// An exclusive, non-blocking flock on the folder; false when another process holds it.
bool lockFolder(OutputFolder& folder) {
  folder.lockFd = ::open(folder.path.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (folder.lockFd < 0) fail(folder.path + ": cannot open the folder (" + std::strerror(errno) + ")");
  return ::flock(folder.lockFd, LOCK_EX | LOCK_NB) == 0;
}
}  // namespace

std::unique_ptr<OutputFolder> claimOutputFolder(const std::string& path, const std::string& flag, const std::string& advice) {
  checkNewOrEmptyFolder(path, flag, advice);
  auto folder = createOutputFolder(path, flag);
  if (!lockFolder(*folder)) {
    folder->keep();  // the other process's folder now, even if this one made it
    fail(flag + " " + path + " is being written by another refrax process: give each run its own folder");
  }
  // Another process may have claimed, filled and released it since the first check.
  try {
    checkNewOrEmptyFolder(path, flag, advice);
  } catch (const Error&) {
    folder->keep();
    throw;
  }
  return folder;
}

std::unique_ptr<OutputFolder> lockRunFolder(const std::string& path) {
  auto folder = std::make_unique<OutputFolder>();
  folder->path = path;
  if (!lockFolder(*folder)) fail(path + " is being written by another refrax process (a training or a resume of it): wait for it to end");
  return folder;
}

std::unique_ptr<OutputFolder> createOutputFolder(const std::string& path, const std::string& flag) {
  auto folder = std::make_unique<OutputFolder>();
  folder->path = path;
  std::error_code ec;
  if (std::filesystem::exists(path, ec)) {
    if (!std::filesystem::is_directory(path, ec)) fail(flag + " " + path + " exists and is not a folder");
    return folder;
  }
  std::filesystem::create_directories(path, ec);
  if (ec) fail(flag + " " + path + ": cannot create the folder (" + ec.message() + ")");
  folder->made = true;
  return folder;
}

namespace {
std::atomic<bool> g_interrupted{false};
extern "C" void onCliInterrupt(int) { g_interrupted.store(true); }
}  // namespace

const std::atomic<bool>& catchInterrupts() {
  std::signal(SIGINT, onCliInterrupt);
  std::signal(SIGTERM, onCliInterrupt);
  return g_interrupted;
}

std::unique_ptr<Context> openContext(const Args& args, bool verbose) {
  ContextOptions o;
  o.device = args.get("device");
  o.trace = args.get("trace");
  o.validation = args.has("validation");
  o.verbose = verbose;
  return createContext(o);
}

Args parseArgs(const Command& command, int argc, char** argv, int first) {
  Args args;
  args.command = command.name;
  const std::vector<Option> options = command.allOptions();
  for (int i = first; i < argc; i++) {
    std::string a = argv[i];
    if (a == "-h" || a == "--help") {
      args.values["help"] = "1";
      continue;
    }
    if (a == "-o") a = "--output";
    if (a.rfind("--", 0) != 0 || a.size() == 2) {
      args.positional.push_back(a);
      continue;
    }
    std::string name = a.substr(2), value;
    size_t eq = name.find('=');
    bool inlineValue = eq != std::string::npos;
    if (inlineValue) {
      value = name.substr(eq + 1);
      name = name.substr(0, eq);
    }
    auto opt = std::find_if(options.begin(), options.end(), [&](const Option& o) { return o.name == name; });
    if (opt == options.end()) {
      // refrax-view is a program of its own, not a refrax subcommand
      std::string program = command.name.rfind("refrax", 0) == 0 ? command.name : "refrax " + command.name;
      fail("unknown option --" + name + " for '" + program + "' (see --help)");
    }
    if (opt->metavar.empty()) {
      if (inlineValue) fail("--" + name + " takes no value");
      args.values[name] = "1";
    } else {
      if (!inlineValue) {
        if (i + 1 >= argc) fail("--" + name + " needs a value (" + opt->metavar + ")");
        value = argv[++i];
      }
      args.values[name] = value;
    }
  }
  return args;
}

void printHelp(const Command& c) {
  std::printf("usage: %s\n\n%s\n", c.usage.c_str(), c.summary.c_str());
  const std::vector<Option> options = c.allOptions();
  if (!options.empty()) std::printf("\noptions:\n");
  for (auto& o : options) {
    std::string left = "--" + o.name + (o.metavar.empty() ? "" : " " + o.metavar);
    std::printf("  %-28s %s%s\n", left.c_str(), o.help.c_str(), o.fallback.empty() ? "" : (" (default " + o.fallback + ")").c_str());
  }
}

}  // namespace refrax::cli
