#pragma once
// What the simulated devices of one mission share outside DDS: the physical world. A
// transmitter switched off by a dig falls silent for every receiver at once, however late the
// radio tells them (under a fade, a device told by the picture kept hearing a dug-out victim's
// transmitter for 30 mission seconds and reported it again). A file of victim indices, one per
// line, appended by the digging device and read by the others every epoch.
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace sarloc::rescuer {

class SimulatedWorld {
 public:
  /// No path: no shared world (each device hears the picture only).
  explicit SimulatedWorld(std::string path = {}) : path_(std::move(path)) {}
  bool shared() const { return !path_.empty(); }
  /// This device switched victim `index`'s transmitter off: every device learns it. Throws
  /// Error naming the file when it cannot be written.
  void switched_off(std::size_t index);
  /// Indices switched off by any device since the last call (whole lines only). A line that is
  /// not an index is skipped with a warning naming it.
  std::vector<std::size_t> take_switched_off();

 private:
  std::string path_;
  std::uint64_t read_ = 0;  ///< bytes consumed (through the last whole line)
};

}  // namespace sarloc::rescuer
