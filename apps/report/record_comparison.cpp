#include "record_comparison.hpp"

#include <cmath>
#include <limits>
#include <map>
#include <set>

namespace sarloc::report {

namespace {

bool confirmed(incident::VictimState s) { return s == incident::VictimState::kFound || s == incident::VictimState::kLocated; }

std::string fmt(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.2f", v);
  return buffer;
}

}  // namespace

RecordComparison compare_records(const MissionRecord& here, const MissionRecord& there) {
  RecordComparison c;
  std::set<std::uint32_t> paired;
  for (const auto& [id, v] : here.victims) {
    if (v.samples.empty()) continue;
    VictimPair pair;
    pair.here = id;
    const auto& mine = v.samples.back();
    pair.state_here = mine.state;
    pair.found_here_s = v.found_s;
    pair.radius_here_m = radius95_2d(mine.position.covariance);
    pair.distance_m = std::numeric_limits<double>::infinity();
    for (const auto& [other_id, o] : there.victims) {
      if (o.samples.empty()) continue;
      const double d = (o.samples.back().position.position - mine.position.position).norm();
      if (d < pair.distance_m) {
        pair.distance_m = d;
        pair.there = other_id;
        pair.state_there = o.samples.back().state;
        pair.found_there_s = o.found_s;
        pair.radius_there_m = radius95_2d(o.samples.back().position.covariance);
      }
    }
    if (pair.there != 0) paired.insert(pair.there);
    c.victims.push_back(pair);
  }
  for (const auto& [id, o] : there.victims) {
    if (!o.samples.empty() && !paired.count(id) && confirmed(o.samples.back().state)) c.only_there.push_back(id);
  }
  for (const auto& [id, track] : here.responders) {
    const auto other = there.responders.find(id);
    if (other == there.responders.end()) continue;
    std::map<std::int64_t, Vec3> theirs;
    for (const auto& s : other->second.samples) {
      if (s.source == responder::PositionSource::kMapAided) theirs[std::llround(s.t_s * 1e3)] = s.position.position;
    }
    TrackDifference d;
    d.responder = id;
    double sum = 0.0;
    for (const auto& s : track.samples) {
      if (s.source != responder::PositionSource::kMapAided) continue;
      const auto match = theirs.find(std::llround(s.t_s * 1e3));
      if (match == theirs.end()) continue;
      const double e = (s.position.position - match->second).head<2>().norm();
      sum += e * e;
      d.max_m = std::max(d.max_m, e);
      ++d.matched;
    }
    if (d.matched == 0) continue;
    d.rms_m = std::sqrt(sum / static_cast<double>(d.matched));
    c.tracks.push_back(d);
  }
  return c;
}

std::vector<std::string> reproduction_failures(const RecordComparison& c, double victim_tolerance_m, double found_tolerance_s,
                                               double track_rms_tolerance_m) {
  std::vector<std::string> failures;
  for (const auto& p : c.victims) {
    const std::string name = "victim " + std::to_string(p.here);
    if (p.there == 0) {
      if (confirmed(p.state_here)) failures.push_back(name + " is confirmed here and absent there");
      continue;
    }
    if (confirmed(p.state_here) != confirmed(p.state_there) || (p.state_here == incident::VictimState::kFound) != (p.state_there == incident::VictimState::kFound)) {
      failures.push_back(name + ": " + incident::to_string(p.state_here) + " here, " + incident::to_string(p.state_there) + " there");
    }
    if (confirmed(p.state_here) && p.distance_m > victim_tolerance_m) {
      failures.push_back(name + ": final estimates " + fmt(p.distance_m) + " m apart (tolerance " + fmt(victim_tolerance_m) + " m)");
    }
    if (p.found_here_s && p.found_there_s && std::abs(*p.found_here_s - *p.found_there_s) > found_tolerance_s) {
      failures.push_back(name + ": found at " + fmt(*p.found_here_s) + " s here, " + fmt(*p.found_there_s) + " s there");
    }
  }
  // The pairing is by nearest estimate, so two victims here may pair with one there: a victim
  // there confirmed and paired with nothing is missing here.
  if (!c.only_there.empty()) {
    failures.push_back(std::to_string(c.only_there.size()) + " victim(s) there have no counterpart here");
  }
  for (const auto& t : c.tracks) {
    if (t.rms_m > track_rms_tolerance_m) {
      failures.push_back(t.responder + ": map-aided tracks " + fmt(t.rms_m) + " m RMS apart (tolerance " + fmt(track_rms_tolerance_m) + " m)");
    }
  }
  return failures;
}

}  // namespace sarloc::report
