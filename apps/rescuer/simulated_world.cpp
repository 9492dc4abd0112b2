#include "simulated_world.hpp"

#include <spdlog/spdlog.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>

#include "sarloc/core/common/errors.hpp"

namespace sarloc::rescuer {

void SimulatedWorld::switched_off(std::size_t index) {
  if (!shared()) return;
  // One short appended line per dig: O_APPEND keeps concurrent writers' lines whole.
  std::ofstream out(path_, std::ios::app);
  out << index << '\n' << std::flush;
  if (!out) throw Error("simulated world " + path_ + ": cannot append: " + std::strerror(errno));
}

std::vector<std::size_t> SimulatedWorld::take_switched_off() {
  std::vector<std::size_t> out;
  if (!shared()) return out;
  std::ifstream in(path_, std::ios::binary);
  if (!in) return out;  // nobody dug yet
  in.seekg(static_cast<std::streamoff>(read_));
  const std::string rest((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::size_t start = 0;
  for (std::size_t end = rest.find('\n'); end != std::string::npos; end = rest.find('\n', start)) {
    const std::string line = rest.substr(start, end - start);
    start = end + 1;
    char* tail = nullptr;
    errno = 0;
    const unsigned long long index = std::strtoull(line.c_str(), &tail, 10);
    if (line.empty() || errno != 0 || *tail != '\0' || line[0] == '-') {
      spdlog::warn("simulated world {}: line '{}' is not a victim index: skipped", path_, line);
      continue;
    }
    out.push_back(static_cast<std::size_t>(index));
  }
  read_ += start;
  return out;
}

}  // namespace sarloc::rescuer
