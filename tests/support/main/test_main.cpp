// The main of every test executable: GoogleTest's, plus a scratch folder of this process's own.
//
// ctest runs each test case as its own process, two or more at a time, and tests write files
// under ::testing::TempDir() by fixed names ("hostile.obj"): with one shared /tmp two cases
// wrote and removed each other's files (ObjNgons.FacesThatAreNoPolygonAreRefusedByFileAndLine
// failed about one run in three under `ctest -j2`). GoogleTest's TempDir() is $TEST_TMPDIR when
// set, so each process gets a fresh folder there, removed when the tests end.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>

#include <unistd.h>

int main(int argc, char** argv) {
  const char* base = std::getenv("TMPDIR");
  std::string pattern = std::string(base != nullptr && *base != '\0' ? base : "/tmp") + "/collide_test_XXXXXX";
  std::string scratch;
  if (::mkdtemp(pattern.data()) != nullptr) {
    scratch = pattern;
    ::setenv("TEST_TMPDIR", (scratch + "/").c_str(), 1);
  }
  ::testing::InitGoogleTest(&argc, argv);
  const int result = RUN_ALL_TESTS();
  if (!scratch.empty()) {
    std::error_code ignored;
    std::filesystem::remove_all(scratch, ignored);
  }
  return result;
}
