#pragma once
// One DDS domain per test, so tests running in parallel (ctest -j) never see each other.
// Add new ones here; a duplicate would make two tests talk across each other. Checked by
// tests/unit/dds/dds_test_domains_test.cpp (also that no two tests that may run at once use one).
#include <cstdint>

namespace sarloc::test {

enum DdsTestDomain : std::uint32_t {
  kDomainRoundTripFirst = 100,  // round_trip_test: one per topic type, 100..119
  kDomainLocalhostProfile = 120,
  kDomainLocalhostDiscovery = 121,
  kDomainLateJoiner = 122,
  kDomainPartitions = 123,
  kDomainLiveliness = 124,
  kDomainWrongProfile = 125,
  kDomainMalformedInput = 126,
  kDomainSectorSplit = 127,
  kDomainManyParticipants = 128,
  kDomainSecurity = 129,
  kDomainSecurityRoles = 167,
  kDomainSignOff = 168,
  kDomainSecurityIdentity = 169,
  kDomainRecordedBoot = 170,
  kDomainRecordedBootMission = 171,  // tests/integration/mission/recorded-boot.yaml names it too
  kDomainMissionDugOut = 172,        // tests/integration/mission/dug-out.yaml names it too
  kDomainCommandDeposit = 173,
  kDomainEstimateStall = 174,
  kDomainAdmissionBusy = 175,
  kDomainWriterLifespan = 176,
  kDomainPositionRefresh = 177,
  kDomainPositionCandidates = 178,
  kDomainAdmissionShed = 179,
  kDomainAdmissionDoorStart = 180,
  kDomainHandover = 181,
  kDomainMissionSectorMove = 182,  // tests/integration/mission/sector-move.yaml names it too
  kDomainDeviceRestart = 183,
  kDomainEstimateStallReader = 184,  // not kDomainEstimateStall: ctest -j runs the two at once
  kDomainRecorderFullDisk = 185,     // not kDomainRecorderKill, likewise
  kDomainCommandAlarmsReopen = 186,  // not kDomainCommandAlarms: ctest runs them side by side
  kDomainDiscoveryServer = 140,
  kDomainBenchEchoListener = 141,
  kDomainBenchEchoQueue = 142,
  kDomainBenchEchoWaitSet = 143,
  kDomainOwnership = 144,
  kDomainCommandStandby = 145,
  kDomainAdmissionRoster = 146,
  kDomainAdmissionEviction = 147,
  kDomainMissionFourWithin5m = 148,
  kDomainCommandPlacement = 149,
  kDomainCommandRedispose = 152,
  kDomainCoreFirefighter = 153,  // tests/integration/mission/firefighters.yaml names it too
  kDomainMissionBuilding = 154,  // tests/integration/mission/building-small.yaml names it too
  kDomainCommandAlarms = 155,
  kDomainMissionMixed = 156,  // tests/integration/mission/mixed.yaml names it too
  kDomainMissionBuildingDaemonKill = 157,
  kDomainRecorder = 158,
  kDomainRecorderKill = 159,
  kDomainMissionRecorded = 160,
  kDomainMissionReplay = 161,
  kDomainRecorderRotate = 162,
  kDomainBenchRecorder = 163,  // sarloc-bench-recorder's default --domain
  kDomainReplayer = 164,
  kDomainMissionDashboard = 165,        // tests/integration/mission/dashboard.yaml names it too
  kDomainAccuracyDefaultMission = 166,  // tests/accuracy: config/missions/default.yaml
  kDomainMissionSmall = 130,            // mission_test: 130..139, and:
  kDomainMissionCommandKill = 134,
  kDomainMissionCommandRestart = 136,
  kDomainMissionNoCommand = 137,
  kDomainMissionLossy = 138,  // lossy.yaml names it too
  kDomainMissionFades = 139,
  // tests/interop/cyclone_interop_test.sh (a script: the ids are passed by its CMakeLists.txt)
  kDomainCycloneSubscribe = 150,
  kDomainCyclonePublish = 151,
};

}  // namespace sarloc::test
