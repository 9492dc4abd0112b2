// sarloc-rescuer's SimulatedWorld: the transmitters one simulated device's dig switched off
// reach every other device of the mission, whole lines only, bad lines skipped.
#include "simulated_world.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

namespace sarloc::rescuer {
namespace {

std::string world_file() {
  const auto path = std::filesystem::temp_directory_path() / ("sarloc-sim-world-" + std::to_string(getpid()) + ".txt");
  std::filesystem::remove(path);
  return path.string();
}

TEST(SimulatedWorld, ADigSwitchesATransmitterOffForEveryDeviceOnce) {
  const std::string path = world_file();
  SimulatedWorld digger(path), other(path);
  EXPECT_TRUE(other.take_switched_off().empty()) << "nobody dug yet: no file";
  digger.switched_off(2);
  EXPECT_EQ(other.take_switched_off(), std::vector<std::size_t>{2});
  EXPECT_TRUE(other.take_switched_off().empty()) << "each once";
  digger.switched_off(0);
  other.switched_off(3);
  EXPECT_EQ(other.take_switched_off(), (std::vector<std::size_t>{0, 3}));
  EXPECT_EQ(digger.take_switched_off(), (std::vector<std::size_t>{2, 0, 3}));
  std::filesystem::remove(path);
}

TEST(SimulatedWorld, AHalfWrittenLineWaitsAndABadOneIsSkipped) {
  const std::string path = world_file();
  SimulatedWorld reader(path);
  {
    std::ofstream out(path, std::ios::app);
    out << "1\nvictim\n-4\n\n7" << std::flush;  // "7" still being written
  }
  EXPECT_EQ(reader.take_switched_off(), std::vector<std::size_t>{1});
  {
    std::ofstream out(path, std::ios::app);
    out << "\n" << std::flush;
  }
  EXPECT_EQ(reader.take_switched_off(), std::vector<std::size_t>{7});
  std::filesystem::remove(path);
}

TEST(SimulatedWorld, WithoutAFileNothingIsShared) {
  SimulatedWorld alone;
  EXPECT_FALSE(alone.shared());
  alone.switched_off(1);
  EXPECT_TRUE(alone.take_switched_off().empty());
}

}  // namespace
}  // namespace sarloc::rescuer
