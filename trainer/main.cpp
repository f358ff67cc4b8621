// refrax: the command-line front end. Subcommands live in trainer/cmd_*.cpp.
#include <cstdio>
#include <cstring>
#include <exception>

#include "engine/base/error.h"
#include "engine/app/cli.h"

using namespace refrax;

static void printOverview() {
  std::printf(
      "refrax — sees through water: refraction-aware Gaussian ray tracing on Vulkan ray queries\n\n"
      "usage: refrax <command> [options]    (refrax <command> --help for its options)\n\ncommands:\n");
  for (auto& c : cli::commands()) std::printf("  %-12s %s\n", c.name.c_str(), c.summary.c_str());
}

int main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  if (argc < 2 || !std::strcmp(argv[1], "-h") || !std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "help")) {
    printOverview();
    return argc < 2 ? 2 : 0;
  }
  const cli::Command* command = nullptr;
  for (auto& c : cli::commands())
    if (c.name == argv[1]) command = &c;
  if (!command) {
    std::fprintf(stderr, "refrax: error: unknown command '%s' (run 'refrax --help' for the list)\n", argv[1]);
    return 2;
  }
  try {
    cli::Args args = cli::parseArgs(*command, argc, argv, 2);
    if (args.has("help")) {
      cli::printHelp(*command);
      return 0;
    }
    return command->run(args);
  } catch (const Error& e) {
    std::fprintf(stderr, "refrax: error: %s\n", e.what());
    return 1;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "refrax: error: out of memory\n");
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "refrax: error: %s\n", e.what());
    return 1;
  }
}
