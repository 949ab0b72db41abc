#pragma once
/// What the LIGGGHTS backend tests share beyond tests/server/test_support.hpp.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <system_error>

namespace demlink::server::test {

/// A scratch folder the MPI ranks of one test run share: named after their common parent
/// (mpirun's launcher) instead of each rank's own process, so what rank 0 writes (a
/// checkpoint) the others find. Removed at the end unless the test failed.
class RankSharedDir {
 public:
  RankSharedDir() {
    const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = std::filesystem::temp_directory_path() / (std::string("demlink_") + info->test_suite_name() + "_" +
                                                      info->name() + "_" + std::to_string(::getppid()));
    std::filesystem::create_directories(path_);
  }
  ~RankSharedDir() {
    std::error_code ec;
    if (!::testing::Test::HasFailure()) std::filesystem::remove_all(path_, ec);
  }
  RankSharedDir(const RankSharedDir&) = delete;
  RankSharedDir& operator=(const RankSharedDir&) = delete;

  [[nodiscard]] const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

}  // namespace demlink::server::test
