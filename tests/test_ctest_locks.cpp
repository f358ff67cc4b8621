// tests/ctest_locks.cmake names cases by their full names. CTest sets no property on a name it
// does not know, and says nothing: a renamed case would drop out of its lock unnoticed. So every
// name there must be a TEST_CASE of this suite, word for word.
#include <doctest/doctest.h>

#include <filesystem>
#include <regex>
#include <string>

#include "engine/io/atomic_file.h"

TEST_CASE("ctest_locks.cmake names only cases that exist" * doctest::test_suite("one-backend")) {
  const std::filesystem::path tests = std::filesystem::path(REFRAX_SOURCE_DIR) / "tests";
  std::string sources;
  for (const auto& entry : std::filesystem::directory_iterator(tests))
    if (entry.path().extension() == ".cpp") sources += refrax::readFile(entry.path().string());
  const std::string locks = refrax::readFile((tests / "ctest_locks.cmake").string());
  const std::regex bracketed(R"(\[==\[([^\]]+)\]==\])");
  int names = 0;
  for (std::sregex_iterator it(locks.begin(), locks.end(), bracketed), end; it != end; ++it) {
    const std::string name = (*it)[1];
    INFO(name);
    CHECK(sources.find("TEST_CASE(\"" + name + "\"") != std::string::npos);
    names++;
  }
  CHECK(names >= 2);
}
