// A firefighter device's recorded boot IMU file: rows become samples in order, a malformed row
// is skipped naming nothing else lost, and a file without the header is refused naming it.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "imu_file.hpp"
#include "sarloc/core/common/errors.hpp"

namespace sarloc::rescuer {
namespace {

std::string write_file(const std::string& name, const std::string& text) {
  const auto path = std::filesystem::temp_directory_path() / name;
  std::ofstream(path) << text;
  return path.string();
}

TEST(ImuFile, ReadsRowsInOrderAndSkipsMalformedOnesOnly) {
  const std::string path = write_file("sarloc-imu-test.csv", std::string("# boot IMU, recorded\n") + ImuFile::kHeader +
                                                                 "\n"
                                                                 "0.00,0.1,0.0,9.81,0.001,0.0,0.0\n"
                                                                 "0.01,0.1,0.0,9.81,abc,0.0,0.0\n"   // line 4: not a number
                                                                 "\n"
                                                                 "0.02,0.2,0.0,9.80,0.0,0.0,0.01\n"
                                                                 "0.02,0.2,0.0,9.80,0.0,0.0,0.01\n"  // line 7: t not after
                                                                 "0.03,0.2,0.0\n"                    // line 8: 3 columns
                                                                 "0.04,0.3,0.0,9.79,0.0,0.0,0.02\n");
  ImuFile file(path);
  std::vector<double> t;
  while (auto s = file.next()) t.push_back(s->t);
  EXPECT_EQ(t, (std::vector<double>{0.00, 0.02, 0.04}));
  EXPECT_EQ(file.skipped_rows(), 3U);
}

TEST(ImuFile, RefusesAMissingFileAndAWrongHeaderNamingThem) {
  EXPECT_THROW(ImuFile("/nonexistent/imu.csv"), ConfigError);
  const std::string path = write_file("sarloc-imu-bad-header.csv", "t,ax,ay,az,gx,gy,gz\n0,0,0,9.8,0,0,0\n");
  try {
    ImuFile file(path);
    FAIL() << "a wrong header";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find(":1: time column 't_s' is not in the header"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace sarloc::rescuer
